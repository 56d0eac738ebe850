// tests/compiler/fourier_bsdf_test.cpp — the fourier material's .bsdf file, read at compile time.
//
// pbrt-v3's real roughgold table compiles into the material's derived parameters with the
// file's own numbers and is recorded as a compile input; truncated and garbled copies are
// errors at the file name's location saying what is wrong; an archive whose table does not
// hang together is refused by SceneArchive::load; and an archive from before version 1.1
// (fourier with its two original parameters) still loads, with no table.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "compiler/archive_builder.h"
#include "compiler/bsdf_file.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/archive.h"
#include "format/fourier_table.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace pbrtc {
namespace {

std::string gold_path() {
  return testing_support::shared_dir() +
         "/scenes/hm-materials-partial/pbrt-v3-scenes/dragon/bsdfs/roughgold_alpha_0.2.bsdf";
}

// Line 3 names the table; its value starts at column 38.
std::string scene_text(const std::string& bsdf) {
  return "Camera \"perspective\"\nWorldBegin\nMaterial \"fourier\" \"string bsdffile\" \"" + bsdf +
         "\"\nShape \"sphere\"\nWorldEnd\n";
}

int32_t word_i(const std::string& b, size_t word) {
  int32_t v;
  std::memcpy(&v, b.data() + 4 * word, 4);
  return v;
}
float word_f(const std::string& b, size_t word) {
  float v;
  std::memcpy(&v, b.data() + 4 * word, 4);
  return v;
}
void put_word(std::string* b, size_t word, int32_t v) {
  std::memcpy(b->data() + 4 * word, &v, 4);
}
void put_word(std::string* b, size_t word, float v) {
  std::memcpy(b->data() + 4 * word, &v, 4);
}

uint32_t fourier_entity(const pbrta::SceneArchive& a) {
  for (const pbrta::MaterialRecord& m : a.materials)
    if (a.type_name(m.entity) == "fourier") return m.entity;
  return pbrta::kNoIndex;
}

TEST(FourierBsdf, RealTableCompilesWithTheFilesNumbers) {
  const std::string raw = testing_support::read_file(gold_path());
  ASSERT_EQ(raw.size(), 207354u);
  const std::string dir = testing_support::scratch_dir("fourier_bsdf_real");
  const std::string scene =
      testing_support::write_file(dir + "/scene.pbrt", scene_text(gold_path()));
  SourceFiles files;
  Diagnostics diag(&files, nullptr);
  SceneDesc desc;
  ASSERT_TRUE(build_scene(scene, &files, &diag, &desc))
      << (diag.all().empty() ? "" : diag.all()[0].text);
  // The table is an input of the compile: the pbrt command's cache hashes it.
  EXPECT_NE(std::find(desc.input_files.begin(), desc.input_files.end(), gold_path()),
            desc.input_files.end());
  std::string error;
  ArchiveOptions opt;
  opt.threads = 1;
  ASSERT_TRUE(write_archive(desc, files, dir, dir + "/scene.pbrta", opt, nullptr, &error)) << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(dir + "/scene.pbrta", 1, &error)) << error;
  EXPECT_EQ(a.header().minor, pbrta::kMinorVersion);
  uint32_t e = fourier_entity(a);
  ASSERT_NE(e, pbrta::kNoIndex);
  pbrta::FourierTableView t;
  ASSERT_TRUE(pbrta::fourier_table_of(a, e, &t, &error)) << error;
  // Header words: 3 nodes, 4 coefficients, 5 maximum order, 6 channels; eta at byte 44.
  const uint32_t n = uint32_t(word_i(raw, 3));
  EXPECT_EQ(n, 58u);
  EXPECT_EQ(t.n_mu, n);
  EXPECT_EQ(t.n_cdf, n * n);
  EXPECT_EQ(t.n_offsets, 2 * n * n);
  EXPECT_EQ(t.n_coeffs, uint32_t(word_i(raw, 4)));
  EXPECT_EQ(t.m_max, word_i(raw, 5));
  EXPECT_EQ(t.channels, word_i(raw, 6));
  EXPECT_EQ(t.eta, word_f(raw, 11));
  // Arrays from word 16: mu[n], cdf[n*n], (offset, length)[n*n], coefficients.
  for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(t.mu[i], word_f(raw, 16 + i)) << i;
  const size_t cdf0 = 16 + n, off0 = cdf0 + n * n, coef0 = off0 + 2 * n * n;
  for (uint32_t i = 0; i < n * n; i += 37) ASSERT_EQ(t.cdf[i], word_f(raw, cdf0 + i)) << i;
  for (uint32_t i = 0; i < 2 * n * n; i += 41) ASSERT_EQ(t.offsets[i], word_i(raw, off0 + i)) << i;
  for (uint32_t i = 0; i < t.n_coeffs; i += 997)
    ASSERT_EQ(t.coeffs[i], word_f(raw, coef0 + i)) << i;
  EXPECT_EQ(t.coeffs[t.n_coeffs - 1], word_f(raw, coef0 + t.n_coeffs - 1));
  EXPECT_TRUE(a.given(e, "bsdfmu"));
}

