// tests/pbrt/pbrt_command_test.cpp — the pbrt command, run as users run it.
//
// Every test runs the built executables (pbrt, pbrtc, pbrtrun in PBRTC_BINARY_DIR) on a
// tiny scene written into a scratch directory: 32x32 pixels, 4 samples, with an Include,
// a PLY mesh and an imagemap texture, so editing each kind of input can be checked.
// Each test has its own XDG_CACHE_HOME, so caches never leak between tests.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "command_runner.h"
#include "compiler/archive_dump.h"
#include "format/archive.h"
#include "format/mesh_arrays.h"
#include "compiler/ply_writer.h"
#include "runtime/film/image_io.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using testing_support::find_in_order;
using testing_support::kBin;
using testing_support::Outcome;
using testing_support::read_file;
using testing_support::run_in;
using testing_support::run_on_terminal;
using testing_support::scratch_dir;
using testing_support::write_file;

std::string pbrt() {
  return kBin + "/pbrt --nthreads 1";
}

// A 4x4 checker of two colours as a linear RGB PFM texture.
void write_texture(const std::string& path, float r, float g, float b) {
  std::vector<float> texels;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      bool on = (x + y) % 2 == 0;
      texels.insert(texels.end(), {on ? r : 0.1f, on ? g : 0.1f, on ? b : 0.1f});
    }
  std::string error;
  ASSERT_TRUE(pbrtc::write_pfm(path, texels.data(), 4, 4, 3, &error)) << error;
}

// A unit quad in the xy plane (two triangles), offset by z, as a binary PLY.
void write_mesh(const std::string& path, float z) {
  const float p[] = {-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z};
  const float uv[] = {0, 0, 1, 0, 1, 1, 0, 1};
  const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
  pbrta::MeshArrays m;
  m.positions = p;
  m.uv = uv;
  m.indices = idx;
  m.num_vertices = 4;
  m.num_triangles = 2;
  std::string error;
  ASSERT_TRUE(pbrtc::write_ply(path, m, &error)) << error;
}

const char* kScene = R"(LookAt 0 0 -4  0 0 0  0 1 0
Camera "perspective" "float fov" 45
Film "image" "integer xresolution" 32 "integer yresolution" 32 "string filename" "film.exr"
Sampler "halton" "integer pixelsamples" 4
Integrator "directlighting"
WorldBegin
LightSource "point" "point from" [0 2 -3] "rgb I" [8 8 8]
LightSource "infinite" "rgb L" [0.2 0.2 0.2]
Include "materials.pbrt"
AttributeBegin
  Texture "checks" "spectrum" "imagemap" "string filename" "tex.pfm"
  Material "matte" "texture Kd" "checks"
  Shape "plymesh" "string filename" "quad.ply"
AttributeEnd
AttributeBegin
  NamedMaterial "red"
  Translate 0.4 0.3 -1
  Shape "sphere" "float radius" 0.3
AttributeEnd
WorldEnd
)";

// The test scene in a fresh directory; returns the directory.
std::string make_scene(const std::string& name) {
  std::string dir = scratch_dir("pbrt_" + name);
  write_file(dir + "/scene.pbrt", kScene);
  write_file(dir + "/materials.pbrt",
             "MakeNamedMaterial \"red\" \"string type\" \"matte\" \"rgb Kd\" [0.8 0.1 0.1]\n");
  write_texture(dir + "/tex.pfm", 0.9f, 0.8f, 0.2f);
  write_mesh(dir + "/quad.ply", 0);
  return dir;
}

rt::ImageRgb read_image(const std::string& path) {
  rt::ImageRgb img;
  std::string error;
  EXPECT_TRUE(rt::read_exr(path, &img, &error)) << error;
  return img;
}

// Same size and bit-identical pixels.
bool same_pixels(const std::string& a, const std::string& b) {
  rt::ImageRgb ia = read_image(a), ib = read_image(b);
  return ia.width() == ib.width() && ia.height() == ib.height() && !ia.rgb.empty() &&
         ia.rgb == ib.rgb;
}

