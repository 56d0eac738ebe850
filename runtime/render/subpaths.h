// runtime/render/subpaths.h — path vertices and the subpath machinery of pbrt-v3's
// bidirectional methods (book 3rd ed., 16.3), shared by bdpt (bdpt.h) and mlt (mlt.h).
//
// Subpaths is one sample's view of the scene: camera_subpath() and light_subpath() are
// pbrt-v3's GenerateCameraSubpath / GenerateLightSubpath (random walks without roulette that
// record forward and reverse area densities at every vertex), connect() is ConnectBDPT: the
// MIS-weighted contribution of joining s light vertices to t camera vertices (s = 0: emission
// found by the camera walk; s = 1: a fresh light sample; t = 1: a fresh lens sample, whose
// raster point replaces *p_raster). Path arrays are written from index 0, and index -1 must
// exist (the walk records the reverse density of the vertex before the first): PathBuffers
// gives such arrays. In participating media the walks scatter at medium vertices (the
// medium's Henyey-Greenstein phase function as their BSDF) and connections carry the media's
// transmittance; every vertex knows the medium it was reached in.
#pragma once

#include <vector>

#include "runtime/light/light_distribution.h"
#include "runtime/material/bsdf.h"
#include "runtime/render/camera.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/visibility.h"
#include "runtime/sampler/sampler.h"

namespace rt {

enum class VertexType : uint8_t { kCamera, kLight, kSurface, kMedium };

// A path vertex. Endpoints keep their point, normal and time in si (the normal is zero where
// the endpoint has no surface: the camera, a point light's sample); surfaces keep the whole hit
// and their BSDF. Densities are per unit area at this vertex (per solid angle for lights at
// infinity), forwards (as the walk that made it sampled it) and in reverse.
struct VertexFields {
  VertexType type = VertexType::kSurface;
  bool delta = false;           // a specular bounce left here
  bool infinite = false;        // light endpoints: infinite or distant light, or an escaped ray
  uint32_t light = kNone;       // light endpoints: the light (kNone for an escaped ray)
  uint32_t area_light = kNone;  // surfaces: the area light they are part of
  uint32_t medium = kNone;      // the medium the vertex was reached in (endpoints: start in)
  float g = 0;                  // medium vertices: the phase function's asymmetry
  Rgb beta;
  float pdf_fwd = 0, pdf_rev = 0;
  SurfaceInteraction si;
};

struct Vertex : VertexFields {
  Bsdf bsdf;

  // Every field back to its default but bsdf, which only surface vertices read and which
  // scattering_at() sets whole: resetting an endpoint or a medium vertex need not write its
  // kilobyte of lobes.
  void reset_except_bsdf() { static_cast<VertexFields&>(*this) = VertexFields{}; }

  Vec3 p() const { return si.p; }
  Vec3 ng() const { return si.n; }
  Vec3 ns() const { return type == VertexType::kSurface ? si.shading.n : si.n; }
  bool on_surface() const { return ng() != Vec3{}; }
};

// Per-thread storage for two paths of up to n vertices each (a vertex holds a whole BSDF:
// too much for the stack at depth), with the extra slot before each.
struct PathBuffers {
  std::vector<Vertex> camera, light;
  void reserve(size_t n) {
    if (camera.size() < n + 1) camera.resize(n + 1);
    if (light.size() < n + 1) light.resize(n + 1);
  }
  Vertex* camera_path() { return camera.data() + 1; }
  Vertex* light_path() { return light.data() + 1; }
};

struct Subpaths {
  const RenderScene& scene;
  const Camera& camera;
  float world_radius;                      // the scene's bounding sphere (lights at infinity)
  const Distribution1D* choice = nullptr;  // how lights are chosen for this sample
  Sampler& sampler;
  RayCounters* counters;

  int camera_subpath(const RayDifferential& ray, int max_depth, Vertex* path) const;
  int light_subpath(int max_depth, float time, Vertex* path) const;
  Rgb connect(const Vertex* light_path, const Vertex* camera_path, int s, int t, Vec2* p_raster,
              float* mis = nullptr) const;

 private:
  bool is_light(const Vertex& v) const;
  bool is_infinite_light(const Vertex& v) const;
  bool is_delta_light(const Vertex& v) const;
  bool connectible(const Vertex& v) const;
  float convert_density(const Vertex& from, float pdf, const Vertex& next) const;
  Rgb f(const Vertex& v, const Vertex& next, TransportMode mode) const;
  Rgb le(const Vertex& v, const Vertex& to) const;
  float infinite_light_density(Vec3 w) const;
  float pdf_light(const Vertex& v, const Vertex& next) const;
  float pdf_light_origin(const Vertex& v, const Vertex& next) const;
  float pdf(const Vertex& v, const Vertex* prev, const Vertex& next) const;
  uint32_t medium_toward(const Vertex& v, Vec3 w) const;
  Rgb visibility(const Vertex& from, const Interaction& to) const;
  Rgb g(const Vertex& v0, const Vertex& v1) const;
  // skip_first: a world quadric the first ray cannot meet (SceneGeometry::intersect).
  int random_walk(RayDifferential ray, uint32_t medium, Rgb beta, float pdf, int max_depth,
                  TransportMode mode, Vertex* path, uint32_t skip_first = kNone) const;
  // A joined end's reverse densities, when connect() found them with its f (joined_end).
  struct JoinedDensities {
    bool qs = false, pt = false;  // which end's pair is known
    float pt_rev = 0, qs_minus_rev = 0, qs_rev = 0, pt_minus_rev = 0;
  };
  // f(v, other, mode). Where v is a surface with a vertex prev before it on its own path, also
  // v's densities towards other and back towards prev (pdf()'s, each way) from the same evaluation
  // of its BSDF, and *known set.
  Rgb end_f(const Vertex& v, const Vertex* prev, const Vertex& other, TransportMode mode,
            bool* known, float* to_other, float* to_prev) const;
  float mis_weight(const Vertex* light_path, const Vertex* camera_path, const Vertex& sampled,
                   int s, int t, const JoinedDensities& known) const;
};

}  // namespace rt
