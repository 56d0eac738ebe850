// tests/compiler/texture_precision_test.cpp — pbrtc --texture-precision (ArchiveOptions::
// texture_format) on real shared scenes: f16 and unorm8 archives of hm-textures' ewa-filtering
// load and verify, their texels are the f32 ones encoded (format/texel_format.h) and their
// texels sections shrink to the byte counts the formats imply; f32 stays the lossless bytes;
// v3-figures f8-22's HDR environment map is refused by unorm8 with an error naming it and
// stored by f16 with its sampling distribution left f32; the reader rejects a format value it
// does not know, a format that does not fit the section, and a distribution that is not f32;
// and a dump of an unorm8 archive writes the values it decodes to.
#include <gtest/gtest.h>

#include <xxhash.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "compiled_scene.h"
#include "compiler/archive_builder.h"
#include "compiler/archive_dump.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/scene_archive.h"
#include "format/texel_format.h"
#include "reseal_and_load.h"
#include "test_support.h"

namespace pbrtc {
namespace {

using Compiled = CompiledScene;

// A shared scene by its path under scenes/.
void compile(const std::string& rel, Compiled* c) {
  compile_scene(testing_support::shared_dir() + "/scenes/" + rel, c);
}

bool write(const Compiled& c, const std::string& out, pbrta::PixelFormat format, bool compress,
           std::string* error) {
  ArchiveOptions opt;
  opt.texture_format = format;
  opt.compress = compress;
  opt.threads = 2;
  return write_archive(c.scene, c.files, directory_of(c.path), out, opt, nullptr, error);
}

// Raw bytes of the texels sections: the padded levels of every image they hold.
uint64_t texel_bytes_of(const pbrta::SceneArchive& a) {
  uint64_t n = 0;
  for (uint32_t i = 0; i < a.reader().section_count(); ++i)
    if (a.reader().entry(i).kind == uint32_t(pbrta::SectionKind::kTexels))
      n += a.reader().entry(i).raw_size;
  return n;
}

// The bytes the levels of the scene's images take in one texels section of a format: each
// level 16-byte aligned, the last one unpadded.
uint64_t expected_texel_bytes(const SceneDesc& s, uint32_t format) {
  uint64_t n = 0;
  for (const ImageDesc& d : s.images)
    for (const std::vector<float>& level : d.image.levels)
      n = ((n + 15) & ~uint64_t(15)) + level.size() * pbrta::texel_bytes(format);
  return n;
}

TEST(TexturePrecision, EwaFilteringShrinksAndDecodesToTheEncodedTexels) {
  Compiled c;
  compile("hm-textures/pbrt-v3-rs/scenes/textures/ewa-filtering.pbrt", &c);
  ASSERT_TRUE(c.ok);
  ASSERT_EQ(c.scene.images.size(), 1u);  // lines.png, 1024 x 1024, 11 levels
  const std::string dir = testing_support::scratch_dir("texture_precision_ewa");
  uint64_t texels[3] = {}, files[3] = {};
  for (uint32_t format = 0; format < 3; ++format) {
    SCOPED_TRACE(pbrta::texel_format_name(format));
    const std::string path = dir + "/" + pbrta::texel_format_name(format) + ".pbrta";
    std::string error;
    ASSERT_TRUE(write(c, path, pbrta::PixelFormat(format), true, &error)) << error;
    pbrta::SceneArchive a;
    ASSERT_TRUE(a.load(path, 1, &error)) << error;
    ASSERT_EQ(a.images.size, 1u);
    const pbrta::ImageRecord& r = a.images[0];
    EXPECT_EQ(r.format, format);
    texels[format] = texel_bytes_of(a);
    files[format] = testing_support::read_file(path).size();
    EXPECT_EQ(texels[format], expected_texel_bytes(c.scene, format));
    // Every level decodes to the f32 texels as the format encodes them.
    const DecodedImage& im = c.scene.images[0].image;
    ASSERT_EQ(r.levels, im.levels.size());
    const uint8_t* at = a.reader().section_data(r.section) + r.offset;
    size_t differ = 0;
    for (const std::vector<float>& level : im.levels) {
      std::vector<float> got(level.size());
      pbrta::decode_texels(format, at, level.size(), got.data());
      std::vector<uint8_t> want_bytes(level.size() * pbrta::texel_bytes(format));
      pbrta::encode_texels(format, level.data(), level.size(), want_bytes.data());
      ASSERT_EQ(0, std::memcmp(at, want_bytes.data(), want_bytes.size()));
      for (size_t k = 0; k < level.size(); ++k) {
        differ += got[k] != level[k];
        const float tol = format == 0 ? 0.f : format == 1 ? level[k] / 2048 : 0.5f / 255;
        ASSERT_LE(std::fabs(got[k] - level[k]), tol) << k;
      }
      at += (want_bytes.size() + 15) & ~size_t(15);
    }
    // f32 is lossless; f16 and unorm8 round: the image's two palette colours, after the sRGB
    // curve, are 0.0781874 and 0.921582, neither of them a half or a step of 1/255.
    if (format == 0) {
      EXPECT_EQ(differ, 0u);
    } else {
      EXPECT_GT(differ, 0u);
    }
  }
  // 1024^2 x 3 channels, 4/3 for the pyramid: 16 MiB of f32 texels, half and a quarter of it.
  EXPECT_GT(texels[0], 16000000u);
  EXPECT_NEAR(double(texels[1]) / double(texels[0]), 0.5, 1e-4);
  EXPECT_NEAR(double(texels[2]) / double(texels[0]), 0.25, 1e-4);
  // Compressed, the file shrinks too. (Not unorm8 below f16: the two-colour lines leave
  // zstd little to do in either, and which one wins is not what the option promises.)
  EXPECT_LT(files[1], files[0] / 4);
  EXPECT_LT(files[2], files[0] / 4);
}

// The default writes what pbrtc always wrote: the same bytes as options that say nothing.
TEST(TexturePrecision, DefaultIsTheLosslessArchive) {
  Compiled c;
  compile("hm-textures/pbrt-v3-rs/scenes/textures/trilinear-filtering.pbrt", &c);
  ASSERT_TRUE(c.ok);
  const std::string dir = testing_support::scratch_dir("texture_precision_default");
  std::string error;
  ArchiveOptions plain;
  plain.threads = 1;
  ASSERT_TRUE(write_archive(c.scene, c.files, directory_of(c.path), dir + "/a.pbrta", plain,
                            nullptr, &error))
      << error;
  ASSERT_TRUE(write(c, dir + "/b.pbrta", pbrta::PixelFormat::kFloat32, true, &error)) << error;
  const std::string a = testing_support::read_file(dir + "/a.pbrta");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, testing_support::read_file(dir + "/b.pbrta"));
}

TEST(TexturePrecision, HdrEnvironmentMapRefusedByUnorm8KeptByF16) {
  Compiled c;
  compile("v3-figures/f8-22.pbrt", &c);
  ASSERT_TRUE(c.ok);
  const std::string dir = testing_support::scratch_dir("texture_precision_hdr");
  // Which image is the environment map: the one with a distribution.
  int map = -1;
  for (size_t i = 0; i < c.scene.images.size(); ++i)
    if (c.scene.images[i].distribution >= 0) map = int(i);
  ASSERT_GE(map, 0);
  std::string error;
  EXPECT_FALSE(write(c, dir + "/u8.pbrta", pbrta::PixelFormat::kUnorm8, true, &error));
  const std::string want = "--texture-precision unorm8: image " + std::to_string(map) + " ('" +
                           c.scene.images[size_t(map)].source + "') holds ";
  EXPECT_EQ(error.substr(0, want.size()), want) << error;
  EXPECT_NE(error.find("20060807_wells6_hd.exr"), std::string::npos) << error;
  EXPECT_NE(error.find("unorm8 (linear [0, 1]) cannot hold: HDR data"), std::string::npos) << error;
  EXPECT_NE(error.find("use --texture-precision f16 or f32"), std::string::npos) << error;
  EXPECT_FALSE(testing_support::read_file(dir + "/u8.pbrta").size()) << "no file left behind";

  error.clear();
  ASSERT_TRUE(write(c, dir + "/f16.pbrta", pbrta::PixelFormat::kHalf16, true, &error)) << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(dir + "/f16.pbrta", 1, &error)) << error;
  const pbrta::ImageRecord& m = a.images[uint32_t(map)];
  EXPECT_EQ(m.format, uint32_t(pbrta::PixelFormat::kHalf16));
  ASSERT_NE(m.distribution, pbrta::kNoIndex);
  EXPECT_EQ(a.images[m.distribution].format, uint32_t(pbrta::PixelFormat::kFloat32));
  // The distribution's texels are the f32 ones, bit for bit.
  const std::vector<float>& dist = c.scene.images[m.distribution].image.levels[0];
  const pbrta::ImageRecord& d = a.images[m.distribution];
  EXPECT_EQ(
      0, std::memcmp(a.reader().section_data(d.section) + d.offset, dist.data(), dist.size() * 4));
  // The map really is HDR (that is why unorm8 refused it), and f16 kept its largest value
  // to half precision.
  const std::vector<float>& l0 = c.scene.images[size_t(map)].image.levels[0];
  float peak = 0;
  size_t peak_at = 0;
  for (size_t k = 0; k < l0.size(); ++k)
    if (l0[k] > peak) peak = l0[k], peak_at = k;
  EXPECT_GT(peak, 1.f);
  uint16_t h;
  std::memcpy(&h, a.reader().section_data(m.section) + m.offset + 2 * peak_at, 2);
  EXPECT_NEAR(pbrta::half_to_float(h), peak, peak / 2048);
}

