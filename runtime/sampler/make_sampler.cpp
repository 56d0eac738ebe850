// Building the scene's sampler entity, with the --spp override applied as the
// pbrt-v3 reference renders did (/work/shared/refs/README.md).
#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/sampler/sampler.h"
#include "runtime/sampler/sampler_kinds.h"

namespace rt {
namespace {

bool fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

// N = xsamples * ysamples with ysamples the largest divisor of N not above sqrt(N).
void split_stratified(int n, int* x, int* y) {
  int best = 1;
  for (int d = 1; int64_t(d) * d <= n; ++d)
    if (n % d == 0) best = d;
  *y = best;
  *x = n / best;
}

}  // namespace

std::unique_ptr<Sampler> make_sampler(const pbrta::SceneArchive& archive, int spp_override,
                                      uint64_t seed, const Bounds2i& sample_bounds,
                                      std::string* error, std::string_view type_override) {
  const uint32_t entity = archive.scene().sampler;
  const std::string type(type_override.empty() ? archive.type_name(entity) : type_override);
  const std::string where = archive.where(entity);
  auto count = [&](int64_t* spp) {
    *spp = spp_override > 0 ? spp_override : archive.get_int(entity, "pixelsamples", 16);
    if (*spp <= 0)
      return fail(error, type + " sampler: pixelsamples must be positive (" + where + ")");
    return true;
  };
  int64_t spp = 0;
  if (type == "halton") {
    if (!count(&spp)) return nullptr;
    return make_halton_sampler(spp, seed, sample_bounds,
                               archive.get_int(entity, "samplepixelcenter", 0) != 0);
  }
  if (type == "sobol") {
    if (!count(&spp)) return nullptr;
    return make_sobol_sampler(round_up_pow2(uint32_t(spp)), seed, sample_bounds);
  }
  if (type == "02sequence" || type == "lowdiscrepancy") {
    if (!count(&spp)) return nullptr;
    return make_zero_two_sampler(round_up_pow2(uint32_t(spp)),
                                 archive.get_int(entity, "dimensions", 4), seed);
  }
  if (type == "maxmindist") {
    if (!count(&spp)) return nullptr;
    // pbrt-v3 has matrices up to 2^16 samples and rounds larger counts down.
    int64_t n =
        std::min<int64_t>(round_up_pow2(uint32_t(std::min<int64_t>(spp, 1 << 16))), 1 << 16);
    return make_maxmindist_sampler(n, archive.get_int(entity, "dimensions", 4), seed);
  }
  if (type == "random") {
    if (!count(&spp)) return nullptr;
    return make_random_sampler(spp, seed);
  }
  if (type == "stratified") {
    int x = archive.get_int(entity, "xsamples", 4), y = archive.get_int(entity, "ysamples", 4);
    if (spp_override > 0) split_stratified(spp_override, &x, &y);
    if (x <= 0 || y <= 0) {
      fail(error, "stratified sampler: xsamples and ysamples must be positive (" + where + ")");
      return nullptr;
    }
    return make_stratified_sampler(x, y, archive.get_int(entity, "jitter", 1) != 0,
                                   archive.get_int(entity, "dimensions", 4), seed);
  }
  fail(error, "not supported yet: " + type + " sampler (" + where + ")");
  return nullptr;
}

}  // namespace rt