std::vector<fs::path> cached_archives(const std::string& dir) {
  std::vector<fs::path> out;
  fs::path archives = fs::path(dir) / "cache/pbrtc/archives";
  if (!fs::exists(archives)) return out;
  for (const auto& e : fs::directory_iterator(archives))
    if (e.path().extension() == ".pbrta" && e.path().filename().string()[0] != '.')
      out.push_back(e.path());
  return out;
}

uint64_t cache_bytes(const std::string& dir) {
  uint64_t total = 0;
  for (const char* sub : {"archives", "manifests"}) {
    fs::path p = fs::path(dir) / "cache/pbrtc" / sub;
    if (!fs::exists(p)) continue;
    for (const auto& e : fs::directory_iterator(p)) total += fs::file_size(e.path());
  }
  return total;
}

TEST(PbrtCommand, SamePixelsAsPbrtcThenPbrtrun) {
  std::string dir = make_scene("same_pixels");
  Outcome c = run_in(dir, kBin + "/pbrtc -q scene.pbrt -o scene.pbrta", "pbrtc");
  ASSERT_EQ(c.status, 0) << c.err;
  Outcome r =
      run_in(dir, kBin + "/pbrtrun -q scene.pbrta --outfile two-step.exr --seed 3", "pbrtrun");
  ASSERT_EQ(r.status, 0) << r.err;
  Outcome p = run_in(dir, pbrt() + " --quiet scene.pbrt --outfile one-step.exr --seed 3");
  ASSERT_EQ(p.status, 0) << p.err;
  EXPECT_TRUE(same_pixels(dir + "/two-step.exr", dir + "/one-step.exr"));
  // The film's own filename when --outfile is not given, as pbrt-v3 does.
  Outcome f = run_in(dir, pbrt() + " --quiet scene.pbrt --seed 3", "film");
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_TRUE(same_pixels(dir + "/film.exr", dir + "/one-step.exr"));
  // A different seed is a different image: the comparison above can fail.
  Outcome s = run_in(dir, pbrt() + " --quiet scene.pbrt --outfile seed4.exr --seed 4", "seed4");
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_FALSE(same_pixels(dir + "/seed4.exr", dir + "/one-step.exr"));
}

TEST(PbrtCommand, SecondRunHitsTheCache) {
  std::string dir = make_scene("second_run");
  Outcome first = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile a.exr", "first");
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_NE(first.err.find("cache: miss"), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("pbrtrun statistics for scene.pbrt"), std::string::npos) << first.err;
  Outcome second = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile b.exr", "second");
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_NE(second.err.find("cache: hit"), std::string::npos) << second.err;
  EXPECT_TRUE(same_pixels(dir + "/a.exr", dir + "/b.exr"));
  // Render-only options do not change the key.
  Outcome third = run_in(dir,
                         pbrt() +
                             " --quiet --stats --quick --spp 2 --cropwindow 0 .5 0 .5 "
                             "scene.pbrt --outfile c.exr",
                         "third");
  ASSERT_EQ(third.status, 0) << third.err;
  EXPECT_NE(third.err.find("cache: hit"), std::string::npos) << third.err;
  std::printf("[ timing ] miss %.3f s, hit %.3f s (whole command)\n", first.seconds,
              second.seconds);
}