TEST(TexturePrecision, F16RefusesValuesBeyondHalfRange) {
  const std::string dir = testing_support::scratch_dir("texture_precision_overflow");
  const float texels[4] = {0.5f, 70000.f, 1.f, 2.f};  // 2 x 2 grey PFM, one texel too bright
  std::string error;
  ASSERT_TRUE(write_pfm(dir + "/hot.pfm", texels, 2, 2, 1, &error)) << error;
  testing_support::write_file(dir + "/scene.pbrt",
                              "Camera \"perspective\"\nWorldBegin\n"
                              "Texture \"t\" \"float\" \"imagemap\" \"string filename\" "
                              "\"hot.pfm\"\nWorldEnd\n");
  SourceFiles files;
  Diagnostics diag(&files, nullptr);
  SceneDesc scene;
  ASSERT_TRUE(build_scene(dir + "/scene.pbrt", &files, &diag, &scene));
  ArchiveOptions opt;
  opt.texture_format = pbrta::PixelFormat::kHalf16;
  EXPECT_FALSE(write_archive(scene, files, dir, dir + "/a.pbrta", opt, nullptr, &error));
  EXPECT_EQ(error, "--texture-precision f16: image 0 ('" + dir +
                       "/hot.pfm') holds 70000 in level 0, which is beyond half precision's "
                       "range (65504); use --texture-precision f32");
  opt.texture_format = pbrta::PixelFormat::kUnorm8;
  EXPECT_FALSE(write_archive(scene, files, dir, dir + "/a.pbrta", opt, nullptr, &error));
  EXPECT_NE(error.find("holds 70000 in level 0"), std::string::npos) << error;
}

