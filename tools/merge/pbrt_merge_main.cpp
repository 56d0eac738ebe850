// tools/merge/pbrt_merge_main.cpp — pbrt-merge: join render states into one image.
//
//   pbrt-merge a.state b.state ... -o out.exr [--preview out.png] [--error-layer]
//              [--save-state merged.state] [-q]
//
// Adds the raw sums of states written by pbrtrun/pbrt --save-state (render_state.h)
// from renders of one archive and film with different seeds, or disjoint sample
// ranges, and writes the image of all their samples with its error estimate
// (error_estimate.h). States of another archive, resolution, crop or configuration,
// or the same seed over the same samples, are refused naming the file. Exit codes: 0
// merged, 1 a state is unreadable or cannot be merged, 2 bad command line or output.
#include <CLI/CLI.hpp>

#include <iostream>
#include <string>
#include <vector>

#include "runtime/film/error_estimate.h"
#include "runtime/film/film.h"
#include "runtime/film/image_io.h"
#include "runtime/film/render_state.h"
#include "runtime/render/render_job.h"

int main(int argc, char** argv) {
  CLI::App app{"pbrt-merge: add render states (--save-state) of one scene into one image"};
  std::vector<std::string> inputs;
  std::string outfile, preview, save_state;
  bool error_layer = false, quiet = false;
  app.add_option("states", inputs, "State files written with --save-state")->required();
  app.add_option("-o,--outfile", outfile, "The merged image (.exr or .png)")->required();
  app.add_option("--preview", preview, "Also write an sRGB PNG preview here");
  app.add_flag("--error-layer", error_layer, "Add the per-pixel error estimate as layer \"error\"");
  app.add_option("--save-state", save_state, "Also write the merged state here");
  app.add_flag("-q,--quiet", quiet, "Print nothing but errors");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  for (const std::string* path : {&outfile, &preview})
    if (!path->empty() && !rt::check_output_path(*path, &error)) {
      std::cerr << "pbrt-merge: error: " << error << "\n";
      return 2;
    }
  rt::RenderState merged;
  for (size_t i = 0; i < inputs.size(); ++i) {
    rt::RenderState s;
    if (!rt::read_render_state(inputs[i], i == 0 ? &merged : &s, &error) ||
        (i > 0 && !rt::merge_state(&merged, s, inputs[i], &error))) {
      std::cerr << "pbrt-merge: error: " << error << "\n";
      return 1;
    }
  }
  rt::Film film;
  if (!rt::film_of_state(merged, &film, &error)) {
    std::cerr << "pbrt-merge: error: " << error << "\n";
    return 1;
  }
  rt::ImageRgb image = film.image();
  const rt::ErrorEstimate e = rt::estimate_error(film, error_layer ? &image.layer_rgb : nullptr);
  if (error_layer) image.layer = "error";
  for (const std::string* path : {&outfile, &preview})
    if (!path->empty() && !rt::write_image(*path, image, &error)) {
      std::cerr << "pbrt-merge: error: " << error << "\n";
      return 2;
    }
  if (!save_state.empty() && !rt::write_render_state(save_state, merged, &error)) {
    std::cerr << "pbrt-merge: error: " << error << "\n";
    return 2;
  }
  if (!quiet) {
    std::cerr << "pbrt-merge: " << inputs.size() << (inputs.size() == 1 ? " state, " : " states, ")
              << merged.samples() << " samples per pixel";
    if (e.valid) std::cerr << ", estimated error " << rt::error_percent(e.rel_error);
    std::cerr << "\n";
  }
  return 0;
}
