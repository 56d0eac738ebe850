// tools/compare/ref_compare_main.cpp — ref-compare: the convergence test on three EXR files.
//
//   ref-compare A.exr B.exr reference.exr [--png side-by-side.png]
//               [--spp N --reference-spp M]
//
// A and B are renders at half the reference's spp with different seeds (or,
// with --spp and --reference-spp, at N/2 each against a reference of M).
// Prints the block statistics and exits 0 when the render converges to the
// reference (tools/compare/convergence.h has the rule), 1 when it does not,
// 2 when the images cannot be read or compared.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

#include "tools/compare/convergence.h"

int main(int argc, char** argv) {
  CLI::App app{"ref-compare: does a render converge to a pbrt-v3 reference?"};
  std::string a_path, b_path, ref_path, png;
  app.add_option("a", a_path, "Render A (half the reference's spp, seed 1)")->required();
  app.add_option("b", b_path, "Render B (half the reference's spp, another seed)")->required();
  app.add_option("reference", ref_path, "The reference EXR")->required();
  app.add_option("--png", png, "Write ours | reference | signed difference here");
  int spp = 0, ref_spp = 0;
  app.add_option("--spp", spp, "Samples per pixel of A and B together (default: the reference's)")
      ->check(CLI::PositiveNumber);
  app.add_option("--reference-spp", ref_spp, "Samples per pixel of the reference")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  rt::ImageRgb a, b, ref;
  std::string error;
  for (auto [path, img] : {std::pair{&a_path, &a}, {&b_path, &b}, {&ref_path, &ref}})
    if (!rt::read_exr(*path, img, &error)) {
      std::cerr << "ref-compare: error: " << error << "\n";
      return 2;
    }
  if ((spp > 0) != (ref_spp > 0)) {
    std::cerr << "ref-compare: error: --spp and --reference-spp go together\n";
    return 2;
  }
  const double spp_ratio = spp > 0 ? double(spp) / ref_spp : 1;
  compare::ConvergenceResult r = compare::check_convergence(a, b, ref, spp_ratio);
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
