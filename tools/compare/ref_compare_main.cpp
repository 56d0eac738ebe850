// tools/compare/ref_compare_main.cpp — ref-compare: the convergence test on three EXR files.
//
//   ref-compare A.exr B.exr reference.exr [--png side-by-side.png]
//               [--spp N --reference-spp M]
//   ref-compare --spread R1.exr ... Rn.exr reference.exr [...]
//
// A and B are renders at half the reference's spp with different seeds (or,
// with --spp and --reference-spp, at N/2 each against a reference of M). With
// --spread, n >= 4 renders of N/n spp each are judged by the spread of their
// block means (for noise correlated between pixels: mlt, sppm).
// Prints the block statistics and exits 0 when the render converges to the
// reference (tools/compare/convergence.h has the rule), 1 when it does not,
// 2 when the images cannot be read or compared.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "tools/compare/convergence.h"

int main(int argc, char** argv) {
  CLI::App app{"ref-compare: does a render converge to a pbrt-v3 reference?"};
  std::vector<std::string> paths;
  std::string png;
  app.add_option("files", paths,
                 "Render A, render B (half the reference's spp each, different seeds), then the "
                 "reference EXR; with --spread: n >= 4 renders, then the reference")
      ->required();
  bool spread = false;
  app.add_flag("--spread", spread,
               "Judge n >= 4 renders by the spread of their block means (correlated noise)");
  app.add_option("--png", png, "Write ours | reference | signed difference here");
  int spp = 0, ref_spp = 0;
  app.add_option("--spp", spp, "Samples per pixel of A and B together (default: the reference's)")
      ->check(CLI::PositiveNumber);
  app.add_option("--reference-spp", ref_spp, "Samples per pixel of the reference")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  if (spread ? paths.size() < 5 : paths.size() != 3) {
    std::cerr << "ref-compare: error: "
              << (spread ? "--spread needs at least 4 renders and the reference"
                         : "give render A, render B and the reference")
              << "\n";
    return 2;
  }
  std::vector<rt::ImageRgb> images(paths.size());
  std::string error;
  for (size_t i = 0; i < paths.size(); ++i)
    if (!rt::read_exr(paths[i], &images[i], &error)) {
      std::cerr << "ref-compare: error: " << error << "\n";
      return 2;
    }
  const std::string& ref_path = paths.back();
  const rt::ImageRgb ref = images.back();
  images.pop_back();
  const rt::ImageRgb& a = images[0];
  const rt::ImageRgb& b = images[1];
  if ((spp > 0) != (ref_spp > 0)) {
    std::cerr << "ref-compare: error: --spp and --reference-spp go together\n";
    return 2;
  }
  const double spp_ratio = spp > 0 ? double(spp) / ref_spp : 1;
  compare::ConvergenceResult r = spread ? compare::check_convergence_spread(images, ref, spp_ratio)
                                        : compare::check_convergence(a, b, ref, spp_ratio);
  if (!r.error.empty()) {
    std::cerr << "ref-compare: error: " << r.error << "\n";
    return 2;
  }
  std::printf(
      "%s: blocks %d/%d pass (%.2f%%), worst |z| %.2f; means ours %.5g %.5g %.5g ref %.5g %.5g "
      "%.5g (%+.2f%% %+.2f%% %+.2f%%) -> %s\n",
      ref_path.c_str(), r.blocks_passed, r.blocks, 100.0 * r.blocks_passed / std::max(1, r.blocks),
      r.worst_z, r.mean_ours[0], r.mean_ours[1], r.mean_ours[2], r.mean_ref[0], r.mean_ref[1],
      r.mean_ref[2], 100 * r.mean_rel_error[0], 100 * r.mean_rel_error[1],
      100 * r.mean_rel_error[2], r.ok ? "CONVERGES" : "DIFFERS");
  if (!png.empty() && !rt::write_png(png, compare::side_by_side(a, b, ref), &error)) {
    std::cerr << "ref-compare: error: " << error << "\n";
    return 2;
  }
  return r.ok ? 0 : 1;
}
