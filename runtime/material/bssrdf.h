// runtime/material/bssrdf.h — pbrt-v3's tabulated BSSRDF (book 3rd ed., 11.4 and 15.5).
//
// Light entering a subsurface material leaves it elsewhere: the BSSRDF at the
// entry point po is separable into a radial profile Sp(pi) = Sr(|po - pi|),
// read from the material's photon-beam-diffusion table (format/bssrdf_table.h)
// by albedo and optical radius (or, for the disney material, Burley's
// analytic profile), and the exit lobe (make_bssrdf_exit, bxdf.h).
// Sampling an exit point: probe() picks a projection axis of po's shading
// frame (the normal with probability 1/2, the tangents 1/4 each), a colour
// channel and a radius from that channel's profile, and returns the chord of
// the sphere of the profile's 99.9% radius along the axis; the caller
// intersects it with the scene, keeps the hits on the same material, and
// picks one uniformly. pdf_sp() is the density of that whole procedure at a
// hit (all axes and channels), per unit area.
#pragma once

#include <cstdint>

#include "runtime/core/math.h"
#include "runtime/core/rgb.h"
#include "runtime/core/vec.h"

namespace rt {

struct BssrdfTable {
  int n_rho = 0, n_radius = 0;
  const float* rho = nullptr;
  const float* radius = nullptr;
  const float* profile = nullptr;
  const float* rho_eff = nullptr;
  const float* cdf = nullptr;
};

struct Bssrdf {
  const BssrdfTable* table = nullptr;  // null: the disney profile
  Rgb sigma_t, rho;                    // tabulated: extinction and albedo, per channel
  Rgb disney_r, disney_d;              // disney: the profile's albedo and scatter distance
  float eta = 1;
  Vec3 p;           // the entry point po
  Vec3 ns, ss, ts;  // its shading frame
  uint32_t material = kNone;

  // sigma_a and sigma_s at po; the frame from the shading normal and dp/du.
  void init(const BssrdfTable* t, Rgb sigma_a, Rgb sigma_s, float eta, Vec3 p, Vec3 ns, Vec3 dpdu,
            uint32_t material);
  // pbrt-v3's DisneyBSSRDF: Burley's normalised diffusion, two exponentials in r of
  // scales d and 3d (Burley 2015, "Extending the Disney BRDF to a BSDF with Integrated
  // Subsurface Scattering"), albedo r.
  void init_disney(Rgb r, Rgb d, float eta, Vec3 p, Vec3 ns, Vec3 dpdu, uint32_t material);
  Rgb sr(float r) const;
  // A radius from channel ch's profile; negative when the channel does not scatter.
  float sample_sr(int ch, float u) const;
  float pdf_sr(int ch, float r) const;
  // u1 picks the axis and the channel, u2 the radius and the angle. False when no chord.
  // *u_rest: what is left of u1, uniform in [0, 1), for picking among the chord's hits.
  bool probe(float u1, Vec2 u2, Vec3* start, Vec3* end, float* u_rest) const;
  float pdf_sp(Vec3 pi, Vec3 n_pi) const;
};

// pbrt-v3's SubsurfaceFromDiffuse: the coefficients whose multiple-scattering
// albedo (the table's rho_eff) is kd, with mean free path mfp, per channel.
void subsurface_from_diffuse(const BssrdfTable& t, Rgb kd, Rgb mfp, Rgb* sigma_a, Rgb* sigma_s);

}  // namespace rt