// Compiles the scene naming a damaged copy of the table; returns the first message.
std::string error_for(const std::string& bytes, const std::string& name) {
  const std::string dir = testing_support::scratch_dir("fourier_bsdf_" + name);
  testing_support::write_file(dir + "/bad.bsdf", bytes);
  const std::string scene =
      testing_support::write_file(dir + "/scene.pbrt", scene_text("bad.bsdf"));
  SourceFiles files;
  Diagnostics diag(&files, nullptr);
  SceneDesc desc;
  EXPECT_FALSE(build_scene(scene, &files, &diag, &desc)) << name;
  if (diag.all().empty()) return "(no message)";
  std::string prefix = scene + ":3:38: error: bsdf file \"" + dir + "/bad.bsdf\" ";
  const std::string& text = diag.all()[0].text;
  EXPECT_EQ(text.compare(0, prefix.size(), prefix), 0) << text;
  return text.size() > prefix.size() ? text.substr(prefix.size()) : text;
}

TEST(FourierBsdf, TruncatedCopiesAreErrorsAtTheFileName) {
  const std::string raw = testing_support::read_file(gold_path());
  ASSERT_EQ(raw.size(), 207354u);
  EXPECT_EQ(error_for(raw.substr(0, 40), "cut40"),
            "is truncated: 40 bytes, shorter than the 64-byte header");
  EXPECT_EQ(error_for(raw.substr(0, 100000), "cut_half"),
            "is truncated: 100000 bytes, but its header (58 nodes, 41502 coefficients, 682 "
            "metadata bytes) needs 207354");
  EXPECT_EQ(error_for(raw.substr(0, raw.size() - 1), "cut1"),
            "is truncated: 207353 bytes, but its header (58 nodes, 41502 coefficients, 682 "
            "metadata bytes) needs 207354");
  EXPECT_EQ(error_for(raw.substr(0, 5), "cut5"),
            "is not a pbrt-v3 BSDF table (no \"SCATFUN\" header)");
  EXPECT_EQ(error_for("", "empty"), "is not a pbrt-v3 BSDF table (no \"SCATFUN\" header)");
}

