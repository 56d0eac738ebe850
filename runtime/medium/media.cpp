// runtime/medium/media.cpp — see media.h. The algorithms are the pbrt book's
// (3rd ed., 15.2: homogeneous sampling, delta tracking, ratio tracking).
#include "runtime/medium/media.h"

#include <cfloat>
#include <cmath>

#include "runtime/core/math.h"

namespace rt {
namespace {

// Samples per majorant cell side: a cloud's empty border and thin fringes
// get cells of their own, while the table stays a small fraction of the grid.
constexpr int kMajorantCell = 8;

Rgb rgb_param(const pbrta::SceneArchive& a, uint32_t e, std::string_view name) {
  const pbrta::ValueRecord* v = a.value(e, name);
  if (!v || v->count == 0) return Rgb();
  const float* f = a.floats(*v);
  return {f[0], f[1], f[2]};
}

// The part of the ray o + t d with t in (t0, t1) inside the unit cube; false if none.
bool clip_unit_cube(Vec3 o, Vec3 d, float* t0, float* t1) {
  for (int a = 0; a < 3; ++a) {
    float inv = 1 / d[a];
    float tn = (0 - o[a]) * inv, tf = (1 - o[a]) * inv;
    if (tn > tf) std::swap(tn, tf);
    tf *= 1 + 2 * gamma_bound(3);            // the pbrt book's conservative slab bound
    if (std::isnan(tn) || std::isnan(tf)) {  // d[a] == 0 and o on a face
      if (o[a] < 0 || o[a] > 1) return false;
      continue;
    }
    *t0 = std::max(*t0, tn);
    *t1 = std::min(*t1, tf);
    if (*t0 > *t1) return false;
  }
  return true;
}

// The ray in grid space with t in world distance: false if it misses the grid.
struct GridRay {
  Vec3 o, d;    // grid space
  Vec3 wo, wd;  // world origin and unit direction
  float t0 = 0, t1 = 0;
};

bool grid_ray(const Medium& m, const Ray& ray, GridRay* g) {
  float len = length(ray.d);
  if (!(len > 0)) return false;
  g->wo = ray.o;
  g->wd = ray.d / len;
  g->o = m.grid_from_world.point(ray.o);
  g->d = m.grid_from_world.vector(g->wd);
  g->t0 = 0;
  g->t1 = std::isinf(ray.tmax) ? kInfinity : ray.tmax * len;
  return clip_unit_cube(g->o, g->d, &g->t0, &g->t1);
}

// Tentative collisions along g, drawn cell by cell at each majorant cell's
// rate: collide(t, density / majorant) at each; it returns true to stop.
template <typename Collide>
void track(const Medium& m, const GridRay& g, Sampler& sampler, Collide&& collide) {
  m.majorants.walk(g.o, g.d, g.t0, g.t1, [&](float t0, float t1, float majorant) {
    const float inv = 1 / (majorant * m.grid_sigma_t);
    for (float t = t0;;) {
      t -= std::log(1 - sampler.get_1d()) * inv;
      if (t >= t1) return false;
      if (collide(t, m.density_at(g.o + g.d * t) / majorant)) return true;
    }
  });
}

}  // namespace

float Medium::density_at(Vec3 p) const {
  float x = p.x * float(nx) - 0.5f, y = p.y * float(ny) - 0.5f, z = p.z * float(nz) - 0.5f;
  // Inside the grid's cells (every eight corners there) the floors come from integer
  // conversions and the corners from one index: SSE2 has no floor, and GCC emulates it.
  if (x >= 0 && y >= 0 && z >= 0 && x < float(nx - 1) && y < float(ny - 1) && z < float(nz - 1)) {
    const int ix = int(x), iy = int(y), iz = int(z);
    const float dx = x - float(ix), dy = y - float(iy), dz = z - float(iz);
    const size_t sy = size_t(nx), sz = size_t(nx) * size_t(ny);
    const float* c = density + (size_t(iz) * size_t(ny) + size_t(iy)) * sy + size_t(ix);
    const float d00 = lerp(dx, c[0], c[1]), d10 = lerp(dx, c[sy], c[sy + 1]);
    const float d01 = lerp(dx, c[sz], c[sz + 1]), d11 = lerp(dx, c[sz + sy], c[sz + sy + 1]);
    return lerp(dz, lerp(dy, d00, d10), lerp(dy, d01, d11));
  }
  float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  int ix = int(fx), iy = int(fy), iz = int(fz);
  float dx = x - fx, dy = y - fy, dz = z - fz;
  auto d = [&](int i, int j, int k) -> float {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return 0;
    return density[(size_t(k) * size_t(ny) + size_t(j)) * size_t(nx) + size_t(i)];
  };
  float d00 = lerp(dx, d(ix, iy, iz), d(ix + 1, iy, iz));
  float d10 = lerp(dx, d(ix, iy + 1, iz), d(ix + 1, iy + 1, iz));
  float d01 = lerp(dx, d(ix, iy, iz + 1), d(ix + 1, iy, iz + 1));
  float d11 = lerp(dx, d(ix, iy + 1, iz + 1), d(ix + 1, iy + 1, iz + 1));
  return lerp(dz, lerp(dy, d00, d10), lerp(dy, d01, d11));
}

bool MediumSet::build(const pbrta::SceneArchive& a, std::string* error) {
  media_.resize(a.media.size);
  stats_ = {};
  for (uint32_t i = 0; i < a.media.size; ++i) {
    const pbrta::MediumRecord& r = a.media[i];
    Medium& m = media_[i];
    const uint32_t e = r.entity;
    const float k = a.get_float(e, "scale", 1);
    m.sigma_a = rgb_param(a, e, "sigma_a") * k;
    m.sigma_s = rgb_param(a, e, "sigma_s") * k;
    m.sigma_t = m.sigma_a + m.sigma_s;
    m.g = a.get_float(e, "g", 0);
    for (int c = 0; c < 3; ++c)
      if (!(m.sigma_a[c] >= 0) || !(m.sigma_s[c] >= 0) || !std::isfinite(m.sigma_t[c])) {
        *error = a.where(e) + ": error: medium coefficients must be finite and not negative";
        return false;
      }
    if (!(std::fabs(m.g) < 1)) {
      *error = a.where(e) + ": error: medium \"g\" must lie in (-1, 1)";
      return false;
    }
    if (a.type_name(e) == "homogeneous") {
      m.kind = MediumKind::kHomogeneous;
      ++stats_.homogeneous;
      continue;
    }
    m.kind = MediumKind::kGrid;
    m.nx = a.get_int(e, "nx", 1);
    m.ny = a.get_int(e, "ny", 1);
    m.nz = a.get_int(e, "nz", 1);
    const pbrta::ValueRecord* dv = a.value(e, "density");
    if (m.nx < 1 || m.ny < 1 || m.nz < 1 || !dv ||
        uint64_t(dv->count) != uint64_t(m.nx) * uint64_t(m.ny) * uint64_t(m.nz)) {
      *error = a.where(e) + ": error: heterogeneous medium density count is not nx * ny * nz";
      return false;
    }
    m.density = a.floats(*dv);
    for (uint32_t k = 0; k < dv->count; ++k)
      if (!(m.density[k] >= 0) || !std::isfinite(m.density[k])) {
        *error = a.where(e) + ": error: heterogeneous medium has a negative or non-finite density";
        return false;
      }
    const float* p0 = a.floats(*a.value(e, "p0"));
    const float* p1 = a.floats(*a.value(e, "p1"));
    Transform world_from_medium = Transform::from_doubles(a.transforms[r.transform].start);
    Transform medium_from_grid =
        translate({p0[0], p0[1], p0[2]}) * scale(p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]);
    Transform world_from_grid = world_from_medium * medium_from_grid;
    if (!world_from_grid.invertible()) {
      *error = a.where(e) + ": error: heterogeneous medium bounds or transform are degenerate";
      return false;
    }
    m.grid_from_world = world_from_grid.inverse();
    m.grid_sigma_t = m.sigma_t.r;
    m.majorants.build(m.density, m.nx, m.ny, m.nz, kMajorantCell);
    ++stats_.grids;
    stats_.grid_cells += uint64_t(m.majorants.cells());
  }
  return true;
}

