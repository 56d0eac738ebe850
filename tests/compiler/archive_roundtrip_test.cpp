// tests/compiler/archive_roundtrip_test.cpp — pbrtc --dump output compiles back to the same archive.
//
// For every shared entry scene that compiles: compile (A), dump A as a pbrt-v3 scene, compile
// the dump (B). B must equal A byte for byte except where the provenance section (the last one,
// holding names, file names and line numbers) and the checksums and sizes that cover it differ.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/archive_dump.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/archive.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace pbrtc {
namespace {

bool compile_to(const std::string& scene, const std::string& out, std::string* error) {
  SourceFiles files;
  Diagnostics diag(&files, nullptr);
  SceneDesc desc;
  if (!build_scene(scene, &files, &diag, &desc)) {
    *error = diag.all().empty() ? "failed" : diag.all()[0].text;
    return false;
  }
  ArchiveOptions opt;
  opt.threads = 1;
  return write_archive(desc, files, directory_of(scene), out, opt, nullptr, error);
}

// Equal outside the provenance section: the header up to its checksums and size,
// every table entry but provenance's, and all bytes before provenance's offset.
::testing::AssertionResult same_outside_provenance(const std::string& a, const std::string& b) {
  if (a.size() < 64 || b.size() < 64) return ::testing::AssertionFailure() << "too short";
  pbrta::Header ha, hb;
  std::memcpy(&ha, a.data(), 64);
  std::memcpy(&hb, b.data(), 64);
  if (std::memcmp(&ha, &hb, 40) != 0)
    return ::testing::AssertionFailure() << "headers differ (version, effects or section count)";
  uint64_t prov_a = 0, prov_b = 0;
  for (uint32_t i = 0; i < ha.section_count; ++i) {
    pbrta::SectionEntry ea, eb;
    std::memcpy(&ea, a.data() + 64 + i * 48, 48);
    std::memcpy(&eb, b.data() + 64 + i * 48, 48);
    if (ea.kind == uint32_t(pbrta::SectionKind::kProvenance)) {
      if (i + 1 != ha.section_count) return ::testing::AssertionFailure() << "provenance not last";
      prov_a = ea.offset;
      prov_b = eb.offset;
      continue;
    }
    if (std::memcmp(&ea, &eb, 48) != 0)
      return ::testing::AssertionFailure() << "section table entry " << i << " (kind " << ea.kind
                                           << ") differs";
  }
  if (prov_a != prov_b || prov_a == 0) return ::testing::AssertionFailure() << "no provenance";
  size_t start = 64 + size_t(ha.section_count) * 48;
  if (a.compare(start, prov_a - start, b, start, prov_b - start) != 0)
    return ::testing::AssertionFailure() << "section bytes differ before provenance";
  return ::testing::AssertionSuccess();
}

TEST(ArchiveRoundTrip, DumpCompilesBackToTheSameArchive) {
  std::string dir = testing_support::scratch_dir("archive_roundtrip");
  int round_tripped = 0;
  std::vector<std::string> not_dumpable;
  int n = 0;
  for (const std::string& scene : testing_support::shared_entry_scenes()) {
    std::string a_path = dir + "/a" + std::to_string(++n) + ".pbrta";
    std::string error;
    if (!compile_to(scene, a_path, &error)) continue;  // missing corpus files
    pbrta::SceneArchive a;
    ASSERT_TRUE(a.load(a_path, 1, &error)) << error;
    std::string out = dir + "/dump" + std::to_string(n);
    if (!dump_archive(a, out, "scene.pbrt", &error)) {
      // Only data the archive does not hold yet may stop a dump.
      ASSERT_NE(error.find("does not store that file's data yet"), std::string::npos)
          << scene << ": " << error;
      not_dumpable.push_back(scene + ": " + error);
      continue;
    }
    std::string b_path = dir + "/b" + std::to_string(n) + ".pbrta";
    ASSERT_TRUE(compile_to(out + "/scene.pbrt", b_path, &error)) << scene << ": " << error;
    EXPECT_TRUE(same_outside_provenance(testing_support::read_file(a_path),
                                        testing_support::read_file(b_path)))
        << scene << " (dump in " << out << ")";
    ++round_tripped;
  }
  for (const std::string& s : not_dumpable) std::printf("not dumpable yet: %s\n", s.c_str());
  std::printf("%d scenes round-tripped, %zu not dumpable yet\n", round_tripped,
              not_dumpable.size());
  EXPECT_GE(round_tripped, 40);
}

}  // namespace
}  // namespace pbrtc
