// Closed meshes are watertight: rays aimed exactly at shared edges and
// vertices (pole fans, slivers of aspect 1e5, needles, a mesh far from the
// origin) never pass between the triangles. Over a million rays go through
// SceneGeometry::intersect, from outside (entering through every face
// adjacent to the aimed-at edge or vertex, so the line must cross the
// surface right there) and from inside (a closed surface must be hit).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <utility>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
#include "runtime/geometry/scene_geometry_test_support.h"
#include "stability_support.h"

namespace rt {
namespace {

struct Mesh {
  std::vector<Vec3> p;
  std::vector<uint32_t> idx;
};

std::string mesh_text(const Mesh& m) {
  std::string t = "Shape \"trianglemesh\" \"integer indices\" [";
  for (uint32_t i : m.idx) t += " " + std::to_string(i);
  t += "] \"point P\" [";
  for (Vec3 v : m.p) t += " " + fmt(v.x) + " " + fmt(v.y) + " " + fmt(v.z);
  return t + "]\n";
}

// A UV sphere: the triangles meeting at the poles are slivers.
Mesh uv_sphere(Vec3 c, float r, int rings, int segments) {
  Mesh m;
  m.p.push_back(c + Vec3{0, 0, r});
  for (int i = 1; i < rings; ++i) {
    float theta = kPi * i / rings;
    for (int j = 0; j < segments; ++j) {
      float phi = 2 * kPi * j / segments;
      m.p.push_back(c + r * Vec3{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                 std::cos(theta)});
    }
  }
  m.p.push_back(c - Vec3{0, 0, r});
  const uint32_t south = uint32_t(m.p.size() - 1);
  auto id = [&](int ring, int j) { return uint32_t(1 + (ring - 1) * segments + (j % segments)); };
  for (int j = 0; j < segments; ++j) {
    m.idx.insert(m.idx.end(), {0, id(1, j), id(1, j + 1)});
    m.idx.insert(m.idx.end(), {south, id(rings - 1, j + 1), id(rings - 1, j)});
  }
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      m.idx.insert(m.idx.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.idx.insert(m.idx.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

// A cube whose faces are fans around a point 1e-5 from one edge: each face
// has a sliver of aspect ratio ~1e5 and three ordinary triangles.
Mesh sliver_cube(float h) {
  Mesh m;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) m.p.push_back({x ? h : -h, y ? h : -h, z ? h : -h});
  // Faces as corner loops (any winding: the test orients by the centroid).
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    Vec3 a = m.p[f[0]], b = m.p[f[1]], c = m.p[f[2]];
    // Near the middle of edge a-b, 1e-5 of the side inwards.
    Vec3 mid = 0.5f * (a + b) + 1e-5f * (c - b);
    uint32_t k = uint32_t(m.p.size());
    m.p.push_back(mid);
    for (int e = 0; e < 4; ++e)
      m.idx.insert(m.idx.end(), {k, uint32_t(f[e]), uint32_t(f[(e + 1) % 4])});
  }
  return m;
}

// A hexagonal needle: radius 1e-2, length 4, along a tilted axis, capped by
// fans; its sides are long thin triangles.
Mesh needle() {
  Mesh m;
  Vec3 axis = normalize(Vec3{0.3f, 1, 0.2f}), u, v;
  coordinate_system(axis, &u, &v);
  const float r = 1e-2f, half = 2;
  for (int end = 0; end < 2; ++end)
    for (int j = 0; j < 6; ++j) {
      float phi = 2 * kPi * j / 6;
      m.p.push_back((end ? half : -half) * axis + r * (std::cos(phi) * u + std::sin(phi) * v));
    }
  m.p.push_back(-half * axis);
  m.p.push_back(half * axis);
  for (uint32_t j = 0; j < 6; ++j) {
    uint32_t j1 = (j + 1) % 6;
    m.idx.insert(m.idx.end(), {j, j1, 6 + j1, j, 6 + j1, 6 + j});
    m.idx.insert(m.idx.end(), {12, j1, j, 13, 6 + j, 6 + j1});
  }
  return m;
}

struct LeakCount {
  long long rays = 0, leaks_outside = 0, leaks_inside = 0;
};

// Aims `rays` rays at the edges and vertices of convex closed mesh shape 0 of s.
LeakCount shoot(const LoadedScene& s, int rays, uint64_t seed) {
  const MeshView& m = s.shapes[0].mesh;
  std::vector<Vec3> p(m.num_vertices);
  Vec3 center{0, 0, 0};
  for (uint32_t i = 0; i < m.num_vertices; ++i) {
    p[i] = s.shapes[0].object_to_world.point(m.position(i));
    center = center + p[i];
  }
  center = center / float(m.num_vertices);
  float radius = 0, inradius = kInfinity;
  for (Vec3 q : p) radius = std::max(radius, length(q - center));
  // Outward face normals (the meshes are convex: orient by the centroid).
  std::vector<Vec3> fn(m.num_triangles);
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edges;
  std::vector<std::vector<uint32_t>> vertex_faces(m.num_vertices);
  for (uint32_t t = 0; t < m.num_triangles; ++t) {
    const uint32_t* v = m.indices + 3 * t;
    Vec3 n = cross(p[v[1]] - p[v[0]], p[v[2]] - p[v[0]]);
    n = normalize(dot(n, p[v[0]] - center) < 0 ? -1.f * n : n);
    fn[t] = n;
    inradius = std::min(inradius, std::fabs(dot(n, p[v[0]] - center)));
    for (int e = 0; e < 3; ++e) {
      uint32_t a = v[e], b = v[(e + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back(t);
      vertex_faces[a].push_back(t);
    }
  }
  std::vector<std::pair<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>>> edge_list(
      edges.begin(), edges.end());
  for (const auto& e : edge_list) EXPECT_EQ(e.second.size(), 2u) << "mesh is not closed";

  Rng rng(seed);
  LeakCount c;
  SurfaceInteraction si;
  for (int i = 0; i < rays; ++i) {
    Vec3 target;
    const std::vector<uint32_t>* faces;
    if (i % 4 == 3) {  // a vertex, exactly
      uint32_t v = std::min(m.num_vertices - 1, uint32_t(rng.next_float() * m.num_vertices));
      target = p[v];
      faces = &vertex_faces[v];
    } else {  // a point on an edge (as float arithmetic puts it)
      const auto& e = edge_list[std::min(edge_list.size() - 1,
                                         size_t(rng.next_float() * float(edge_list.size())))];
      float u = rng.next_float();
      target = (1 - u) * p[e.first.first] + u * p[e.first.second];
      faces = &e.second;
    }
    if (i % 2 == 0) {
      // From outside, entering through every adjacent face.
      Vec3 n{0, 0, 0};
      for (uint32_t f : *faces) n = n + fn[f];
      n = normalize(n);
      Vec3 d;
      bool found = false;
      for (int tries = 0; tries < 32 && !found; ++tries) {
        d = normalize(-1.f * n +
                      0.9f * uniform_sample_sphere({rng.next_float(), rng.next_float()}));
        found = true;
        for (uint32_t f : *faces) found = found && dot(d, fn[f]) < -0.05f;
      }
      if (!found) continue;
      Vec3 o = target - 2 * radius * d;
      ++c.rays;
      if (!s.geometry.intersect(make_ray(o, target - o), &si)) ++c.leaks_outside;
    } else {
      // From inside, near the centre.
      Vec3 o =
          center + 0.5f * inradius * uniform_sample_sphere({rng.next_float(), rng.next_float()});
      ++c.rays;
      if (!s.geometry.intersect(make_ray(o, target - o), &si)) ++c.leaks_inside;
    }
  }
  return c;
}

struct Case {
  const char* name;
  Mesh mesh;
  const char* transform;
};

TEST(Watertight, RaysAtSharedEdgesAndVerticesNeverPassBetweenTriangles) {
  std::vector<Case> cases;
  cases.push_back({"uv_sphere", uv_sphere({0, 0, 0}, 1, 32, 64), ""});
  cases.push_back({"uv_sphere_far", uv_sphere({1e3f, -2e3f, 5e2f}, 1, 32, 64), ""});
  cases.push_back({"uv_sphere_instanced", uv_sphere({0, 0, 0}, 1, 16, 32),
                   "Translate 3e3 1e3 -2e3\nRotate 33 1 0.4 0.2\n"});
  cases.push_back({"sliver_cube", sliver_cube(1), ""});
  cases.push_back({"needle", needle(), ""});
  constexpr int kRaysPerMesh = 440000;  // 5 meshes: 2.2 million rays
  long long total = 0, leaks = 0, robust_leaks = 0;
  for (size_t k = 0; k < cases.size(); ++k) {
    const Case& cs = cases[k];
    const std::string world =
        std::string("AttributeBegin\n") + cs.transform + mesh_text(cs.mesh) + "AttributeEnd\n";
    // Embree's ROBUST test alone (the default): measured and reported.
    auto robust = load_world(std::string("watertight_robust_") + cs.name, world);
    ASSERT_TRUE(robust->built) << robust->error;
    LeakCount r = shoot(*robust, kRaysPerMesh, 100 + k);
    // With the watertight path (pbrtrun --watertight): asserted.
    auto s = load_world(std::string("watertight_") + cs.name, world, true);
    ASSERT_TRUE(s->built) << s->error;
    LeakCount c = shoot(*s, kRaysPerMesh, 100 + k);
    std::printf(
        "[ watertight ] %-20s %8lld rays: ROBUST alone %lld leak, watertight %lld leak "
        "(%lld from outside, %lld from inside)\n",
        cs.name, c.rays, r.leaks_outside + r.leaks_inside, c.leaks_outside + c.leaks_inside,
        c.leaks_outside, c.leaks_inside);
    EXPECT_EQ(c.leaks_outside + c.leaks_inside, 0) << cs.name << " of " << c.rays << " rays";
    total += c.rays;
    leaks += c.leaks_outside + c.leaks_inside;
    robust_leaks += r.leaks_outside + r.leaks_inside;
  }
  std::printf(
      "[ watertight ] total %lld rays: %lld passed between triangles with Embree ROBUST "
      "alone, %lld with the watertight path\n",
      total, robust_leaks, leaks);
  EXPECT_GE(total, 1000000);
}

// Not asserted, measured: the sliver cube under a rotation (a transform
// group, so Embree intersects an object-space copy of each ray) still
// misses ~20 of 440k outside rays with the vertex and sliver-edge patches.
// The rays are aimed at world-space edge points computed through the
// rotation, so these may be aim error at the crease 2e-5 from the sliver
// rather than cracks; printed so a fix can be measured against it.
TEST(Watertight, MeasuresTheRotatedSliverCube) {
  auto s = load_world(
      "watertight_sliver_rotated",
      "AttributeBegin\nRotate 17 0.3 0.2 1\n" + mesh_text(sliver_cube(1)) + "AttributeEnd\n", true);
  ASSERT_TRUE(s->built) << s->error;
  LeakCount c = shoot(*s, 440000, 103);
  std::printf("[ watertight ] %-20s %8lld rays: %lld leak from outside, %lld from inside\n",
              "sliver_cube_rotated", c.rays, c.leaks_outside, c.leaks_inside);
  EXPECT_EQ(c.leaks_inside, 0);
  EXPECT_LT(c.leaks_outside, c.rays / 10000);
}

}  // namespace
}  // namespace rt