TEST(FourierBsdf, GarbledCopiesAreErrorsSayingWhatIsWrong) {
  const std::string raw = testing_support::read_file(gold_path());
  ASSERT_EQ(raw.size(), 207354u);
  const uint32_t n = 58;
  const size_t off0 = 16 + n + n * n, coef0 = off0 + 2 * n * n;
  auto edit = [&](auto f) {
    std::string b = raw;
    f(&b);
    return b;
  };
  EXPECT_EQ(error_for(edit([](std::string* b) { (*b)[0] = 'X'; }), "magic"),
            "is not a pbrt-v3 BSDF table (no \"SCATFUN\" header)");
  EXPECT_EQ(error_for(edit([](std::string* b) { (*b)[7] = 2; }), "version"),
            "is a BSDF table of version 2; pbrt-v3 reads version 1");
  EXPECT_EQ(error_for(edit([](std::string* b) { put_word(b, 6, 2); }), "channels"),
            "has 2 channels; pbrt-v3 reads 1 (luminance) or 3 (RGB)");
  EXPECT_EQ(error_for(edit([](std::string* b) { put_word(b, 3, 1 << 20); }), "nodes"),
            "has 1048576 zenith nodes (2 to 1024 are supported)");
  EXPECT_EQ(error_for(edit([](std::string* b) { put_word(b, 4, 0x7FFFFFFF); }), "coeffs"),
            "is truncated: 207354 bytes, but its header (58 nodes, 2147483647 coefficients, 682 "
            "metadata bytes) needs 8589975934");
  EXPECT_EQ(error_for(edit([](std::string* b) { put_word(b, 4, -5); }), "negative"),
            "has a negative count in its header (coefficients -5, maximum order 172, metadata "
            "bytes 682)");
  EXPECT_EQ(error_for(edit([](std::string* b) { put_word(b, 9, 3); }), "parameters"),
            "has 3 parameters; pbrt-v3 reads only unparameterised tables");
  // Node pair 2330 (o 40, i 10: reflection, 13 terms at coefficient 25908) moved past the
  // coefficients, then made longer than the file's maximum.
  ASSERT_EQ(word_i(raw, off0 + 2 * 2330), 25908);
  ASSERT_EQ(word_i(raw, off0 + 2 * 2330 + 1), 13);
  EXPECT_EQ(error_for(edit([&](std::string* b) { put_word(b, off0 + 2 * 2330, 41500); }), "offset"),
            "node pair 2330: series of length 13 at coefficient 41500 lies outside the 41502 "
            "coefficients or exceeds the maximum length 172");
  EXPECT_EQ(
      error_for(edit([&](std::string* b) { put_word(b, off0 + 2 * 2330 + 1, 173); }), "length"),
      "node pair 2330: series of length 173 at coefficient 25908 lies outside the 41502 "
      "coefficients or exceeds the maximum length 172");
  EXPECT_EQ(error_for(edit([&](std::string* b) {
                        put_word(b, coef0 + 100, std::numeric_limits<float>::quiet_NaN());
                      }),
                      "nan"),
            "coefficient 100 is not finite");
  EXPECT_EQ(error_for(edit([&](std::string* b) { put_word(b, 16 + 10, 0.5f); }), "order"),
            "zenith node 11 (" + std::to_string(word_f(raw, 16 + 11)) +
                ") is not in [-1, 1] at or above the previous one");
}

// Compiles the real table and lets `damage` edit the resolved scene before it is written.
template <class Damage>
bool load_damaged(const std::string& name, Damage damage, pbrta::SceneArchive* a,
                  std::string* error, uint16_t minor = pbrta::kMinorVersion) {
  const std::string dir = testing_support::scratch_dir("fourier_archive_" + name);
  const std::string scene =
      testing_support::write_file(dir + "/scene.pbrt", scene_text(gold_path()));
  SourceFiles files;
  Diagnostics diag(&files, nullptr);
  SceneDesc desc;
  EXPECT_TRUE(build_scene(scene, &files, &diag, &desc));
  for (MaterialDesc& m : desc.materials)
    if (m.params.type_name() == "fourier") damage(&m.params);
  ArchiveOptions opt;
  opt.threads = 1;
  EXPECT_TRUE(write_archive(desc, files, dir, dir + "/scene.pbrta", opt, nullptr, error));
  if (minor != pbrta::kMinorVersion) {
    // As another pbrtc wrote it: the header's minor, resealed.
    std::string b = testing_support::read_file(dir + "/scene.pbrta");
    pbrta::Header h;
    std::memcpy(&h, b.data(), sizeof h);
    h.minor = minor;
    h.header_checksum = XXH3_64bits(&h, 56);
    std::memcpy(b.data(), &h, sizeof h);
    testing_support::write_file(dir + "/scene.pbrta", b);
  }
  return a->load(dir + "/scene.pbrta", 1, error);
}

