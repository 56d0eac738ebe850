// tools/mesh/info_command.cpp — `pbrt-mesh info MESH`: what a mesh holds and what is wrong.
//
// Counts, bounds and attributes, then the topology problems count_topology finds on the plain
// indexed mesh (so non-manifold input is reported, not silently repaired). For a .drc file, the
// position quantization bits the stream was encoded with, from the project's one Draco wrapper.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "format/draco_codec.h"
#include "tools/mesh/commands.h"
#include "tools/mesh/mesh.h"
#include "tools/mesh/mesh_topology.h"

namespace meshtools {
namespace {

int run_info(const std::string& path) {
  Mesh m;
  if (!read_input_mesh(path, &m, false)) return 1;
  const TopologyCounts t = count_topology(m);
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<float>::max();
    hi[k] = -std::numeric_limits<float>::max();
  }
  for (size_t i = 0; i < m.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], m.positions[i]);
    hi[i % 3] = std::max(hi[i % 3], m.positions[i]);
  }
  std::string attrs;
  auto add = [&](const char* a) { attrs += attrs.empty() ? a : std::string(", ") + a; };
  if (!m.normals.empty()) add("normals");
  if (!m.uvs.empty()) add("uv");
  if (!m.face_indices.empty()) add("face indices");
  if (attrs.empty()) attrs = "positions only";

  std::printf("%s (%s)\n", path.c_str(), extension_of(path).c_str());
  std::printf("  vertices          %zu (%zu in no face)\n", m.num_vertices(),
              t.unreferenced_vertices);
  std::printf("  triangles         %zu\n", m.num_triangles());
  if (m.num_vertices() > 0)
    std::printf("  bounds            (%.9g %.9g %.9g) - (%.9g %.9g %.9g)\n", lo[0], lo[1], lo[2],
                hi[0], hi[1], hi[2]);
  std::printf("  attributes        %s\n", attrs.c_str());
  std::printf("  edges             %zu (%zu on the boundary)\n", t.edges, t.boundary_edges);
  std::printf("  boundary loops    %zu%s\n", t.boundary_loops,
              t.boundary_loops == 0 && t.edges > 0 ? " (closed)" : "");
  std::printf("  non-manifold      %zu edges, %zu vertices\n", t.non_manifold_edges,
              t.non_manifold_vertices);
  std::printf("  degenerate faces  %zu\n", t.degenerate_faces);
  std::printf("  duplicate faces   %zu\n", t.duplicate_faces);
  if (extension_of(path) == "drc") {
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    int bits = 0;
    std::string error;
    if (pbrta::draco_position_bits(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(),
                                   &bits, &error) &&
        bits > 0)
      std::printf("  draco bits        %d (position quantization)\n", bits);
    else
      std::printf("  draco bits        none (positions not quantized)\n");
  }
  return 0;
}

}  // namespace

void add_info_command(CLI::App* app, int* exit_code) {
  auto path = std::make_shared<std::string>();
  CLI::App* cmd =
      app->add_subcommand("info", "Counts, bounds, attributes and topology problems of a mesh");
  cmd->add_option("MESH", *path, "Mesh file (.obj .ply .off .stl .drc .pbrt)")->required();
  cmd->callback([path, exit_code]() { *exit_code = run_info(*path); });
}

}  // namespace meshtools
