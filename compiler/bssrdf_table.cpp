// compiler/bssrdf_table.cpp — see bssrdf_table.h. The model is photon beam
// diffusion (Habel, Christensen and Jarosz 2013) as the pbrt book (3rd ed.,
// 15.5) evaluates it: a multiple-scattering term from 100 dipoles along the
// refracted beam and a single-scattering term integrated along it.
#include "compiler/bssrdf_table.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "compiler/medium_presets.h"
#include "format/bssrdf_table.h"

namespace pbrtc {
namespace {

constexpr int kRhoSamples = 100, kRadiusSamples = 64, kBeamSamples = 100;
constexpr double kPi = 3.14159265358979323846;

// Unpolarised Fresnel reflectance of a dielectric boundary; cos_i < 0 means
// the ray arrives from the inside (eta is the inside's index over the outside's).
double fresnel_dielectric(double cos_i, double eta) {
  cos_i = std::clamp(cos_i, -1.0, 1.0);
  double eta_i = 1, eta_t = eta;
  if (cos_i < 0) {
    std::swap(eta_i, eta_t);
    cos_i = -cos_i;
  }
  double sin_t = eta_i / eta_t * std::sqrt(std::max(0.0, 1 - cos_i * cos_i));
  if (sin_t >= 1) return 1;
  double cos_t = std::sqrt(std::max(0.0, 1 - sin_t * sin_t));
  double par = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  double perp = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  return (par * par + perp * perp) / 2;
}

double phase_hg(double cos_theta, double g) {
  double denom = 1 + g * g + 2 * g * cos_theta;
  return (1 - g * g) / (4 * kPi * denom * std::sqrt(denom));
}

// Multiple scattering: dipoles at depths sampled along the refracted beam
// (exponentially, by the reduced extinction), each a real source and its
// mirror image about the extrapolated boundary, with the boundary condition's
// fluence and flux terms (Grosjean's approximation for the diffusion coefficient).
double beam_multiple(double sigma_s, double sigma_a, double g, double eta, double r) {
  const double sigmap_s = sigma_s * (1 - g), sigmap_t = sigma_a + sigmap_s;
  const double rhop = sigmap_s / sigmap_t;
  const double d_g = (2 * sigma_a + sigmap_t) / (3 * sigmap_t * sigmap_t);
  const double sigma_tr = std::sqrt(std::max(0.0, sigma_a / d_g));
  const double fm1 = pbrta::fresnel_moment1(eta), fm2 = pbrta::fresnel_moment2(eta);
  const double ze = -2 * d_g * (1 + 3 * fm2) / (1 - 2 * fm1);
  const double c_phi = 0.25 * (1 - 2 * fm1), c_e = 0.5 * (1 - 3 * fm2);
  double ed = 0;
  for (int i = 0; i < kBeamSamples; ++i) {
    double zr = -std::log(1 - (i + 0.5) / kBeamSamples) / sigmap_t;
    double zv = -zr + 2 * ze;
    double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
    double er = std::exp(-sigma_tr * dr), ev = std::exp(-sigma_tr * dv);
    double phi_d = (er / dr - ev / dv) / (4 * kPi * d_g);
    double ed_n = (zr * (1 + sigma_tr * dr) * er / (dr * dr * dr) -
                   zv * (1 + sigma_tr * dv) * ev / (dv * dv * dv)) /
                  (4 * kPi);
    double e = phi_d * c_phi + ed_n * c_e;
    double kappa = 1 - std::exp(-2 * sigmap_t * (dr + zr));
    ed += kappa * rhop * rhop * e;
  }
  return ed / kBeamSamples;
}

// Single scattering: points along the refracted beam past the critical
// depth, sampled exponentially by the extinction, seen from the exit point.
double beam_single(double sigma_s, double sigma_a, double g, double eta, double r) {
  const double sigma_t = sigma_a + sigma_s, rho = sigma_s / sigma_t;
  const double t_crit = r * std::sqrt(std::max(0.0, eta * eta - 1));
  double ess = 0;
  for (int i = 0; i < kBeamSamples; ++i) {
    double ti = t_crit - std::log(1 - (i + 0.5) / kBeamSamples) / sigma_t;
    double d = std::sqrt(r * r + ti * ti);
    double cos_o = ti / d;
    ess += rho * std::exp(-sigma_t * (d + t_crit)) / (d * d) * phase_hg(cos_o, g) *
           (1 - fresnel_dielectric(-cos_o, eta)) * std::abs(cos_o);
  }
  return ess / kBeamSamples;
}

// The integral of a Catmull-Rom spline through (x, f), and its running
// integral at the nodes (cdf[0] = 0).
double integrate_catmull_rom(const float* x, const float* f, float* cdf, int n) {
  double sum = 0;
  cdf[0] = 0;
  for (int i = 0; i + 1 < n; ++i) {
    double x0 = x[i], x1 = x[i + 1], f0 = f[i], f1 = f[i + 1], w = x1 - x0;
    double d0 = i > 0 ? w * (f1 - f[i - 1]) / (x1 - x[i - 1]) : f1 - f0;
    double d1 = i + 2 < n ? w * (f[i + 2] - f0) / (x[i + 2] - x0) : f1 - f0;
    sum += ((d0 - d1) / 12 + (f0 + f1) / 2) * w;
    cdf[i + 1] = float(sum);
  }
  return sum;
}

void set_floats(Entity* e, std::string_view name, const std::vector<float>& f) {
  Value& v = e->values[size_t(e->slot(name))];
  v.offset = uint32_t(e->floats.size());
  v.count = uint32_t(f.size());
  v.given = true;
  e->floats.insert(e->floats.end(), f.begin(), f.end());
}

}  // namespace

void compute_bssrdf_table(float g, float eta, BssrdfTable* t) {
  t->rho.resize(kRhoSamples);
  t->radius.resize(kRadiusSamples);
  t->profile.assign(size_t(kRhoSamples) * kRadiusSamples, 0.f);
  t->cdf.assign(size_t(kRhoSamples) * kRadiusSamples, 0.f);
  t->rho_eff.resize(kRhoSamples);
  // Radii grow geometrically from 0.0025 (and 0); albedos crowd towards 1,
  // where the profile changes fastest.
  t->radius[0] = 0;
  t->radius[1] = 2.5e-3f;
  for (int j = 2; j < kRadiusSamples; ++j) t->radius[j] = t->radius[j - 1] * 1.2f;
  for (int i = 0; i < kRhoSamples; ++i)
    t->rho[i] = float((1 - std::exp(-8.0 * i / (kRhoSamples - 1))) / (1 - std::exp(-8.0)));
  for (int i = 0; i < kRhoSamples; ++i) {
    float* row = &t->profile[size_t(i) * kRadiusSamples];
    for (int j = 0; j < kRadiusSamples; ++j) {
      double rho = t->rho[i], r = t->radius[j];
      row[j] =
          float(2 * kPi * r *
                (beam_single(rho, 1 - rho, g, eta, r) + beam_multiple(rho, 1 - rho, g, eta, r)));
    }
    t->rho_eff[i] = float(integrate_catmull_rom(
        t->radius.data(), row, &t->cdf[size_t(i) * kRadiusSamples], kRadiusSamples));
  }
}

bool derive_subsurface(Entity* m, Loc name_loc, Diagnostics* diag) {
  if (m->type_name() == "subsurface") {
    const std::string& name = m->get_string("name");
    if (!name.empty()) {
      const MeasuredMedium* mm = find_measured_medium(name);
      if (!mm) {
        diag->error(name_loc, "unknown subsurface preset \"" + name +
                                  "\" (known: " + measured_medium_names() + ")");
        return false;
      }
      for (const char* p : {"sigma_a", "sigma_s"}) {
        Value& v = m->values[size_t(m->slot(p))];
        if (v.given || v.texture != kNone) continue;
        const float* rgb = p[6] == 'a' ? mm->sigma_a : mm->sigma_prime_s;
        for (int c = 0; c < 3; ++c) m->floats[v.offset + c] = rgb[c];
        v.given = true;
      }
      Value& g = m->values[size_t(m->slot("g"))];
      m->floats[g.offset] = 0;
      g.given = true;
    }
  }
  BssrdfTable t;
  compute_bssrdf_table(m->get_float("g"), m->get_float("eta"), &t);
  set_floats(m, "bssrdfrho", t.rho);
  set_floats(m, "bssrdfradius", t.radius);
  set_floats(m, "bssrdfprofile", t.profile);
  set_floats(m, "bssrdfrhoeff", t.rho_eff);
  set_floats(m, "bssrdfcdf", t.cdf);
  return true;
}

}  // namespace pbrtc