TEST(FourierBsdf, LoadRefusesAnInconsistentTable) {
  pbrta::SceneArchive a;
  std::string error;
  auto ints = [](Entity* m, const char* name) {
    return m->ints.data() + m->values[size_t(m->slot(name))].offset;
  };
  // Node pair 2330's 13 terms moved past the coefficients.
  EXPECT_FALSE(load_damaged(
      "offset", [&](Entity* m) { ints(m, "bsdfoffsets")[2 * 2330] = 41500; }, &a, &error));
  EXPECT_NE(error.find("section 'entities' (#2): entity "), std::string::npos) << error;
  EXPECT_NE(error.find(": fourier table node pair 2330: series of length 13 at coefficient 41500 "
                       "lies outside the 41502 coefficients"),
            std::string::npos)
      << error;
  // The last pair's series starts at the end of the coefficients: any length reads past them.
  EXPECT_FALSE(load_damaged(
      "length", [&](Entity* m) { ints(m, "bsdfoffsets")[2 * 3363 + 1] = 1; }, &a, &error));
  EXPECT_NE(error.find("fourier table node pair 3363: series of length 1 at coefficient 41502"),
            std::string::npos)
      << error;
  EXPECT_FALSE(load_damaged(
      "channels", [&](Entity* m) { ints(m, "bsdfchannels")[0] = 2; }, &a, &error));
  EXPECT_NE(error.find("fourier table has 2 channels (1 or 3 are supported)"), std::string::npos)
      << error;
  EXPECT_FALSE(load_damaged(
      "cdf", [&](Entity* m) { m->values[size_t(m->slot("bsdfcdf"))].count -= 1; }, &a, &error));
  EXPECT_NE(error.find("fourier table has 3363 cdf values for 58 nodes (needs 3364)"),
            std::string::npos)
      << error;
  // Undamaged, it loads.
  EXPECT_TRUE(load_damaged(
      "none", [](Entity*) {}, &a, &error))
      << error;
}

// ARCHIVE.md's minor versions: a newer minor may append parameters to a type. An entity with
// one value more than this reader's schema is damage in this reader's own version, and in a newer
// minor's archive the reader ignores the value it does not know.
TEST(FourierBsdf, ANewerMinorsAppendedParameterIsIgnored) {
  auto appended = [](Entity* m) { m->values.push_back(m->values.back()); };
  pbrta::SceneArchive a;
  std::string error;
  EXPECT_FALSE(load_damaged("long", appended, &a, &error));
  EXPECT_NE(error.find("fourier has 9 parameters, the record 10 (archive version 2." +
                       std::to_string(pbrta::kMinorVersion) + ")"),
            std::string::npos)
      << error;
  ASSERT_TRUE(load_damaged("newer", appended, &a, &error, pbrta::kMinorVersion + 1)) << error;
  const uint32_t e = fourier_entity(a);
  ASSERT_NE(e, pbrta::kNoIndex);
  EXPECT_EQ(a.entities[e].num_values, 10u);
  pbrta::FourierTableView t;
  EXPECT_TRUE(pbrta::fourier_table_of(a, e, &t, &error)) << error;
}

TEST(FourierBsdf, WrittenFileReadsBackToTheSameTable) {
  const std::string raw = testing_support::read_file(gold_path());
  BsdfTable a, b;
  std::string error;
  ASSERT_TRUE(read_bsdf_file(raw, &a, &error)) << error;
  std::string written = write_bsdf_file(a.view());
  // The same bytes but for the metadata, which is not kept (header word 8 is its size).
  EXPECT_EQ(written.size(), raw.size() - 682);
  EXPECT_EQ(written.compare(64, std::string::npos, raw, 64, written.size() - 64), 0);
  ASSERT_TRUE(read_bsdf_file(written, &b, &error)) << error;
  EXPECT_EQ(a.mu, b.mu);
  EXPECT_EQ(a.cdf, b.cdf);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.coeffs, b.coeffs);
  EXPECT_EQ(a.eta, b.eta);
  EXPECT_EQ(a.m_max, b.m_max);
  EXPECT_EQ(a.channels, b.channels);
}

}  // namespace
}  // namespace pbrtc
