#include "format/fourier_table.h"

#include <cmath>

#include "format/scene_archive.h"

namespace pbrta {

bool check_fourier_table(const FourierTableView& t, std::string* error) {
  auto fail = [&](const std::string& what) {
    *error = what;
    return false;
  };
  const uint64_t n = t.n_mu, nn = n * n;
  if (n < 2 || n > kMaxFourierNodes)
    return fail("has " + std::to_string(n) + " zenith nodes (needs 2 to " +
                std::to_string(kMaxFourierNodes) + ")");
  if (t.n_cdf != nn)
    return fail("has " + std::to_string(t.n_cdf) + " cdf values for " + std::to_string(n) +
                " nodes (needs " + std::to_string(nn) + ")");
  if (t.n_offsets != 2 * nn)
    return fail("has " + std::to_string(t.n_offsets) + " offset/length values for " +
                std::to_string(n) + " nodes (needs " + std::to_string(2 * nn) + ")");
  if (t.channels != 1 && t.channels != 3)
    return fail("has " + std::to_string(t.channels) + " channels (1 or 3 are supported)");
  if (t.m_max < 0 || t.m_max > kMaxFourierOrder)
    return fail("has maximum series length " + std::to_string(t.m_max) + " (at most " +
                std::to_string(kMaxFourierOrder) + ")");
  if (!(std::isfinite(t.eta) && t.eta > 0))
    return fail("has index of refraction " + std::to_string(t.eta));
  if (!t.mu || !t.cdf || !t.offsets || (t.n_coeffs && !t.coeffs)) return fail("has no data");
  // Nodes may repeat (layerlab's tables have 0 twice, one per hemisphere): an interval of zero
  // width is never the one a lookup lands in, except the last one, at the last node.
  for (uint32_t i = 0; i < n; ++i) {
    float m = t.mu[i];
    if (!(m >= -1 && m <= 1) || (i > 0 && !(m >= t.mu[i - 1])))
      return fail("zenith node " + std::to_string(i) + " (" + std::to_string(m) +
                  ") is not in [-1, 1] at or above the previous one");
  }
  if (!(t.mu[n - 1] > t.mu[n - 2])) return fail("last two zenith nodes are equal");
  for (uint64_t i = 0; i < nn; ++i)
    if (!std::isfinite(t.cdf[i])) return fail("cdf value " + std::to_string(i) + " is not finite");
  for (uint64_t i = 0; i < nn; ++i) {
    int64_t offset = t.offsets[2 * i], length = t.offsets[2 * i + 1];
    if (offset < 0 || length < 0 || length > t.m_max ||
        offset + length * t.channels > int64_t(t.n_coeffs))
      return fail("node pair " + std::to_string(i) + ": series of length " +
                  std::to_string(length) + " at coefficient " + std::to_string(offset) +
                  " lies outside the " + std::to_string(t.n_coeffs) +
                  " coefficients or exceeds the maximum length " + std::to_string(t.m_max));
  }
  for (uint32_t i = 0; i < t.n_coeffs; ++i)
    if (!std::isfinite(t.coeffs[i]))
      return fail("coefficient " + std::to_string(i) + " is not finite");
  return true;
}

bool fourier_table_of(const SceneArchive& a, uint32_t entity, FourierTableView* t,
                      std::string* error) {
  if (entity >= a.entities.size || a.entities[entity].category != uint8_t(Category::kMaterial) ||
      a.type_name(entity) != "fourier") {
    *error = "entity " + std::to_string(entity) + " is not a fourier material";
    return false;
  }
  const ValueRecord* eta = a.value(entity, "bsdfeta");
  const ValueRecord* m_max = a.value(entity, "bsdfmmax");
  const ValueRecord* channels = a.value(entity, "bsdfchannels");
  const ValueRecord* mu = a.value(entity, "bsdfmu");
  const ValueRecord* cdf = a.value(entity, "bsdfcdf");
  const ValueRecord* offsets = a.value(entity, "bsdfoffsets");
  const ValueRecord* coeffs = a.value(entity, "bsdfcoeffs");
  if (!eta || !m_max || !channels || !mu || !cdf || !offsets || !coeffs || !eta->count ||
      !m_max->count || !channels->count || !mu->count) {
    *error = "the archive holds no table read from \"bsdffile\"";
    return false;
  }
  t->eta = a.floats(*eta)[0];
  t->m_max = int32_t(a.words[m_max->offset]);
  t->channels = int32_t(a.words[channels->offset]);
  t->mu = a.floats(*mu);
  t->n_mu = mu->count;
  t->cdf = a.floats(*cdf);
  t->n_cdf = cdf->count;
  t->offsets = reinterpret_cast<const int32_t*>(a.words.data + offsets->offset);
  t->n_offsets = offsets->count;
  t->coeffs = a.floats(*coeffs);
  t->n_coeffs = coeffs->count;
  return true;
}

}  // namespace pbrta
