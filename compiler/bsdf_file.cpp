#include "compiler/bsdf_file.h"

#include <cstring>

namespace pbrtc {

namespace {

constexpr char kBsdfMagic[8] = {'S', 'C', 'A', 'T', 'F', 'U', 'N', '\x01'};
constexpr size_t kBsdfHeaderBytes = 64;

int32_t int_at(std::string_view b, size_t offset) {
  uint8_t c[4];
  std::memcpy(c, b.data() + offset, 4);
  return int32_t(uint32_t(c[0]) | uint32_t(c[1]) << 8 | uint32_t(c[2]) << 16 |
                 uint32_t(c[3]) << 24);
}

float float_at(std::string_view b, size_t offset) {
  int32_t bits = int_at(b, offset);
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

void put_int(std::string* out, int32_t v) {
  uint32_t u = uint32_t(v);
  char c[4] = {char(u & 0xFF), char(u >> 8 & 0xFF), char(u >> 16 & 0xFF), char(u >> 24 & 0xFF)};
  out->append(c, 4);
}

void put_float(std::string* out, float f) {
  int32_t bits;
  std::memcpy(&bits, &f, 4);
  put_int(out, bits);
}

}  // namespace

pbrta::FourierTableView BsdfTable::view() const {
  pbrta::FourierTableView v;
  v.eta = eta;
  v.m_max = m_max;
  v.channels = channels;
  v.mu = mu.data();
  v.cdf = cdf.data();
  v.offsets = offsets.data();
  v.coeffs = coeffs.data();
  v.n_mu = uint32_t(mu.size());
  v.n_cdf = uint32_t(cdf.size());
  v.n_offsets = uint32_t(offsets.size());
  v.n_coeffs = uint32_t(coeffs.size());
  return v;
}

bool read_bsdf_file(std::string_view b, BsdfTable* t, std::string* error) {
  if (b.size() < 8 || std::memcmp(b.data(), kBsdfMagic, 7) != 0) {
    *error = "is not a pbrt-v3 BSDF table (no \"SCATFUN\" header)";
    return false;
  }
  if (b[7] != kBsdfMagic[7]) {
    *error = "is a BSDF table of version " + std::to_string(int(uint8_t(b[7]))) +
             "; pbrt-v3 reads version 1";
    return false;
  }
  if (b.size() < kBsdfHeaderBytes) {
    *error = "is truncated: " + std::to_string(b.size()) + " bytes, shorter than the " +
             std::to_string(kBsdfHeaderBytes) + "-byte header";
    return false;
  }
  const int32_t flags = int_at(b, 8), n_mu = int_at(b, 12), n_coeffs = int_at(b, 16);
  const int32_t m_max = int_at(b, 20), channels = int_at(b, 24), bases = int_at(b, 28);
  const int32_t metadata = int_at(b, 32), parameters = int_at(b, 36),
                parameter_values = int_at(b, 40);
  auto fail = [&](const std::string& what) {
    *error = what;
    return false;
  };
  if (flags != 1) return fail("has flags " + std::to_string(flags) + "; pbrt-v3 reads 1 (a BSDF)");
  if (bases != 1)
    return fail("has " + std::to_string(bases) +
                " bases; pbrt-v3 reads only tables with one (no textured parameters)");
  if (parameters != 0 || parameter_values != 0)
    return fail("has " + std::to_string(parameters) +
                " parameters; pbrt-v3 reads only unparameterised tables");
  if (channels != 1 && channels != 3)
    return fail("has " + std::to_string(channels) +
                " channels; pbrt-v3 reads 1 (luminance) or 3 (RGB)");
  if (n_mu < 2 || uint32_t(n_mu) > pbrta::kMaxFourierNodes)
    return fail("has " + std::to_string(n_mu) + " zenith nodes (2 to " +
                std::to_string(pbrta::kMaxFourierNodes) + " are supported)");
  if (n_coeffs < 0 || m_max < 0 || metadata < 0)
    return fail("has a negative count in its header (coefficients " + std::to_string(n_coeffs) +
                ", maximum order " + std::to_string(m_max) + ", metadata bytes " +
                std::to_string(metadata) + ")");
  // Every array's size follows from the header; the file must hold them all.
  const uint64_t n = uint64_t(n_mu), nn = n * n;
  const uint64_t data_bytes = 4 * (n + nn + 2 * nn + uint64_t(n_coeffs));
  const uint64_t needed = kBsdfHeaderBytes + data_bytes + uint64_t(metadata);
  if (b.size() < needed)
    return fail("is truncated: " + std::to_string(b.size()) + " bytes, but its header (" +
                std::to_string(n_mu) + " nodes, " + std::to_string(n_coeffs) + " coefficients, " +
                std::to_string(metadata) + " metadata bytes) needs " + std::to_string(needed));
  t->eta = float_at(b, 44);
  t->m_max = m_max;
  t->channels = channels;
  size_t at = kBsdfHeaderBytes;
  auto floats = [&](std::vector<float>* out, uint64_t count) {
    out->resize(size_t(count));
    for (uint64_t i = 0; i < count; ++i, at += 4) (*out)[size_t(i)] = float_at(b, at);
  };
  floats(&t->mu, n);
  floats(&t->cdf, nn);
  t->offsets.resize(size_t(2 * nn));
  for (uint64_t i = 0; i < 2 * nn; ++i, at += 4) t->offsets[size_t(i)] = int_at(b, at);
  floats(&t->coeffs, uint64_t(n_coeffs));
  return pbrta::check_fourier_table(t->view(), error);
}

std::string write_bsdf_file(const pbrta::FourierTableView& t) {
  std::string out(kBsdfMagic, 8);
  for (int32_t v : {1, int32_t(t.n_mu), int32_t(t.n_coeffs), t.m_max, t.channels, 1, 0, 0, 0})
    put_int(&out, v);
  put_float(&out, t.eta);
  for (int i = 0; i < 4; ++i) put_int(&out, 0);
  for (uint32_t i = 0; i < t.n_mu; ++i) put_float(&out, t.mu[i]);
  for (uint32_t i = 0; i < t.n_cdf; ++i) put_float(&out, t.cdf[i]);
  for (uint32_t i = 0; i < t.n_offsets; ++i) put_int(&out, t.offsets[i]);
  for (uint32_t i = 0; i < t.n_coeffs; ++i) put_float(&out, t.coeffs[i]);
  return out;
}

}  // namespace pbrtc