// On a terminal a compile shows pbrtc's progress line (its PLY, image and compressing phases),
// erased before the render's progress bar; a cache hit compiles nothing and shows none of it,
// and --quiet shows neither.
TEST(PbrtCommand, ACompileShowsItsProgressOnATerminal) {
  std::string dir = make_scene("progress");
  const Outcome miss = run_on_terminal(dir, pbrt() + " scene.pbrt --outfile a.exr");
  ASSERT_EQ(miss.status, 0) << miss.out;
  const std::string line = "\r\033[Kscene.pbrt: ";
  const std::vector<size_t> at = find_in_order(
      miss.out,
      {line + "PLY meshes (1)", line + "images (1)", line + "compressing (", "Rendering: ["});
  ASSERT_EQ(at.size(), 4u);
  // The last line drawn before the bar is an erase, not a compile count.
  const size_t last = miss.out.rfind("\r\033[K", at[3]);
  EXPECT_GT(last, at[2]);
  EXPECT_NE(miss.out.compare(last, line.size(), line), 0) << miss.out;
  const Outcome hit = run_on_terminal(dir, pbrt() + " scene.pbrt --outfile b.exr");
  ASSERT_EQ(hit.status, 0) << hit.out;
  EXPECT_EQ(hit.out.find(line), std::string::npos) << hit.out;
  EXPECT_NE(hit.out.find("Rendering: ["), std::string::npos) << hit.out;
  const Outcome quiet =
      run_on_terminal(dir, pbrt() + " --quiet --no-cache scene.pbrt --outfile c.exr");
  ASSERT_EQ(quiet.status, 0) << quiet.out;
  EXPECT_EQ(quiet.out, "");
}

// Edits one input, then expects a recompile and a different image.
void expect_recompile(const std::string& name, void (*edit)(const std::string& dir)) {
  std::string dir = make_scene(name);
  Outcome first = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile a.exr", "first");
  ASSERT_EQ(first.status, 0) << first.err;
  edit(dir);
  Outcome second = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile b.exr", "second");
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_NE(second.err.find("cache: miss"), std::string::npos) << second.err;
  EXPECT_FALSE(same_pixels(dir + "/a.exr", dir + "/b.exr"));
  Outcome third = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile c.exr", "third");
  EXPECT_NE(third.err.find("cache: hit"), std::string::npos) << third.err;
  EXPECT_TRUE(same_pixels(dir + "/b.exr", dir + "/c.exr"));
}

TEST(PbrtCommand, EditingAnIncludedFileRecompiles) {
  expect_recompile("edit_include", [](const std::string& dir) {
    // Same size, other content: only the hash can tell.
    write_file(dir + "/materials.pbrt",
               "MakeNamedMaterial \"red\" \"string type\" \"matte\" \"rgb Kd\" [0.1 0.8 0.1]\n");
  });
}

TEST(PbrtCommand, EditingAPlyMeshRecompiles) {
  expect_recompile("edit_mesh",
                   [](const std::string& dir) { write_mesh(dir + "/quad.ply", 0.5f); });
}

TEST(PbrtCommand, EditingATextureRecompiles) {
  expect_recompile("edit_texture", [](const std::string& dir) {
    write_texture(dir + "/tex.pfm", 0.1f, 0.3f, 0.9f);
  });
}

TEST(PbrtCommand, TouchingWithoutChangingContentStillHits) {
  std::string dir = make_scene("touch_only");
  ASSERT_EQ(run_in(dir, pbrt() + " --quiet scene.pbrt --outfile a.exr", "first").status, 0);
  fs::last_write_time(dir + "/quad.ply",
                      fs::last_write_time(dir + "/quad.ply") + std::chrono::seconds(5));
  Outcome second = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile b.exr", "second");
  EXPECT_NE(second.err.find("cache: hit"), std::string::npos) << second.err;
}

TEST(PbrtCommand, CorruptEntryIsDetectedAndRebuilt) {
  std::string dir = make_scene("corrupt");
  ASSERT_EQ(run_in(dir, pbrt() + " --quiet scene.pbrt --outfile a.exr", "first").status, 0);
  std::vector<fs::path> archives = cached_archives(dir);
  ASSERT_EQ(archives.size(), 1u);
  {
    // Flip bytes in the second half of the file: section data, covered by checksums.
    std::fstream f(archives[0], std::ios::in | std::ios::out | std::ios::binary);
    uint64_t size = fs::file_size(archives[0]);
    ASSERT_GT(size, 256u);
    for (uint64_t at = size / 2; at < size / 2 + 16; ++at) {
      f.seekg(std::streamoff(at));
      char c = char(f.get());
      f.seekp(std::streamoff(at));
      f.put(char(c ^ 0x5A));
    }
  }
  Outcome second = run_in(dir, pbrt() + " --stats --quiet scene.pbrt --outfile b.exr", "second");
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_NE(second.err.find("cache: rebuilt (corrupt)"), std::string::npos) << second.err;
  EXPECT_TRUE(same_pixels(dir + "/a.exr", dir + "/b.exr"));
  Outcome third = run_in(dir, pbrt() + " --stats --quiet scene.pbrt --outfile c.exr", "third");
  EXPECT_NE(third.err.find("cache: hit"), std::string::npos) << third.err;
  EXPECT_EQ(cached_archives(dir).size(), 1u);
}

