// runtime/material/bssrdf.cpp — see bssrdf.h.
#include "runtime/material/bssrdf.h"

#include <algorithm>
#include <cmath>

#include "runtime/material/catmull_rom.h"

namespace rt {
namespace {

// Channel ch's profile at optical radius r_optical: the table interpolated
// over albedo and radius, divided by the 2 pi r the table holds it times.
// *rho_eff (optional) gets the interpolated total albedo. 0 off the table.
float profile_at(const BssrdfTable& t, float rho, float r_optical, float* rho_eff) {
  int rho_offset, radius_offset;
  float rho_w[4], radius_w[4];
  if (!catmull_rom_weights(t.n_rho, t.rho, rho, &rho_offset, rho_w) ||
      !catmull_rom_weights(t.n_radius, t.radius, r_optical, &radius_offset, radius_w))
    return 0;
  float sr = 0, eff = 0;
  for (int i = 0; i < 4; ++i) {
    if (rho_w[i] == 0) continue;
    eff += t.rho_eff[rho_offset + i] * rho_w[i];
    for (int j = 0; j < 4; ++j)
      if (radius_w[j] != 0)
        sr += rho_w[i] * radius_w[j] * t.profile[(rho_offset + i) * t.n_radius + radius_offset + j];
  }
  if (rho_eff) *rho_eff = eff;
  if (r_optical != 0) sr /= 2 * kPi * r_optical;
  return sr;
}

}  // namespace

void Bssrdf::init(const BssrdfTable* t, Rgb sigma_a, Rgb sigma_s, float eta_, Vec3 p_, Vec3 ns_,
                  Vec3 dpdu, uint32_t material_) {
  table = t;
  sigma_t = sigma_a + sigma_s;
  for (int c = 0; c < 3; ++c) rho[c] = sigma_t[c] != 0 ? sigma_s[c] / sigma_t[c] : 0;
  eta = eta_;
  p = p_;
  ns = ns_;
  ss = normalize(dpdu);
  ts = cross(ns, ss);
  material = material_;
}

void Bssrdf::init_disney(Rgb r, Rgb d, float eta_, Vec3 p_, Vec3 ns_, Vec3 dpdu,
                         uint32_t material_) {
  init(nullptr, Rgb(), Rgb(), eta_, p_, ns_, dpdu, material_);
  disney_r = r;
  disney_d = d;
}

Rgb Bssrdf::sr(float r) const {
  Rgb out;
  if (!table) {
    r = std::max(r, 1e-6f);  // the profile's 1/r singularity
    for (int c = 0; c < 3; ++c) {
      float d = disney_d[c];
      if (d > 0)
        out[c] = disney_r[c] * (std::exp(-r / d) + std::exp(-r / (3 * d))) / (8 * kPi * d * r);
    }
    return out;
  }
  for (int c = 0; c < 3; ++c)
    out[c] = std::max(
        0.f, profile_at(*table, rho[c], r * sigma_t[c], nullptr) * sigma_t[c] * sigma_t[c]);
  return out;
}

float Bssrdf::sample_sr(int ch, float u) const {
  if (!table) {
    // A quarter of the samples from the short exponential, the rest from the long one.
    const float d = disney_d[ch];
    if (u < .25f) return d * std::log(1 / (1 - std::min(u * 4, kOneMinusEpsilon)));
    return 3 * d * std::log(1 / (1 - std::min((u - .25f) / .75f, kOneMinusEpsilon)));
  }
  if (sigma_t[ch] == 0) return -1;
  const BssrdfTable& t = *table;
  float pdf;
  return sample_catmull_rom_2d(t.n_rho, t.n_radius, t.rho, t.radius, t.profile, t.cdf, rho[ch], u,
                               nullptr, &pdf) /
         sigma_t[ch];
}

float Bssrdf::pdf_sr(int ch, float r) const {
  if (!table) {
    const float d = disney_d[ch];
    if (!(d > 0)) return 0;
    r = std::max(r, 1e-6f);
    return .25f * std::exp(-r / d) / (2 * kPi * d * r) +
           .75f * std::exp(-r / (3 * d)) / (6 * kPi * d * r);
  }
  float rho_eff = 0;
  float sr = profile_at(*table, rho[ch], r * sigma_t[ch], &rho_eff);
  if (!(rho_eff > 0)) return 0;
  return std::max(0.f, sr * sigma_t[ch] * sigma_t[ch] / rho_eff);
}

bool Bssrdf::probe(float u1, Vec2 u2, Vec3* start, Vec3* end, float* u_rest) const {
  Vec3 vx, vy, vz;
  if (u1 < .5f) {
    vx = ss;
    vy = ts;
    vz = ns;
    u1 *= 2;
  } else if (u1 < .75f) {
    vx = ts;
    vy = ns;
    vz = ss;
    u1 = (u1 - .5f) * 4;
  } else {
    vx = ns;
    vy = ss;
    vz = ts;
    u1 = (u1 - .75f) * 4;
  }
  const int ch = std::clamp(int(u1 * 3), 0, 2);
  *u_rest = std::min(u1 * 3 - float(ch), kOneMinusEpsilon);
  const float r = sample_sr(ch, u2.x);
  if (r < 0) return false;
  const float phi = 2 * kPi * u2.y;
  const float r_max = sample_sr(ch, 0.999f);
  if (r >= r_max) return false;
  const float l = 2 * std::sqrt(r_max * r_max - r * r);
  *start = p + (vx * std::cos(phi) + vy * std::sin(phi)) * r - vz * (l / 2);
  *end = *start + vz * l;
  return true;
}

float Bssrdf::pdf_sp(Vec3 pi, Vec3 n) const {
  const Vec3 d = p - pi;
  const Vec3 dl{dot(ss, d), dot(ts, d), dot(ns, d)};
  const Vec3 nl{dot(ss, n), dot(ts, n), dot(ns, n)};
  const float r_proj[3] = {std::sqrt(dl.y * dl.y + dl.z * dl.z),
                           std::sqrt(dl.z * dl.z + dl.x * dl.x),
                           std::sqrt(dl.x * dl.x + dl.y * dl.y)};
  const float axis_prob[3] = {.25f, .25f, .5f};
  float pdf = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int ch = 0; ch < 3; ++ch)
      pdf += pdf_sr(ch, r_proj[axis]) * std::fabs(nl[axis]) * axis_prob[axis] / 3;
  return pdf;
}

void subsurface_from_diffuse(const BssrdfTable& t, Rgb kd, Rgb mfp, Rgb* sigma_a, Rgb* sigma_s) {
  for (int c = 0; c < 3; ++c) {
    float rho = invert_catmull_rom(t.n_rho, t.rho, t.rho_eff, kd[c]);
    (*sigma_s)[c] = rho / mfp[c];
    (*sigma_a)[c] = (1 - rho) / mfp[c];
  }
}

}  // namespace rt