// Edits the uncompressed archive's image records and checks what the reader says.
TEST(TexturePrecision, ReaderChecksFormats) {
  Compiled c;
  compile("v3-figures/f8-22.pbrt", &c);
  ASSERT_TRUE(c.ok);
  const std::string dir = testing_support::scratch_dir("texture_precision_reader");
  const std::string path = dir + "/u.pbrta";
  std::string error;
  // unorm8 cannot take the HDR map, so f16 for this scene; lines.exr is an image too.
  ASSERT_TRUE(write(c, path, pbrta::PixelFormat::kHalf16, false, &error)) << error;
  pbrta::SceneArchive archive;
  ASSERT_TRUE(archive.load(path, 1, &error)) << error;
  const uint32_t images_entry =
      testing_support::section_entry(archive, pbrta::SectionKind::kImages);
  ASSERT_NE(images_entry, pbrta::kNoIndex);
  const uint64_t images_at = archive.reader().entry(images_entry).offset;
  uint32_t map = pbrta::kNoIndex;
  for (uint32_t i = 0; i < archive.images.size; ++i)
    if (archive.images[i].distribution != pbrta::kNoIndex) map = i;
  ASSERT_NE(map, pbrta::kNoIndex);
  const uint32_t dist = archive.images[map].distribution;
  const std::string good = testing_support::read_file(path);
  auto edit_format = [&](uint32_t image, uint32_t value) {
    std::string bytes = good;
    std::memcpy(&bytes[images_at + image * sizeof(pbrta::ImageRecord) +
                       offsetof(pbrta::ImageRecord, format)],
                &value, 4);
    return testing_support::reseal_and_load(bytes, dir + "/bad.pbrta");
  };
  const std::string prefix =
      dir + "/bad.pbrta: section 'images' (#" + std::to_string(images_entry) + "): image ";
  EXPECT_EQ(edit_format(map, 3), prefix + std::to_string(map) + ": malformed header");
  // f16 levels read as f32 need twice the bytes: the last ones run off the section.
  const std::string grown = edit_format(map, 0);
  EXPECT_EQ(grown.substr(0, prefix.size() + std::to_string(map).size() + 8),
            prefix + std::to_string(map) + ": level ")
      << grown;
  EXPECT_NE(grown.find("lies outside its section"), std::string::npos) << grown;
  EXPECT_EQ(edit_format(dist, 2), prefix + std::to_string(map) + ": distribution image " +
                                      std::to_string(dist) + " is unorm8, not f32");

  // A distribution is one level: in an f32 archive, the map named as its own distribution (f32,
  // in range, but a whole pyramid) is refused.
  const std::string path32 = dir + "/f32.pbrta";
  ASSERT_TRUE(write(c, path32, pbrta::PixelFormat::kFloat32, false, &error)) << error;
  pbrta::SceneArchive a32;
  ASSERT_TRUE(a32.load(path32, 1, &error)) << error;
  ASSERT_GT(a32.images[map].levels, 1u);
  ASSERT_EQ(testing_support::section_entry(a32, pbrta::SectionKind::kImages), images_entry);
  std::string bytes = testing_support::read_file(path32);
  std::memcpy(&bytes[a32.reader().entry(images_entry).offset + map * sizeof(pbrta::ImageRecord) +
                     offsetof(pbrta::ImageRecord, distribution)],
              &map, 4);
  EXPECT_EQ(testing_support::reseal_and_load(bytes, dir + "/bad.pbrta"),
            prefix + std::to_string(map) + ": " + std::to_string(a32.images[map].levels) +
                " levels, but as image " + std::to_string(map) + "'s distribution it has 1");
}