// An entry whose archive says version 1.4 (what a pbrt of archive 1.x wrote; entries are keyed by
// the archive version, so only a hand-copied one is ever found): recompiled, same image.
TEST(PbrtCommand, OutdatedEntryIsRecompiled) {
  std::string dir = make_scene("outdated");
  ASSERT_EQ(run_in(dir, pbrt() + " --quiet scene.pbrt --outfile a.exr", "first").status, 0);
  std::vector<fs::path> archives = cached_archives(dir);
  ASSERT_EQ(archives.size(), 1u);
  {
    std::string b = testing_support::read_file(archives[0].string());
    pbrta::Header h;
    std::memcpy(&h, b.data(), sizeof h);
    h.major = 1;
    h.minor = 4;
    h.header_checksum = XXH3_64bits(&h, offsetof(pbrta::Header, header_checksum));
    std::memcpy(b.data(), &h, sizeof h);
    testing_support::write_file(archives[0].string(), b);
  }
  Outcome second = run_in(dir, pbrt() + " --stats scene.pbrt --outfile b.exr", "second");
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_NE(second.err.find("cache: rebuilt (outdated)"), std::string::npos) << second.err;
  EXPECT_NE(second.err.find("archive version 1.4: recompile with this pbrtc"), std::string::npos)
      << second.err;
  EXPECT_TRUE(same_pixels(dir + "/a.exr", dir + "/b.exr"));
  Outcome third = run_in(dir, pbrt() + " --stats --quiet scene.pbrt --outfile c.exr", "third");
  EXPECT_NE(third.err.find("cache: hit"), std::string::npos) << third.err;
}

TEST(PbrtCommand, ConcurrentRunsOfOneSceneBothSucceed) {
  std::string dir = make_scene("concurrent");
  Outcome a, b;
  std::thread ta([&] { a = run_in(dir, pbrt() + " --quiet scene.pbrt --outfile a.exr", "a"); });
  std::thread tb([&] { b = run_in(dir, pbrt() + " --quiet scene.pbrt --outfile b.exr", "b"); });
  ta.join();
  tb.join();
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_TRUE(same_pixels(dir + "/a.exr", dir + "/b.exr"));
  EXPECT_EQ(cached_archives(dir).size(), 1u);
  Outcome c = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile c.exr", "c");
  EXPECT_NE(c.err.find("cache: hit"), std::string::npos) << c.err;
}

TEST(PbrtCommand, CacheStaysUnderItsCap) {
  std::string dir = make_scene("cap");
  ASSERT_EQ(run_in(dir, pbrt() + " --quiet scene.pbrt --outfile a.exr", "first").status, 0);
  const uint64_t one = cache_bytes(dir);
  ASSERT_GT(one, 0u);
  // Room for about two and a half scenes; then render six different ones.
  const uint64_t cap = one * 5 / 2;
  for (int i = 0; i < 6; ++i) {
    std::string scene = "scene" + std::to_string(i) + ".pbrt";
    std::string text = kScene;
    text.replace(text.find("[0 2 -3]"), 8, "[0 2 -" + std::to_string(i + 2) + "]");
    write_file(dir + "/" + scene, text);
    Outcome r = run_in(dir,
                       pbrt() + " --quiet --stats --cache-size " + std::to_string(cap) + "b " +
                           scene + " --outfile out.exr",
                       "cap" + std::to_string(i));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("cache: miss"), std::string::npos) << r.err;
    EXPECT_LE(cache_bytes(dir), cap) << "after scene " << i;
  }
  EXPECT_LE(cached_archives(dir).size(), 2u);
  // The most recent scene survived; the first was evicted.
  Outcome last = run_in(dir,
                        pbrt() + " --quiet --stats --cache-size " + std::to_string(cap) +
                            "b scene5.pbrt --outfile out.exr",
                        "last");
  EXPECT_NE(last.err.find("cache: hit"), std::string::npos) << last.err;
  Outcome oldest = run_in(dir,
                          pbrt() + " --quiet --stats --cache-size " + std::to_string(cap) +
                              "b scene.pbrt --outfile out.exr",
                          "oldest");
  EXPECT_NE(oldest.err.find("cache: miss"), std::string::npos) << oldest.err;
}

