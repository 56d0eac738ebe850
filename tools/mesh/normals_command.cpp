// tools/mesh/normals_command.cpp — `pbrt-mesh normals IN OUT`: recompute vertex normals.
//
// Reads any mesh format, replaces its normals with area- or angle-weighted ones (splitting
// vertices along edges sharper than --crease), writes OUT and reports what the pass changed:
// the position error, measured with the same Hausdorff sampler simplify uses (it should be 0:
// a vertex split copies positions, so a nonzero value means a bug, and printing the measurement
// rather than a constant is what shows it), and how far the new normals turned from the input's.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "tools/mesh/commands.h"
#include "tools/mesh/mesh.h"
#include "tools/mesh/mesh_ops.h"

namespace meshtools {
namespace {

struct NormalsArgs {
  std::string in, out;
  std::string weight = "angle";
  double crease = 180.0;
  bool quiet = false;
};

int run_normals(const NormalsArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  Mesh mesh;
  std::string error;
  if (!read_input_mesh(args.in, &mesh, args.quiet)) return 1;
  const Mesh input = mesh;
  NormalsOptions options;
  options.weighting = args.weight == "area" ? NormalWeighting::kArea : NormalWeighting::kAngle;
  options.crease_angle_degrees = args.crease;
  std::vector<uint32_t> source;
  compute_normals(&mesh, options, &source);
  if (!write_mesh(args.out, mesh, WriteOptions{}, &error)) {
    std::fprintf(stderr, "pbrt-mesh: error: %s\n", error.c_str());
    return 1;
  }
  if (args.quiet) return 0;

  const HausdorffResult h = hausdorff_distance(input, mesh);
  std::printf("%s: %zu triangles, %zu -> %zu vertices (%s weighting, crease %g deg)\n",
              args.out.c_str(), mesh.num_triangles(), input.num_vertices(), mesh.num_vertices(),
              args.weight.c_str(), args.crease);
  std::printf("  position error (measured Hausdorff, %zu samples): max %.9g, rms %.9g\n", h.samples,
              h.max, h.rms);
  if (input.normals.size() == 3 * input.num_vertices() && input.num_vertices() > 0) {
    // Each output vertex against the input normal of the vertex it was copied from; input
    // normals of zero length carry no direction and are counted, not compared.
    double max_angle = 0, sum_angle = 0;
    size_t compared = 0, unusable = 0;
    for (size_t v = 0; v < mesh.num_vertices(); ++v) {
      const float* a = &input.normals[3 * source[v]];
      const float* b = &mesh.normals[3 * v];
      const double la = std::sqrt(double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2]);
      const double lb = std::sqrt(double(b[0]) * b[0] + double(b[1]) * b[1] + double(b[2]) * b[2]);
      if (!(la > 0) || !std::isfinite(la) || !(lb > 0)) {
        ++unusable;
        continue;
      }
      const double c =
          (double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2]) / (la * lb);
      const double angle = std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
      max_angle = std::max(max_angle, angle);
      sum_angle += angle;
      ++compared;
    }
    std::printf("  normal change vs input: max %.4g deg, mean %.4g deg over %zu vertices",
                max_angle, compared ? sum_angle / double(compared) : 0.0, compared);
    if (unusable) std::printf(" (%zu input normals of zero length skipped)", unusable);
    std::printf("\n");
  } else {
    std::printf("  input had no normals\n");
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("  %.2f s\n", seconds);
  return 0;
}

}  // namespace

void add_normals_command(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<NormalsArgs>();
  CLI::App* cmd = app->add_subcommand(
      "normals", "recompute vertex normals (area- or angle-weighted, with a crease angle)");
  cmd->add_option("IN", args->in, "input mesh (.ply .obj .off .stl .drc .pbrt)")->required();
  cmd->add_option("OUT", args->out, "output mesh, format by extension")->required();
  cmd->add_option("--weight", args->weight, "face weighting: area or angle (default angle)")
      ->check(CLI::IsMember({"area", "angle"}));
  cmd->add_option("--crease", args->crease,
                  "split vertices where faces meet at more than DEG degrees (default 180: never)")
      ->check(CLI::Range(0.0, 180.0));
  cmd->add_flag("--quiet", args->quiet, "print nothing but errors");
  cmd->callback([args, exit_code] { *exit_code = run_normals(*args); });
}

}  // namespace meshtools
