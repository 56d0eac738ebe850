// tests/compiler/archive_info_test.cpp — pbrtc --info on a real archive: the version line, the
// effects the header sets, the scene's counts, and one table row per section whose kind, codec
// and count are the section table's, in columns that line up (the longest codec name, draco,
// included).
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "compiled_scene.h"
#include "compiler/archive_builder.h"
#include "compiler/archive_info.h"
#include "compiler/parser.h"
#include "format/archive_names.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace pbrtc {
namespace {

// The column just past the first whole-word `word` at or after `from` (npos if none).
size_t end_of_word(const std::string& line, const std::string& word, size_t from) {
  for (size_t at = line.find(word, from); at != std::string::npos; at = line.find(word, at + 1)) {
    const size_t end = at + word.size();
    const bool starts = at == 0 || line[at - 1] == ' ';
    const bool ends = end == line.size() || line[end] == ' ';
    if (starts && ends) return end;
  }
  return std::string::npos;
}

TEST(ArchiveInfo, ReportsTheSectionTableInAlignedColumns) {
  CompiledScene c;
  compile_scene(testing_support::shared_dir() + "/scenes/v3-killeroo-simple/killeroo-simple.pbrt",
                &c);
  ASSERT_TRUE(c.ok);
  const std::string path = testing_support::scratch_dir("archive_info") + "/k.pbrta";
  ArchiveOptions opt;
  opt.draco_bits = 12;  // so the table holds draco and zstd sections
  std::string error;
  ASSERT_TRUE(write_archive(c.scene, c.files, directory_of(c.path), path, opt, nullptr, &error))
      << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(path, 2, &error)) << error;

  std::ostringstream out;
  print_archive_info(out, path, a);
  const std::vector<std::string> lines = testing_support::lines_of(out.str());
  ASSERT_GE(lines.size(), 6u) << out.str();
  const std::string version = path + ": pbrtc scene archive " + std::to_string(a.header().major) +
                              "." + std::to_string(a.header().minor) + ", ";
  EXPECT_EQ(lines[0].rfind(version, 0), 0u) << lines[0];
  EXPECT_NE(lines[1].find("area lights"), std::string::npos) << lines[1];
  uint64_t triangles = 0;
  for (const TriangleMesh& m : c.scene.meshes) triangles += m.num_triangles();
  EXPECT_NE(lines[3].find("(meshes " + std::to_string(c.scene.meshes.size()) + ", triangles " +
                          std::to_string(triangles) + ")"),
            std::string::npos)
      << lines[3];

  // "sections:", the column heads, one row per section, the total.
  const pbrta::ArchiveReader& r = a.reader();
  size_t head = 0;
  while (head < lines.size() && lines[head] != "  sections:") ++head;
  ASSERT_EQ(lines.size(), head + 1 + 1 + r.section_count() + 1) << out.str();
  const std::string& heads = lines[head + 1];
  const size_t count_end = end_of_word(heads, "count", 0);
  ASSERT_NE(count_end, std::string::npos) << heads;
  bool saw_draco = false, saw_zstd = false;
  for (uint32_t i = 0; i < r.section_count(); ++i) {
    const std::string& row = lines[head + 2 + i];
    SCOPED_TRACE(row);
    const pbrta::SectionEntry& e = r.entry(i);
    const std::string kind(pbrta::section_kind_name(pbrta::SectionKind(e.kind)));
    const std::string codec(pbrta::codec_name(pbrta::Codec(e.codec)));
    saw_draco |= e.codec == uint32_t(pbrta::Codec::kDraco);
    saw_zstd |= e.codec == uint32_t(pbrta::Codec::kZstd);
    const size_t kind_end = end_of_word(row, kind, 0);
    ASSERT_NE(kind_end, std::string::npos);
    const size_t codec_end = end_of_word(row, codec, kind_end);
    ASSERT_NE(codec_end, std::string::npos);
    // The count is right-aligned under its head, so no codec name pushes it along.
    EXPECT_EQ(end_of_word(row, std::to_string(e.count), codec_end), count_end);
  }
  EXPECT_TRUE(saw_draco);
  EXPECT_TRUE(saw_zstd);
  EXPECT_EQ(lines.back().find("total"), heads.find("kind"));
}

}  // namespace
}  // namespace pbrtc