TEST(PbrtCommand, NoCacheLeavesNothingBehind) {
  std::string dir = make_scene("no_cache");
  Outcome r = run_in(dir, pbrt() + " --quiet --stats --no-cache scene.pbrt --outfile a.exr");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("cache: bypassed"), std::string::npos) << r.err;
  EXPECT_TRUE(cached_archives(dir).empty());
  EXPECT_FALSE(fs::exists(dir + "/cache/pbrtc"));
}

TEST(PbrtCommand, QuickRendersAQuarterResolutionAtOneSample) {
  std::string dir = make_scene("quick");
  Outcome r = run_in(dir, pbrt() + " --quiet --stats --quick scene.pbrt --outfile q.exr");
  ASSERT_EQ(r.status, 0) << r.err;
  rt::ImageRgb img = read_image(dir + "/q.exr");
  EXPECT_EQ(img.width(), 8);
  EXPECT_EQ(img.height(), 8);
  EXPECT_NE(r.err.find("samples per pixel      1\n"), std::string::npos) << r.err;
}

// pbrt-v3's --quick divides sppm's iterations (and mlt's mutations) by 16 instead of setting
// one sample per pixel.
TEST(PbrtCommand, QuickDividesSppmIterationsBySixteen) {
  std::string dir = scratch_dir("pbrt_quick_sppm");
  write_file(dir + "/sppm.pbrt", R"(Camera "perspective"
Film "image" "integer xresolution" 16 "integer yresolution" 16
Integrator "sppm" "integer iterations" 64 "integer photonsperiteration" 100
WorldBegin
LightSource "point" "point from" [0 0 -2] "rgb I" [1 1 1]
Material "matte"
Shape "sphere"
WorldEnd
)");
  Outcome r = run_in(dir, pbrt() + " --quiet --stats --quick sppm.pbrt --outfile q.exr");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("samples per pixel      4\n"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("photons                400 in 4 iterations"), std::string::npos) << r.err;
}

// The "rays ... N shadow" count of a --stats report.
long long shadow_rays(const std::string& stats) {
  size_t at = stats.find(" intersection, ");
  return at == std::string::npos ? -1 : std::atoll(stats.c_str() + at + 15);
}

TEST(PbrtCommand, QuickDividesLightSamplesByFour) {
  std::string dir = scratch_dir("pbrt_quick_nsamples");
  // directlighting samples an area light "nsamples" times per hit: 8, and 2 under --quick.
  auto scene = [](int res) {
    return "LookAt 0 0 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 45\n"
           "Film \"image\" \"integer xresolution\" " +
           std::to_string(res) + " \"integer yresolution\" " + std::to_string(res) +
           "\nSampler \"halton\" \"integer pixelsamples\" 4\n"
           "Integrator \"directlighting\"\nWorldBegin\n"
           "AttributeBegin\n  Translate 0 1.5 -1\n"
           "  AreaLightSource \"diffuse\" \"rgb L\" [4 4 4] \"integer nsamples\" 8\n"
           "  Shape \"sphere\" \"float radius\" 0.3\nAttributeEnd\n"
           "Material \"matte\"\n"
           "Shape \"trianglemesh\" \"point3 P\" [-2 -1 -2  2 -1 -2  2 -1 2  -2 -1 2]\n"
           "  \"integer indices\" [0 1 2 0 2 3]\nWorldEnd\n";
  };
  write_file(dir + "/full.pbrt", scene(32));
  write_file(dir + "/small.pbrt", scene(8));
  Outcome quick = run_in(dir, pbrt() + " --quiet --stats --quick full.pbrt --outfile q.exr", "q");
  ASSERT_EQ(quick.status, 0) << quick.err;
  Outcome one = run_in(dir, pbrt() + " --quiet --stats --spp 1 small.pbrt --outfile s.exr", "s");
  ASSERT_EQ(one.status, 0) << one.err;
  // Same 8x8 pixels, same camera rays and hits: only the light samples differ.
  long long q = shadow_rays(quick.err), s = shadow_rays(one.err);
  ASSERT_GT(q, 0) << quick.err;
  EXPECT_EQ(s, 4 * q) << one.err << quick.err;
}

