// runtime/render/sppm.h — pbrt-v3's stochastic progressive photon mapping
// integrator, "sppm" (book 3rd ed., 16.2; Hachisuka and Jensen 2009).
//
// render_sppm() renders the whole image itself (it is not a per-camera-sample
// integrator). Each iteration:
//   1. Camera pass: one camera ray per pixel of the cropped film, from a Halton
//      sampler of `iterations` samples per pixel (sample number = iteration,
//      differentials scaled by 1/sqrt(iterations)). The path follows specular
//      and glossy bounces (BSDF sampling, Russian roulette below luminance
//      0.25), collecting emission where the previous bounce was specular (or
//      at the first hit), infinite-light radiance where it escapes, and one
//      uniformly chosen light sample at every surface; it stops at the first
//      surface with a diffuse lobe (or a glossy one at the last depth), which
//      becomes the pixel's visible point (position, direction, BSDF, path weight).
//   2. The visible points, each with its pixel's current radius, are filed in
//      a hashed grid (sppm_grid.h).
//   3. Photon pass: `photons_per_iteration` photons leave lights chosen by
//      power (LightSet::sample_le). At every surface after the first, the
//      photon adds beta * f(visible point) to each visible point within its
//      radius (and counts itself, f zero or not); it continues by sampling the
//      importance-transport BSDF, with Russian roulette by the ratio of path
//      luminance after and before the bounce. Photon i of iteration k uses
//      the Halton point k * photons_per_iteration + i, one dimension per number
//      drawn (radical inverses in successive primes), as pbrt-v3 does.
//   4. Update: with M photons found, N += 2/3 M, the radius shrinks by
//      sqrt(N_new / (N + M)) and the accumulated flux tau is rescaled to it.
// The image is written with Film::set_pixel (no reconstruction filter, as
// pbrt-v3 writes it): Ld / iterations + tau / (Np pi r^2), Np the photons
// traced in all.
//
// Seeds: seed 0 draws pbrt-v3's sequences exactly (its Halton camera samples,
// unscrambled radical inverses for photons); another seed scrambles both, so
// renders with different seeds are independent estimates.
//
// Differences from pbrt-v3, all deliberate: a camera sample or photon deposit
// with non-finite values is dropped and counted (pbrt-v3 would keep a NaN
// pixel); a visible point is filed once per grid bucket (see sppm_grid.h);
// photon dimensions past the 1000th prime fall back to hashed uniform values
// (pbrt-v3 stops there). Participating media are ignored, as in pbrt-v3.
// Memory: one BSDF (about 1 KB) per pixel for the visible points.
//
// Threads: the passes run in parallel with oneTBB; the flux sums are atomic,
// so results depend on the thread count only through float summation order.
#pragma once

#include <cstdint>

#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/renderer.h"

namespace rt {

struct SppmSettings {
  int iterations = 64;                 // camera passes, photon passes
  int64_t photons_per_iteration = -1;  // <= 0: one per pixel of the cropped film
  float radius = 1;                    // initial search radius (world units)
  int max_depth = 5;
  uint64_t seed = 0;
};

// The scene's sppm settings; spp_override > 0 replaces the iteration count (pbrt-v3's --spp,
// as the reference renders used it).
SppmSettings sppm_settings(const IntegratorSettings& settings, int spp_override, uint64_t seed);

// Photons traced per iteration on this film.
int64_t sppm_photons_per_iteration(const SppmSettings& settings, const Film& film);

// Renders into *film (every pixel of the crop set with set_pixel). RenderStats::samples counts
// camera passes (pixels x iterations); options.differential_spp > 0 replaces the iteration
// count in the differential scale.
RenderStats render_sppm(const RenderScene& scene, const Camera& camera, Film* film,
                        const SppmSettings& settings, const RenderOptions& options);

}  // namespace rt
