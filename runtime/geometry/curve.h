// runtime/geometry/curve.h — pbrt-v3's "curve" shape: flat, cylinder and ribbon
// curves as cubic Bézier segments, hit by recursive subdivision (book 3rd ed.,
// section 3.7).
//
// make_curve() reads a curve shape's parameters and turns every segment into
// the cubic Bézier pbrt-v3 intersects (degree 2 elevated, uniform B-splines
// converted), with the widths interpolated along the whole curve and the
// ribbon's end normals. Each segment is split into 2^splitdepth pieces over
// u, as pbrt-v3 splits it into that many shapes: a piece is one Embree user
// primitive (piece_bounds()).
//
// intersect_curve_piece() is pbrt-v3's test in object space: the piece is seen
// from a frame where the ray runs down +z, refined to a depth set by its
// curvature against its width, and a leaf is hit where the ray passes within
// half the width of the closest point. The hit is the point on the ray, with
// pbrt-v3's (generous) error bound of twice the width, uv = (u along the
// segment, v across it), and the dp/du, dp/dv that give each type its look:
// flat curves face the ray, cylinders turn dp/dv about the curve with v so
// their normal sweeps half a circle, ribbons follow the interpolated normal.
// No allocation; the caller moves rays and hits between world and object space.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/ray.h"
#include "runtime/core/vec.h"

namespace rt {

enum class CurveType : uint8_t { kFlat, kCylinder, kRibbon };

// One Bézier segment (pbrt-v3's CurveCommon), object space.
struct CurveSegment {
  Vec3 cp[4];
  float width[2] = {1, 1};  // at u = 0 and u = 1 of this segment
  Vec3 n[2];                // ribbons: unit normals at the ends
  float normal_angle = 0, inv_sin_normal_angle = 0;
};

struct CurveShape {
  CurveType type = CurveType::kFlat;
  int split_depth = 3;
  std::vector<CurveSegment> segments;
  // Each piece's own four Bezier points (its segment's blossoms over [u0, u1]), made once by
  // make_curve: every ray through a piece's box starts from them.
  std::vector<Vec3> piece_points;
  uint32_t num_pieces() const { return uint32_t(segments.size()) << split_depth; }
  const Vec3* points_of(uint32_t piece) const { return &piece_points[4 * size_t(piece)]; }
  const CurveSegment& segment_of(uint32_t piece) const { return segments[piece >> split_depth]; }
  // The u interval of a piece within its segment.
  float u0(uint32_t piece) const {
    return float(piece & ((1u << split_depth) - 1)) / float(1u << split_depth);
  }
  float u1(uint32_t piece) const {
    return float((piece & ((1u << split_depth) - 1)) + 1) / float(1u << split_depth);
  }
  // A piece's object-space box: its control points grown by half its widest width.
  Bounds3 piece_bounds(uint32_t piece) const;
};

// The curve of shape entity `entity`; false with a located message when its
// parameters break pbrt-v3's rules (pbrtc checks them too).
[[nodiscard]] bool make_curve(const pbrta::SceneArchive& a, uint32_t entity, CurveShape* out,
                              std::string* error);

struct CurveHit {
  float t = 0;  // along the given ray
  Vec3 p, p_error;
  Vec2 uv;
  Vec3 dpdu, dpdv;
};

// Closest hit in (0, ray.tmax] of an object-space ray with piece `piece`; hit
// may be null (any hit will do).
bool intersect_curve_piece(const CurveShape& c, uint32_t piece, const Ray& ray, CurveHit* hit);

}  // namespace rt