TEST(PbrtCommand, ReadsStandardInputAndSeveralFiles) {
  std::string dir = make_scene("stdin");
  Outcome f = run_in(dir, pbrt() + " --quiet scene.pbrt --outfile file.exr", "file");
  ASSERT_EQ(f.status, 0) << f.err;
  Outcome s = run_in(dir, pbrt() + " --quiet --stats --outfile stdin.exr < scene.pbrt", "stdin");
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_NE(s.err.find("<stdin>: cache: miss"), std::string::npos) << s.err;
  EXPECT_TRUE(same_pixels(dir + "/file.exr", dir + "/stdin.exr"));
  Outcome again =
      run_in(dir, pbrt() + " --quiet --stats --outfile stdin.exr < scene.pbrt", "again");
  EXPECT_NE(again.err.find("<stdin>: cache: hit"), std::string::npos) << again.err;
  // Two scenes in a row, each rendered in turn (to its film's filename).
  write_file(dir + "/other.pbrt",
             std::string(kScene).replace(std::string(kScene).find("film.exr"), 8, "other.exr"));
  Outcome two = run_in(dir, pbrt() + " --quiet --stats scene.pbrt other.pbrt", "two");
  ASSERT_EQ(two.status, 0) << two.err;
  EXPECT_NE(two.err.find("pbrtrun statistics for scene.pbrt"), std::string::npos);
  EXPECT_NE(two.err.find("pbrtrun statistics for other.pbrt"), std::string::npos);
  EXPECT_TRUE(same_pixels(dir + "/film.exr", dir + "/other.exr"));
}

TEST(PbrtCommand, ErrorsNameTheLineAndExitNonZero) {
  std::string dir = make_scene("errors");
  write_file(dir + "/bad.pbrt",
             "WorldBegin\nShape \"sphere\" \"float radius\" [1]\nShape \"spere\"\n");
  Outcome bad = run_in(dir, pbrt() + " bad.pbrt --outfile x.exr", "bad");
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("bad.pbrt:3:1: error: unknown shape type \"spere\""), std::string::npos)
      << bad.err;
  EXPECT_FALSE(fs::exists(dir + "/x.exr"));
  // bdpt traces from lights to the camera: like pbrt-v3, only with a perspective camera.
  std::string text = kScene;
  text.replace(text.find("\"directlighting\""), 16, "\"bdpt\"");
  text.replace(text.find("\"perspective\" \"float fov\" 45"), 28, "\"orthographic\"");
  write_file(dir + "/bdpt.pbrt", text);
  Outcome unsupported = run_in(dir, pbrt() + " bdpt.pbrt --outfile y.exr", "unsupported");
  EXPECT_EQ(unsupported.status, 1);
  EXPECT_NE(unsupported.err.find("bdpt needs a perspective camera"), std::string::npos)
      << unsupported.err;
  EXPECT_FALSE(fs::exists(dir + "/y.exr"));
  Outcome usage = run_in(dir, pbrt() + " --frobnicate scene.pbrt", "usage");
  EXPECT_EQ(usage.status, 2);
  EXPECT_NE(usage.err.find("usage: pbrt"), std::string::npos);
}

