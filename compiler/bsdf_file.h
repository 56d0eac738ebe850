// compiler/bsdf_file.h — pbrt-v3's tabulated-BSDF files (.bsdf), read and written.
//
// The fourier material names a binary file of Fourier-series BSDF tables (layerlab's
// "SCATFUN" format, version 1, as pbrt-v3's FourierBSDFTable::Read takes it; all
// little-endian): the 8 bytes "SCATFUN\x01"; int32 flags (1: a BSDF), node count n,
// coefficient count, maximum series length, channel count, basis count (1), metadata byte
// count, parameter count (0), parameter value count (0); float32 eta; 4 reserved 32-bit
// words (layerlab's alpha and unused); then float32 mu[n], float32 cdf[n*n], int32
// (offset, length)[n*n], float32 coefficients[count], then the metadata bytes (ignored, as
// pbrt-v3 ignores them). pbrt-v3 reads only monochromatic (1 channel) or RGB (3) tables with
// one basis and no parameters; so does this reader.
//
// read_bsdf_file() checks every count against the file's size before reading an array, and
// the arrays with format/fourier_table.h's check_fourier_table(), so what it returns is what
// an archive may hold. write_bsdf_file() writes a table back (pbrtc --dump); it reads back to
// the same arrays.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "format/fourier_table.h"

namespace pbrtc {

struct BsdfTable {
  float eta = 1;
  int32_t m_max = 0;
  int32_t channels = 0;
  std::vector<float> mu, cdf, coeffs;
  std::vector<int32_t> offsets;  // (offset, length) per node pair

  pbrta::FourierTableView view() const;
};

// Parses a whole .bsdf file's bytes. False with *error: a sentence saying what
// is wrong ("is truncated: ...", "is not a pbrt-v3 BSDF table ...").
bool read_bsdf_file(std::string_view bytes, BsdfTable* table, std::string* error);

// The bytes of a .bsdf file holding t (no metadata).
std::string write_bsdf_file(const pbrta::FourierTableView& t);

}  // namespace pbrtc
