// format/bssrdf_table.cpp — see bssrdf_table.h.
#include "format/bssrdf_table.h"

#include <cmath>

#include "format/scene_archive.h"

namespace pbrta {
namespace {

bool increasing(const float* x, uint32_t n, float lo, float hi, const char* what,
                std::string* error) {
  for (uint32_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i]) || x[i] < lo || x[i] > hi || (i > 0 && !(x[i] > x[i - 1]))) {
      *error =
          std::string(what) + " sample " + std::to_string(i) + " is out of range or not increasing";
      return false;
    }
  }
  return true;
}

}  // namespace

// Polynomial fits of d'Eon and Irving, "A Quantized-Diffusion Model for
// Rendering Translucent Materials" (SIGGRAPH 2011), the coefficients pbrt-v3 uses.
double fresnel_moment1(double eta) {
  double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
  if (eta < 1)
    return 0.45966 - 1.73965 * eta + 3.37668 * e2 - 3.904945 * e3 + 2.49277 * e4 - 0.68441 * e5;
  return -4.61686 + 11.1136 * eta - 10.4646 * e2 + 5.11455 * e3 - 1.27198 * e4 + 0.12746 * e5;
}

double fresnel_moment2(double eta) {
  double e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
  if (eta < 1)
    return 0.27614 - 0.87350 * eta + 1.12077 * e2 - 0.65095 * e3 + 0.07883 * e4 + 0.04860 * e5;
  double r = 1 / eta, r2 = r * r, r3 = r2 * r;
  return -547.033 + 45.3087 * r3 - 218.725 * r2 + 458.843 * r + 404.557 * eta - 189.519 * e2 +
         54.9327 * e3 - 9.00603 * e4 + 0.63942 * e5;
}

bool check_bssrdf_table(const BssrdfTableView& t, std::string* error) {
  if (t.n_rho < 4 || t.n_radius < 4 || t.n_rho > kMaxBssrdfSamples ||
      t.n_radius > kMaxBssrdfSamples) {
    *error = "has " + std::to_string(t.n_rho) + " albedo and " + std::to_string(t.n_radius) +
             " radius samples (4 to " + std::to_string(kMaxBssrdfSamples) + " each)";
    return false;
  }
  const uint64_t cells = uint64_t(t.n_rho) * t.n_radius;
  if (t.n_profile != cells || t.n_cdf != cells || t.n_rho_eff != t.n_rho) {
    *error = "array sizes disagree: profile " + std::to_string(t.n_profile) + ", cdf " +
             std::to_string(t.n_cdf) + ", rhoeff " + std::to_string(t.n_rho_eff) + " for " +
             std::to_string(t.n_rho) + " x " + std::to_string(t.n_radius) + " samples";
    return false;
  }
  if (!increasing(t.rho, t.n_rho, 0, 1, "albedo", error) ||
      !increasing(t.radius, t.n_radius, 0, INFINITY, "radius", error))
    return false;
  if (t.radius[0] != 0) {
    *error = "the first radius sample is not 0";
    return false;
  }
  for (uint64_t k = 0; k < cells; ++k)
    if (!(t.profile[k] >= 0) || !std::isfinite(t.profile[k]) || !std::isfinite(t.cdf[k])) {
      *error = "profile or cdf entry " + std::to_string(k) + " is negative or not finite";
      return false;
    }
  for (uint32_t i = 0; i < t.n_rho; ++i)
    if (!(t.rho_eff[i] >= 0) || !std::isfinite(t.rho_eff[i])) {
      *error = "rhoeff entry " + std::to_string(i) + " is negative or not finite";
      return false;
    }
  return true;
}

bool bssrdf_table_of(const SceneArchive& a, uint32_t entity, BssrdfTableView* t,
                     std::string* error) {
  const ValueRecord* v[5] = {a.value(entity, "bssrdfrho"), a.value(entity, "bssrdfradius"),
                             a.value(entity, "bssrdfprofile"), a.value(entity, "bssrdfrhoeff"),
                             a.value(entity, "bssrdfcdf")};
  for (const ValueRecord* r : v)
    if (!r || r->count == 0) {
      *error = "the archive holds no BSSRDF table for this material";
      return false;
    }
  t->rho = a.floats(*v[0]);
  t->n_rho = v[0]->count;
  t->radius = a.floats(*v[1]);
  t->n_radius = v[1]->count;
  t->profile = a.floats(*v[2]);
  t->n_profile = v[2]->count;
  t->rho_eff = a.floats(*v[3]);
  t->n_rho_eff = v[3]->count;
  t->cdf = a.floats(*v[4]);
  t->n_cdf = v[4]->count;
  return true;
}

}  // namespace pbrta
