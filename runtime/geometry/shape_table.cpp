// runtime/geometry/shape_table.cpp — see shape_table.h.
#include "runtime/geometry/shape_table.h"

#include <cstring>

namespace rt {

namespace {

ShapeKind kind_of(std::string_view type) {
  if (type == "sphere") return ShapeKind::kSphere;
  if (type == "cylinder") return ShapeKind::kCylinder;
  if (type == "disk") return ShapeKind::kDisk;
  if (type == "cone") return ShapeKind::kCone;
  if (type == "paraboloid") return ShapeKind::kParaboloid;
  if (type == "hyperboloid") return ShapeKind::kHyperboloid;
  if (type == "curve") return ShapeKind::kCurve;
  return ShapeKind::kTriangles;
}

Vec3 get_point(const pbrta::SceneArchive& a, uint32_t e, std::string_view name, Vec3 fallback) {
  const pbrta::ValueRecord* v = a.value(e, name);
  if (!v || v->count == 0) return fallback;
  const float* f = a.floats(*v);
  return {f[0], f[1], f[2]};
}

}  // namespace

bool ShapeTable::build(const pbrta::SceneArchive& a, std::string* error) {
  shapes_.resize(a.shapes.size);
  size_t animated = 0, curves = 0;
  for (uint32_t i = 0; i < a.shapes.size; ++i) {
    const pbrta::TransformRecord& t = a.transforms[a.shapes[i].transform];
    animated += std::memcmp(t.start, t.end, sizeof t.start) != 0;
    curves += a.shapes[i].mesh == pbrta::kNoIndex &&
              kind_of(a.type_name(a.shapes[i].entity)) == ShapeKind::kCurve;
  }
  motions_.clear();
  motions_.reserve(animated);
  curves_.clear();
  curves_.reserve(curves);
  for (uint32_t i = 0; i < a.shapes.size; ++i) {
    const pbrta::ShapeRecord& r = a.shapes[i];
    ShapeInfo& s = shapes_[i];
    s.entity = r.entity;
    s.kind = r.mesh != pbrta::kNoIndex ? ShapeKind::kTriangles : kind_of(a.type_name(r.entity));
    const pbrta::TransformRecord& t = a.transforms[r.transform];
    s.object_to_world = Transform::from_doubles(t.start);
    s.animated = std::memcmp(t.start, t.end, sizeof t.start) != 0;
    if (s.animated) {
      s.motion = &motions_.emplace_back(t.start, t.end, float(t.start_time), float(t.end_time));
      if (!Transform::from_doubles(t.end).invertible()) {
        *error = a.where(r.entity) + ": error: shape end transform is singular";
        return false;
      }
    }
    if (!s.object_to_world.invertible() || s.object_to_world.is_projective()) {
      *error = a.where(r.entity) + ": error: shape transform is singular or projective";
      return false;
    }
    s.reverse_orientation = r.flags & pbrta::kShapeReverseOrientation;
    // pbrt-v3 makes a moving shape with the identity transform: its handedness never flips it.
    s.swaps_handedness = (r.flags & pbrta::kShapeSwapsHandedness) && !s.animated;
    s.material = r.material;
    s.area_light = r.area_light;
    s.object = r.object;
    s.inside_medium = r.inside_medium;
    s.outside_medium = r.outside_medium;
    uint32_t e = r.entity;
    QuadricParams& q = s.q;
    switch (s.kind) {
      case ShapeKind::kSphere:
        q.radius = a.get_float(e, "radius", 1);
        q.zmin = a.given(e, "zmin") ? a.get_float(e, "zmin") : -q.radius;
        q.zmax = a.given(e, "zmax") ? a.get_float(e, "zmax") : q.radius;
        break;
      case ShapeKind::kCylinder:
      case ShapeKind::kParaboloid:
        q.radius = a.get_float(e, "radius", 1);
        q.zmin = a.get_float(e, "zmin", s.kind == ShapeKind::kCylinder ? -1 : 0);
        q.zmax = a.get_float(e, "zmax", 1);
        break;
      case ShapeKind::kDisk:
        q.height = a.get_float(e, "height", 0);
        q.radius = a.get_float(e, "radius", 1);
        q.inner_radius = a.get_float(e, "innerradius", 0);
        break;
      case ShapeKind::kCone:
        q.radius = a.get_float(e, "radius", 1);
        q.height = a.get_float(e, "height", 1);
        break;
      case ShapeKind::kHyperboloid:
        q.p1 = get_point(a, e, "p1", {0, 0, 0});
        q.p2 = get_point(a, e, "p2", {1, 1, 1});
        break;
      case ShapeKind::kCurve:
        s.curve = &curves_.emplace_back();
        if (!make_curve(a, e, &curves_.back(), error)) return false;
        break;
      default:
        break;
    }
    if (s.kind != ShapeKind::kTriangles && s.kind != ShapeKind::kCurve)
      q.phimax = radians(clamp(a.get_float(e, "phimax", 360), 0.f, 360.f));
    if (r.mesh != pbrta::kNoIndex) {
      const pbrta::MeshRecord& m = a.meshes[r.mesh];
      MeshView& v = s.mesh;
      v.num_vertices = m.num_vertices;
      v.num_triangles = m.num_triangles;
      v.positions = a.positions(r.mesh);
      v.normals = a.normals(r.mesh);
      v.tangents = a.tangents(r.mesh);
      v.uv = a.uvs(r.mesh);
      v.indices = a.indices(r.mesh);
      v.face_indices = a.face_indices(r.mesh);
      // alpha and shadowalpha exist on trianglemesh and plymesh only.
      if (const pbrta::ValueRecord* av = a.value(e, "alpha")) {
        s.alpha_texture = av->texture == pbrta::kNoIndex ? kNone : av->texture;
        if (av->count) s.alpha = a.floats(*av)[0];
      }
      if (const pbrta::ValueRecord* sv = a.value(e, "shadowalpha")) {
        s.shadow_alpha_texture = sv->texture == pbrta::kNoIndex ? kNone : sv->texture;
        if (sv->count) s.shadow_alpha = a.floats(*sv)[0];
      }
    }
  }
  return true;
}

}  // namespace rt