// A dump of an unorm8 archive writes the decoded values; they compile back (f32) to exactly
// those values in level 0.
TEST(TexturePrecision, DumpWritesDecodedTexels) {
  Compiled c;
  compile("hm-textures/pbrt-v3-rs/scenes/textures/2d-mappings.pbrt", &c);
  ASSERT_TRUE(c.ok);
  ASSERT_FALSE(c.scene.images.empty());
  const std::string dir = testing_support::scratch_dir("texture_precision_dump");
  std::string error;
  ASSERT_TRUE(write(c, dir + "/u8.pbrta", pbrta::PixelFormat::kUnorm8, true, &error)) << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(dir + "/u8.pbrta", 1, &error)) << error;
  ASSERT_TRUE(dump_archive(a, dir + "/dump", "u8.pbrt", &error)) << error;
  Compiled back;
  back.path = dir + "/dump/u8.pbrt";
  Diagnostics diag(&back.files, nullptr);
  ASSERT_TRUE(build_scene(back.path, &back.files, &diag, &back.scene));
  ASSERT_TRUE(write(back, dir + "/back.pbrta", pbrta::PixelFormat::kFloat32, true, &error))
      << error;
  pbrta::SceneArchive b;
  ASSERT_TRUE(b.load(dir + "/back.pbrta", 1, &error)) << error;
  ASSERT_EQ(b.images.size, a.images.size);
  for (uint32_t i = 0; i < a.images.size; ++i) {
    const pbrta::ImageRecord& q = a.images[i];
    const pbrta::ImageRecord& f = b.images[i];
    if (q.source_image != pbrta::kNoIndex) continue;  // resampled: compare its source instead
    ASSERT_EQ(f.format, 0u);
    ASSERT_EQ(q.width, f.width);
    const size_t n = size_t(q.width) * q.height * q.channels;
    std::vector<float> want(n);
    pbrta::decode_texels(q.format, a.reader().section_data(q.section) + q.offset, n, want.data());
    EXPECT_EQ(0, std::memcmp(b.reader().section_data(f.section) + f.offset, want.data(), n * 4))
        << "image " << i;
  }
}

}  // namespace
}  // namespace pbrtc
