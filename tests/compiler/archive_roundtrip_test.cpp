// tests/compiler/archive_roundtrip_test.cpp — pbrtc --dump output compiles back to the same
// archive.
//
// For every shared entry scene that compiles: compile (A), dump A as a pbrt-v3 scene, compile
// the dump (B). B must equal A byte for byte except where the provenance section (the last one,
// holding names, file names and line numbers) and the checksums and sizes that cover it differ.
// Every such scene must dump: images included (written as PFM from the texels as decoded).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

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
      return ::testing::AssertionFailure()
             << "section table entry " << i << " (kind " << ea.kind << ") differs";
  }
  if (prov_a != prov_b || prov_a == 0) return ::testing::AssertionFailure() << "no provenance";
  size_t start = 64 + size_t(ha.section_count) * 48;
  if (a.compare(start, prov_a - start, b, start, prov_b - start) != 0)
    return ::testing::AssertionFailure() << "section bytes differ before provenance";
  return ::testing::AssertionSuccess();
}

void write_image(const std::string& path, int w, int h, int channels, OIIO::TypeDesc format,
                 const void* pixels) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(w, h, channels, format))) << out->geterror();
  ASSERT_TRUE(out->write_image(format, pixels)) << out->geterror();
  ASSERT_TRUE(out->close());
}

// Dumps archive `a` (compiled to a_path) under dir/dump, compiles the dump to
// dir/b.pbrta and expects the same bytes outside provenance, then dumps that
// archive again and expects the same scene text. Returns the first dump's text.
std::string expect_dump_round_trip(const pbrta::SceneArchive& a, const std::string& a_path,
                                   const std::string& dir) {
  std::string error;
  const std::string b_path = dir + "/b.pbrta";
  if (!dump_archive(a, dir + "/dump", "scene.pbrt", &error) ||
      !compile_to(dir + "/dump/scene.pbrt", b_path, &error)) {
    ADD_FAILURE() << error;
    return "";
  }
  EXPECT_TRUE(same_outside_provenance(testing_support::read_file(a_path),
                                      testing_support::read_file(b_path)));
  const std::string dumped = testing_support::read_file(dir + "/dump/scene.pbrt");
  pbrta::SceneArchive b;
  if (!b.load(b_path, 1, &error) || !dump_archive(b, dir + "/dump2", "scene.pbrt", &error)) {
    ADD_FAILURE() << error;
    return dumped;
  }
  EXPECT_EQ(dumped, testing_support::read_file(dir + "/dump2/scene.pbrt"));
  return dumped;
}

// Every way a scene uses an image, in one scene: float and spectrum imagemaps with the curve,
// scale and wrap modes, from 8-bit, EXR and PFM files, resampled or not, one file shared by
// several users with equal and with different options, and the three kinds of light map.
TEST(ArchiveRoundTrip, ImagesOfEveryUseRoundTrip) {
  const std::string dir = testing_support::scratch_dir("archive_roundtrip_images");
  uint8_t px[5][3][3];
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 3; ++x)
      for (int k = 0; k < 3; ++k) px[y][x][k] = uint8_t(50 * y + 20 * x + 7 * k);
  write_image(dir + "/a.png", 3, 5, 3, OIIO::TypeDesc::UINT8, px);
  write_image(dir + "/g.png", 3, 5, 1, OIIO::TypeDesc::UINT8, px);
  std::vector<float> hdr(size_t(6) * 3 * 3);
  for (size_t i = 0; i < hdr.size(); ++i) hdr[i] = 0.1f + float(i % 13) * 1.37f;
  write_image(dir + "/sky.exr", 6, 3, 3, OIIO::TypeDesc::FLOAT, hdr.data());
  write_image(dir + "/sq.exr", 4, 2, 3, OIIO::TypeDesc::FLOAT, hdr.data());
  std::string error;
  ASSERT_TRUE(write_pfm(dir + "/f.pfm", hdr.data(), 6, 3, 1, &error)) << error;
  const std::string scene = testing_support::write_file(
      dir + "/scene.pbrt",
      "Camera \"perspective\"\nWorldBegin\n"
      "Texture \"a\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\"\n"
      "Texture \"a2\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\" "
      "\"float maxanisotropy\" 2\n"
      "Texture \"a3\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\" "
      "\"float scale\" 0.3 \"string wrap\" \"black\" \"bool gamma\" \"false\"\n"
      "Texture \"af\" \"float\" \"imagemap\" \"string filename\" \"a.png\" "
      "\"string wrap\" \"clamp\"\n"
      "Texture \"g\" \"float\" \"imagemap\" \"string filename\" \"g.png\" "
      "\"float scale\" 1.7\n"
      "Texture \"f\" \"float\" \"imagemap\" \"string filename\" \"f.pfm\"\n"
      "Texture \"s\" \"spectrum\" \"imagemap\" \"string filename\" \"sq.exr\" "
      "\"bool gamma\" \"true\"\n"
      "Material \"matte\" \"texture Kd\" \"a\" \"texture sigma\" \"g\"\n"
      "Shape \"sphere\"\n"
      "LightSource \"infinite\" \"string mapname\" \"sky.exr\" \"rgb L\" [2 1 0.5]\n"
      "LightSource \"infinite\" \"string mapname\" \"sky.exr\" \"rgb scale\" [3 3 3]\n"
      "LightSource \"infinite\"\n"
      "LightSource \"projection\" \"string mapname\" \"a.png\" \"float fov\" 30\n"
      "LightSource \"goniometric\" \"string mapname\" \"sq.exr\"\n"
      "WorldEnd\n");
  const std::string a_path = dir + "/a.pbrta", b_path = dir + "/b.pbrta";
  ASSERT_TRUE(compile_to(scene, a_path, &error)) << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(a_path, 1, &error)) << error;
  uint32_t sources = 0;
  for (const pbrta::ImageRecord& r : a.images) sources += r.source_image != pbrta::kNoIndex;
  EXPECT_EQ(sources, 8u);  // a.png x 4 options, g.png, f.pfm, sky.exr x 2 lights (L differs)
  expect_dump_round_trip(a, a_path, dir);
}