// The test scene without its image texture.
std::string scene_without_images() {
  std::string text = kScene;
  const size_t from = text.find("  Texture \"checks\""), to = text.find("  Shape \"plymesh\"");
  text.replace(from, to - from, "  Material \"matte\"\n");
  return text;
}

// OpenImageIO and the ~260 libraries it brings cost ~0.5 s of dynamic linking per process
// start, so pbrtc and pbrt load them (through libpbrtc_images.so) only for a scene that names
// an image. LD_DEBUG=files makes the dynamic linker list every object it loads, dlopen()ed ones
// too, so both halves of that are seen, not assumed.
TEST(PbrtCommand, ImageLibrariesLoadOnlyForScenesThatNameAnImage) {
  std::string dir = make_scene("image_module");
  write_file(dir + "/plain.pbrt", scene_without_images());
  const std::string trace = "LD_DEBUG=files ";
  // It ran, the trace is there (so absence means something), and neither library was loaded.
  auto expect_no_image_libraries = [](const Outcome& r) {
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("file=libtbb"), std::string::npos) << "no loader trace: " << r.err;
    EXPECT_EQ(r.err.find("libOpenImageIO"), std::string::npos);
    EXPECT_EQ(r.err.find("libpbrtc_images"), std::string::npos);
  };
  expect_no_image_libraries(
      run_in(dir, trace + kBin + "/pbrtc -q plain.pbrt -o plain.pbrta", "plain"));
  expect_no_image_libraries(
      run_in(dir, trace + pbrt() + " --quiet plain.pbrt --outfile plain.exr", "render"));

  Outcome textured = run_in(dir, trace + kBin + "/pbrtc -q scene.pbrt -o scene.pbrta", "textured");
  ASSERT_EQ(textured.status, 0) << textured.err;
  EXPECT_NE(textured.err.find("libpbrtc_images.so [0];  dynamically loaded"), std::string::npos)
      << textured.err;
  EXPECT_NE(textured.err.find("libOpenImageIO"), std::string::npos);
}

// Images are decoded by the module, not the pbrt executable, so a different module (rebuilt, or
// named by PBRTC_IMAGE_MODULE) must not reuse archives the old one decoded images for.
TEST(PbrtCommand, ADifferentImageModuleRecompiles) {
  std::string dir = make_scene("other_image_module");
  Outcome first = run_in(dir, pbrt() + " --quiet --stats scene.pbrt --outfile a.exr", "first");
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_NE(first.err.find("cache: miss"), std::string::npos) << first.err;
  fs::copy_file(kBin + "/libpbrtc_images.so", dir + "/copy.so");
  const std::string other = "PBRTC_IMAGE_MODULE='" + dir + "/copy.so' ";
  Outcome second =
      run_in(dir, other + pbrt() + " --quiet --stats scene.pbrt --outfile b.exr", "second");
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_NE(second.err.find("cache: miss"), std::string::npos) << second.err;
  Outcome third =
      run_in(dir, other + pbrt() + " --quiet --stats scene.pbrt --outfile c.exr", "third");
  ASSERT_EQ(third.status, 0) << third.err;
  EXPECT_NE(third.err.find("cache: hit"), std::string::npos) << third.err;
  EXPECT_TRUE(same_pixels(dir + "/a.exr", dir + "/c.exr"));
}

