// tools/mesh/simplify_command.cpp — `pbrt-mesh simplify IN OUT --ratio R`: quadric decimation.
//
// Decimates with OpenMesh's quadric decimater and prints the faces before and after and the
// Hausdorff distance between input and output as measured by sampling both surfaces, absolute
// and as a fraction of the input's bounding-box diagonal, so the cost of a ratio is visible
// before the mesh goes into a scene.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "tools/mesh/commands.h"
#include "tools/mesh/mesh.h"
#include "tools/mesh/mesh_ops.h"

namespace meshtools {
namespace {

struct SimplifyArgs {
  std::string in, out;
  double ratio = 0.5;
  std::optional<double> max_error;
  bool quiet = false;
};

int run_simplify(const SimplifyArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  Mesh mesh;
  std::string error;
  if (!read_input_mesh(args.in, &mesh, args.quiet)) return 1;
  SimplifyOptions options;
  options.ratio = args.ratio;
  options.max_quadric_error = args.max_error;
  options.measure = !args.quiet;
  Mesh out;
  SimplifyReport report;
  if (!simplify(mesh, options, &out, &report, &error)) {
    std::fprintf(stderr, "pbrt-mesh: error: %s: %s\n", args.in.c_str(), error.c_str());
    return 1;
  }
  if (!write_mesh(args.out, out, WriteOptions{}, &error)) {
    std::fprintf(stderr, "pbrt-mesh: error: %s\n", error.c_str());
    return 1;
  }
  if (args.quiet) return 0;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s: faces %zu -> %zu (%.1f%%), vertices %zu -> %zu\n", args.out.c_str(),
              report.faces_before, report.faces_after,
              report.faces_before ? 100.0 * report.faces_after / report.faces_before : 0.0,
              report.vertices_before, report.vertices_after);
  const double diag = report.bbox_diagonal;
  const auto& h = report.hausdorff;
  std::printf(
      "  Hausdorff distance (measured, %zu samples): max %.6g (%.4f%% of bbox diagonal "
      "%.6g), rms %.6g (%.4f%%)\n",
      h.samples, h.max, diag > 0 ? 100.0 * h.max / diag : 0.0, diag, h.rms,
      diag > 0 ? 100.0 * h.rms / diag : 0.0);
  if (report.degenerate_faces_dropped) {
    std::printf("  %zu faces with a repeated vertex dropped\n", report.degenerate_faces_dropped);
  }
  if (report.locked_vertices) {
    std::printf("  %zu seam vertices kept in place\n", report.locked_vertices);
  }
  if (report.normals_recomputed) std::printf("  normals recomputed (angle-weighted)\n");
  std::printf("  %.2f s\n", seconds);
  return 0;
}

}  // namespace

void add_simplify_command(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<SimplifyArgs>();
  CLI::App* cmd = app->add_subcommand(
      "simplify", "quadric decimation, reporting the measured Hausdorff distance");
  cmd->add_option("IN", args->in, "input mesh (.ply .obj .off .stl .drc .pbrt)")->required();
  cmd->add_option("OUT", args->out, "output mesh, format by extension")->required();
  cmd->add_option("--ratio", args->ratio, "fraction of the faces to keep, in (0, 1]")
      ->required()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--max-error", args->max_error,
                  "refuse collapses whose quadric error (area x squared distance, length^4) "
                  "exceeds E; the result may then keep more faces than the ratio asks");
  cmd->add_flag("--quiet", args->quiet, "print nothing but errors");
  cmd->callback([args, exit_code] { *exit_code = run_simplify(*args); });
}

}  // namespace meshtools