// The fourier material's table goes out as a .bsdf file and compiles back to the same words; a
// per-shape override naming the table again makes a second material with its own copy.
TEST(ArchiveRoundTrip, FourierTableRoundTrips) {
  const std::string dir = testing_support::scratch_dir("archive_roundtrip_fourier");
  const std::string bsdf =
      testing_support::shared_dir() +
      "/scenes/hm-materials-partial/pbrt-v3-scenes/dragon/bsdfs/roughgold_alpha_0.2.bsdf";
  const std::string scene = testing_support::write_file(
      dir + "/scene.pbrt",
      "Camera \"perspective\"\nWorldBegin\n"
      "MakeNamedMaterial \"gold\" \"string type\" \"fourier\" \"string bsdffile\" \"" +
          bsdf +
          "\"\n"
          "NamedMaterial \"gold\"\nShape \"sphere\"\n"
          "Shape \"sphere\" \"float radius\" 2 \"string bsdffile\" \"" +
          bsdf + "\"\nWorldEnd\n");
  const std::string a_path = dir + "/a.pbrta", b_path = dir + "/b.pbrta";
  std::string error;
  ASSERT_TRUE(compile_to(scene, a_path, &error)) << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(a_path, 1, &error)) << error;
  const std::string dumped = expect_dump_round_trip(a, a_path, dir);
  EXPECT_NE(dumped.find("\"string type\" \"fourier\" \"string bsdffile\" [\"bsdfs/material"),
            std::string::npos)
      << dumped;
  EXPECT_EQ(dumped.find("bsdfcoeffs"), std::string::npos) << dumped;
}

TEST(ArchiveRoundTrip, DumpCompilesBackToTheSameArchive) {
  std::string dir = testing_support::scratch_dir("archive_roundtrip");
  int round_tripped = 0;
  std::vector<std::string> failures;
  int n = 0;
  for (const std::string& scene : testing_support::shared_entry_scenes()) {
    std::string a_path = dir + "/a" + std::to_string(++n) + ".pbrta";
    std::string error;
    if (!compile_to(scene, a_path, &error)) continue;  // missing corpus files
    pbrta::SceneArchive a;
    ASSERT_TRUE(a.load(a_path, 1, &error)) << error;
    std::string out = dir + "/dump" + std::to_string(n);
    if (!dump_archive(a, out, "scene.pbrt", &error)) {
      failures.push_back(scene + ": cannot dump: " + error);
      continue;
    }
    std::string b_path = dir + "/b" + std::to_string(n) + ".pbrta";
    if (!compile_to(out + "/scene.pbrt", b_path, &error)) {
      failures.push_back(scene + ": the dump in " + out + " does not compile: " + error);
      continue;
    }
    ::testing::AssertionResult same = same_outside_provenance(testing_support::read_file(a_path),
                                                              testing_support::read_file(b_path));
    if (!same) {
      failures.push_back(scene + ": recompiled from the dump in " + out + ", " + same.message());
      continue;
    }
    ++round_tripped;
  }
  std::printf("%d scenes round-tripped, %zu did not\n", round_tripped, failures.size());
  std::string list;
  for (const std::string& f : failures) list += "\n  " + f;
  EXPECT_TRUE(failures.empty()) << "every compilable shared scene must round-trip; these did not:"
                                << list;
  // The corpus has 65 compilable scenes; far fewer means the corpus is missing, not that all
  // is well.
  EXPECT_GE(round_tripped, 60);
}

}  // namespace
}  // namespace pbrtc