// Without its image module pbrtc still compiles scenes that name no image; one that does fails
// at the image's line, saying what was tried and how to point pbrtc at the module.
TEST(PbrtCommand, AMissingImageModuleFailsOnlyScenesWithImages) {
  std::string dir = make_scene("no_image_module");
  write_file(dir + "/plain.pbrt", scene_without_images());
  const std::string missing = "PBRTC_IMAGE_MODULE='" + dir + "/gone/libpbrtc_images.so' ";
  Outcome plain = run_in(dir, missing + kBin + "/pbrtc -q plain.pbrt -o plain.pbrta", "plain");
  EXPECT_EQ(plain.status, 0) << plain.err;
  EXPECT_TRUE(fs::exists(dir + "/plain.pbrta"));
  Outcome textured = run_in(dir, missing + kBin + "/pbrtc -q scene.pbrt -o scene.pbrta", "tex");
  EXPECT_EQ(textured.status, 1);
  EXPECT_NE(textured.err.find("scene.pbrt:11:"), std::string::npos) << textured.err;
  EXPECT_NE(textured.err.find("tex.pfm"), std::string::npos) << textured.err;
  EXPECT_NE(textured.err.find("cannot load pbrtc's image reader module (" + dir +
                              "/gone/libpbrtc_images.so: cannot open shared object file"),
            std::string::npos)
      << textured.err;
  EXPECT_NE(textured.err.find("set PBRTC_IMAGE_MODULE"), std::string::npos) << textured.err;
  EXPECT_FALSE(fs::exists(dir + "/scene.pbrta"));
}

TEST(PbrtCommand, HelpListsEveryOption) {
  std::string dir = scratch_dir("pbrt_help");
  Outcome r = run_in(dir, kBin + "/pbrt --help");
  ASSERT_EQ(r.status, 0);
  for (const char* line :
       {"usage: pbrt [<options>] <filename.pbrt...>",
        "--cropwindow <x0,x1,y0,y1> Specify an image crop window.",
        "--help               Print this help text.",
        "--nthreads <num>     Use specified number of threads for rendering.",
        "--outfile <filename> Write the final image to the given filename.",
        "--quick              Automatically reduce a number of quality settings to",
        "--quiet              Suppress all text output other than error messages.",
        "--cat                Print a reformatted version of the input file(s) to",
        "--toply              Print a reformatted version of the input file(s) to", "--spp <num>",
        "--seed <num>", "--stats", "--cache-size <size>", "--no-cache", "--preview <file.png>"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line;
}

TEST(PbrtCommand, CatAndToplyPrintScenesThatRenderTheSame) {
  std::string dir = make_scene("cat");
  ASSERT_EQ(run_in(dir, pbrt() + " --quiet scene.pbrt --outfile orig.exr", "orig").status, 0);
  Outcome cat = run_in(dir, pbrt() + " --cat scene.pbrt", "cat");
  ASSERT_EQ(cat.status, 0) << cat.err;
  EXPECT_EQ(cat.out.find("plymesh"), std::string::npos);  // meshes inline
  EXPECT_NE(cat.out.find("Shape \"trianglemesh\""), std::string::npos);
  EXPECT_NE(cat.out.find("\"tex.pfm\""), std::string::npos);  // the file the scene named
  EXPECT_FALSE(fs::exists(dir + "/film.exr"));                // nothing rendered
  write_file(dir + "/cat.pbrt", cat.out);
  ASSERT_EQ(run_in(dir, pbrt() + " --quiet cat.pbrt --outfile cat.exr", "cat-render").status, 0);
  EXPECT_TRUE(same_pixels(dir + "/orig.exr", dir + "/cat.exr"));

  Outcome ply = run_in(dir, pbrt() + " --toply scene.pbrt", "toply");
  ASSERT_EQ(ply.status, 0) << ply.err;
  EXPECT_NE(ply.out.find("Shape \"plymesh\" \"string filename\" [\"mesh_0.ply\"]"),
            std::string::npos)
      << ply.out;
  EXPECT_TRUE(fs::exists(dir + "/mesh_0.ply"));
  write_file(dir + "/toply.pbrt", ply.out);
  ASSERT_EQ(run_in(dir, pbrt() + " --quiet toply.pbrt --outfile ply.exr", "ply-render").status, 0);
  EXPECT_TRUE(same_pixels(dir + "/orig.exr", dir + "/ply.exr"));
}

TEST(PbrtCommand, PreviewWritesAPng) {
  std::string dir = make_scene("preview");
  Outcome r = run_in(dir, pbrt() + " --quiet scene.pbrt --outfile a.exr --preview a.png");
  ASSERT_EQ(r.status, 0) << r.err;
  std::string png = read_file(dir + "/a.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}

}  // namespace