Rgb MediumSet::sample(uint32_t mi, const Ray& ray, Sampler& sampler, bool* scattered,
                      Vec3* p) const {
  const Medium& m = media_[mi];
  *scattered = false;
  if (m.kind == MediumKind::kHomogeneous) {
    const float len = length(ray.d);
    int channel = std::min(int(sampler.get_1d() * 3), 2);
    float dist = -std::log(1 - sampler.get_1d()) / m.sigma_t[channel];
    float t = std::min(dist / len, ray.tmax);
    const bool inside = t < ray.tmax;
    if (inside) {
      *scattered = true;
      *p = ray.at(t);
    }
    // min() keeps 0 * infinity out for channels that do not attenuate.
    Rgb tr = exp(m.sigma_t * -std::min(t * len, FLT_MAX));
    Rgb density = inside ? m.sigma_t * tr : tr;
    float pdf = density.average();
    if (pdf == 0) pdf = 1;
    return inside ? tr * m.sigma_s / pdf : tr / pdf;
  }
  GridRay g;
  if (m.grid_sigma_t <= 0 || !grid_ray(m, ray, &g)) return Rgb(1.f);
  float t_hit = 0;
  track(m, g, sampler, [&](float t, float density_ratio) {
    if (density_ratio <= sampler.get_1d()) return false;  // a null collision
    t_hit = t;
    *scattered = true;
    return true;
  });
  if (!*scattered) return Rgb(1.f);
  *p = g.wo + g.wd * t_hit;
  return m.sigma_s / m.grid_sigma_t;
}

Rgb MediumSet::tr(uint32_t mi, const Ray& ray, Sampler& sampler) const {
  const Medium& m = media_[mi];
  if (m.kind == MediumKind::kHomogeneous)
    return exp(m.sigma_t * -std::min(ray.tmax * length(ray.d), FLT_MAX));
  GridRay g;
  if (m.grid_sigma_t <= 0 || !grid_ray(m, ray, &g)) return Rgb(1.f);
  float tr = 1;
  track(m, g, sampler, [&](float, float density_ratio) {
    tr *= 1 - density_ratio;
    if (tr < 0.1f) {  // pbrt-v3's Russian roulette on small transmittance
      float q = std::max(0.05f, 1 - tr);
      if (sampler.get_1d() < q) {
        tr = 0;
        return true;
      }
      tr /= 1 - q;
    }
    return false;
  });
  return Rgb(tr);
}

}  // namespace rt
