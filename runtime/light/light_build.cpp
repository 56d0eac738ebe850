// runtime/light/light_build.cpp — LightSet::build: the archive's lights as
// pbrt-v3's Create*Light functions make them (see lights.h).
#include <algorithm>
#include <cmath>

#include "runtime/geometry/quadric_intersect.h"
#include "runtime/light/lights.h"

namespace rt {

namespace {

Rgb get_rgb(const pbrta::SceneArchive& a, uint32_t entity, const char* name, Rgb fallback) {
  const pbrta::ValueRecord* v = a.value(entity, name);
  if (!v || v->count == 0) return fallback;
  const float* f = a.floats(*v);
  return {f[0], f[1], f[2]};
}

Vec3 get_point(const pbrta::SceneArchive& a, uint32_t entity, const char* name, Vec3 fallback) {
  const pbrta::ValueRecord* v = a.value(entity, name);
  if (!v || v->count == 0) return fallback;
  const float* f = a.floats(*v);
  return {f[0], f[1], f[2]};
}

std::string unsupported(const pbrta::SceneArchive& a, uint32_t entity, const std::string& what) {
  return "not supported yet: " + what + " (" + a.where(entity) + ")";
}

// The light's own frame: pbrt-v3 uses the transform at the start of the
// shutter interval for lights.
Transform light_transform(const pbrta::SceneArchive& a, const pbrta::LightRecord& r) {
  return Transform::from_doubles(a.transforms[r.transform].start);
}

const char* shape_name(ShapeKind k) {
  switch (k) {
    case ShapeKind::kTriangles:
      return "triangle mesh";
    case ShapeKind::kSphere:
      return "sphere";
    case ShapeKind::kCylinder:
      return "cylinder";
    case ShapeKind::kDisk:
      return "disk";
    case ShapeKind::kCone:
      return "cone";
    case ShapeKind::kParaboloid:
      return "paraboloid";
    case ShapeKind::kHyperboloid:
      return "hyperboloid";
    case ShapeKind::kCurve:
      return "curve";
  }
  return "shape";
}

}  // namespace

bool LightSet::build(const pbrta::SceneArchive& a, const ShapeTable& shapes,
                     const Bounds3& world_bounds, std::string* error) {
  *this = LightSet();
  shapes_ = &shapes;
  world_bounds.bounding_sphere(&world_center_, &world_radius_);
  for (uint32_t i = 0; i < a.lights.size; ++i)
    if (!add_light(a, i, error)) return false;
  for (uint32_t i = 0; i < a.lights.size; ++i)
    media_.push_back(a.lights[i].medium != pbrta::kNoIndex ? a.lights[i].medium : kNone);
  return add_area_lights(a, error);
}

bool LightSet::add_light(const pbrta::SceneArchive& a, uint32_t index, std::string* error) {
  const pbrta::LightRecord& r = a.lights[index];
  uint32_t e = r.entity;
  std::string_view type = a.type_name(e);
  Transform l2w = light_transform(a, r);
  if (!l2w.invertible()) {
    *error = a.where(e) + ": light transform is not invertible";
    return false;
  }
  Rgb scale = get_rgb(a, e, "scale", Rgb(1));
  auto load_map = [&](uint32_t* map) {
    *map = kNone;
    if (r.image == pbrta::kNoIndex) return true;
    MipMap m;
    if (!m.init(a, r.image, /*flip_rows=*/false, error)) return false;
    *map = uint32_t(maps_.size());
    maps_.push_back(std::move(m));
    return true;
  };

  if (type == "point" || type == "spot" || type == "goniometric" || type == "projection") {
    PositionalLight pl;
    pl.intensity = get_rgb(a, e, "I", Rgb(1)) * scale;
    Transform frame = l2w;
    LightKind kind = LightKind::kPoint;
    if (type == "point") {
      // pbrt-v3 translates by `from` in world space, after the CTM.
      frame = translate(get_point(a, e, "from", Vec3{0, 0, 0})) * l2w;
    } else if (type == "spot") {
      kind = LightKind::kSpot;
      Vec3 from = get_point(a, e, "from", Vec3{0, 0, 0});
      Vec3 to = get_point(a, e, "to", Vec3{0, 0, 1});
      Vec3 dir = normalize(to - from), du, dv;
      if (dir.has_nan()) {
        *error = a.where(e) + ": spot light with from == to";
        return false;
      }
      coordinate_system(dir, &du, &dv);
      // The rotation taking dir to +z is orthonormal: its inverse is its transpose.
      Matrix4 z_to_dir;
      for (int i = 0; i < 3; ++i) {
        z_to_dir.m[i][0] = du[i];
        z_to_dir.m[i][1] = dv[i];
        z_to_dir.m[i][2] = dir[i];
      }
      frame = l2w * translate(from) * Transform(z_to_dir, transpose(z_to_dir));
      float cone = a.get_float(e, "coneangle", 30);
      float delta = a.get_float(e, "conedeltaangle", 5);
      pl.cos_total = std::cos(radians(cone));
      pl.cos_falloff_start = std::cos(radians(cone - delta));
    } else if (type == "goniometric") {
      kind = LightKind::kGoniometric;
      if (!load_map(&pl.map)) return false;
    } else {
      kind = LightKind::kProjection;
      if (!load_map(&pl.map)) return false;
      float aspect = 1;
      if (pl.map != kNone) {
        const pbrta::ImageRecord& img = a.images[r.image];
        // pbrt-v3 takes the aspect ratio from the file as read, before resampling.
        float w = float(img.source_width ? img.source_width : img.width);
        float h = float(img.source_height ? img.source_height : img.height);
        aspect = w / h;
      }
      if (aspect > 1) {
        pl.screen_lo[0] = -aspect, pl.screen_lo[1] = -1;
        pl.screen_hi[0] = aspect, pl.screen_hi[1] = 1;
      } else {
        pl.screen_lo[0] = -1, pl.screen_lo[1] = -1 / aspect;
        pl.screen_hi[0] = 1, pl.screen_hi[1] = 1 / aspect;
      }
      pl.hither = 1e-3f;
      float fov = a.get_float(e, "fov", 45);
      pl.projection = perspective(fov, pl.hither, 1e30f);
      float tan_diag = std::tan(radians(fov) / 2) * std::sqrt(1 + 1 / (aspect * aspect));
      pl.cos_total = std::cos(std::atan(tan_diag));
    }
    pl.p = frame.point(Vec3{0, 0, 0});
    pl.world_to_light = frame.inverse();
    entries_.push_back({kind, uint32_t(positional_.size()), kNone, 0});
    positional_.push_back(std::move(pl));
    return true;
  }
  if (type == "distant") {
    DistantLight d;
    d.l = get_rgb(a, e, "L", Rgb(1)) * scale;
    Vec3 from = get_point(a, e, "from", Vec3{0, 0, 0});
    Vec3 to = get_point(a, e, "to", Vec3{0, 0, 1});
    d.w = normalize(l2w.vector(from - to));
    if (d.w.has_nan()) {
      *error = a.where(e) + ": distant light with from == to";
      return false;
    }
    entries_.push_back({LightKind::kDistant, uint32_t(distant_.size()), kNone, 0});
    distant_.push_back(d);
    return true;
  }
  if (type == "infinite") {
    InfiniteLight il;
    il.light_to_world = l2w;
    il.world_to_light = l2w.inverse();
    il.l = get_rgb(a, e, "L", Rgb(1)) * scale;
    il.nsamples = std::max(1, int(a.get_int(e, "nsamples", 1)));
    if (!load_map(&il.map)) return false;
    if (il.map != kNone) {
      // pbrtc stored the distribution pbrt-v3 builds (ARCHIVE.md, images):
      // 2w x 2h luminance times sin(theta), L * scale already in it.
      uint32_t di = a.images[r.image].distribution;
      if (di == pbrta::kNoIndex) {
        *error = a.where(e) + ": environment map has no sampling distribution";
        return false;
      }
      MipMap dist;
      if (!dist.init(a, di, /*flip_rows=*/false, error)) return false;
      const MipMap& map = maps_[il.map];
      if (dist.width() != 2 * map.width() || dist.height() != 2 * map.height() ||
          dist.channels() != 1) {
        *error = a.where(e) + ": environment map distribution is not 2w x 2h, one channel";
        return false;
      }
      // Used in place: a copy would be 32 MB more for a 2048x1024 map. pbrtc stores it f32.
      if (!dist.viewed()) {
        *error = a.where(e) + ": environment map distribution is not stored as f32";
        return false;
      }
      il.distribution = Distribution2D(dist.level_texels(0), dist.width(), dist.height(), true);
    }
    infinite_lights_.push_back(count());
    entries_.push_back({LightKind::kInfinite, uint32_t(infinite_.size()), kNone, 0});
    infinite_.push_back(std::move(il));
    return true;
  }
  *error = unsupported(a, e, "light \"" + std::string(type) + "\"");
  return false;
}

bool LightSet::add_area_lights(const pbrta::SceneArchive& a, std::string* error) {
  emitters_.resize(a.area_lights.size);
  for (uint32_t i = 0; i < a.area_lights.size; ++i) {
    uint32_t e = a.area_lights[i];
    if (a.type_name(e) != "diffuse") {
      *error = unsupported(a, e, "area light \"" + std::string(a.type_name(e)) + "\"");
      return false;
    }
    AreaEmitter& em = emitters_[i];
    em.l = get_rgb(a, e, "L", Rgb(1)) * get_rgb(a, e, "scale", Rgb(1));
    em.nsamples = std::max(1, int(a.get_int(e, "nsamples", 1)));
    em.twosided = a.get_int(e, "twosided", 0) != 0;
  }
  const ShapeTable& shapes = *shapes_;
  area_first_.assign(shapes.size(), kNone);
  for (uint32_t s = 0; s < shapes.size(); ++s) {
    const ShapeInfo& info = shapes[s];
    if (info.area_light == kNone) continue;
    // pbrtc drops area lights on instanced and animated shapes (pbrt-v3
    // ignores them with a warning), so what is left has a fixed world placement.
    if (info.object != kNone) continue;
    switch (info.kind) {
      case ShapeKind::kTriangles:
      case ShapeKind::kSphere:
      case ShapeKind::kCylinder:
      case ShapeKind::kDisk:
        break;
      default:
        *error =
            unsupported(a, info.entity, std::string("area light on a ") + shape_name(info.kind));
        return false;
    }
    area_first_[s] = count();
    uint32_t n = info.kind == ShapeKind::kTriangles ? info.mesh.num_triangles : 1;
    for (uint32_t p = 0; p < n; ++p) entries_.push_back({LightKind::kArea, info.area_light, s, p});
    if (info.kind != ShapeKind::kTriangles) continue;
    triangles_.resize(count());
    for (uint32_t p = 0; p < n; ++p) triangles_[area_first_[s] + p] = world_triangle(info, p);
  }
  reach_.assign(count(), Bounds3{});
  for (uint32_t light = 0; light < count(); ++light) {
    const Entry& e = entries_[light];
    if (e.kind != LightKind::kArea) continue;
    const ShapeInfo& info = shapes[e.shape];
    Bounds3 b;
    if (info.kind == ShapeKind::kTriangles) {
      const WorldTriangle& t = triangles_[light];
      b.extend(t.p0);
      b.extend(t.p1);
      b.extend(t.p2);
    } else {
      b = quadric_world_bounds(info);
    }
    // Hits are found on the shape within rounding of it (a few ulps of the coordinates): a
    // ten-thousandth of the box's size and of its distance from the origin is far beyond that.
    const Vec3 mag = vmax(abs(b.lo), abs(b.hi));
    const Vec3 d = b.diagonal();
    const float pad =
        1e-4f * (std::max(mag.x, std::max(mag.y, mag.z)) + std::max(d.x, std::max(d.y, d.z))) +
        1e-30f;
    b.lo = b.lo - Vec3{pad, pad, pad};
    b.hi = b.hi + Vec3{pad, pad, pad};
    reach_[light] = b;
  }
  return true;
}

}  // namespace rt
