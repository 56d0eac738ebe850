// runtime/render/pbrtrun_main.cpp — pbrtrun: render a compiled scene archive.
//
//   pbrtrun scene.pbrta [--outfile x.exr] [--spp N] [--resdiv K]
//           [--cropwindow x0 x1 y0 y1] [--nthreads N] [--seed N] [--quiet] [--stats]
//
// Loads the archive (validated, no text parsing), builds Embree's scene and
// the integrator, renders with a progress bar and writes float32 OpenEXR (or
// an sRGB PNG preview for a .png name; --preview adds one beside the EXR).
// Anything the renderer cannot do yet stops before rendering with
// "not supported yet: <feature> (file:line)". Exit codes: 0 rendered,
// 1 bad archive or unsupported scene, 2 bad command line or output path.
#include <sys/resource.h>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/effects.h"
#include "runtime/render/integrator.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/renderer.h"
#include "runtime/sampler/sampler.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double peak_memory_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

int fail(const std::string& message, int code = 1) {
  std::cerr << "pbrtrun: " << message << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pbrtrun: render a pbrtc scene archive (.pbrta) to OpenEXR"};
  std::string input, outfile, preview;
  int spp = 0, resdiv = 1, nthreads = 0;
  uint64_t seed = 0;
  std::vector<float> crop;
  bool quiet = false, show_stats = false;
  app.add_option("archive", input, "The scene archive written by pbrtc")->required();
  app.add_option("-o,--outfile", outfile,
                 "Write the image to this file (.exr: float32 OpenEXR; .png: sRGB preview); "
                 "default: the film's filename");
  app.add_option("--preview", preview, "Also write an sRGB PNG preview to this file");
  app.add_option("--spp", spp, "Samples per pixel (overrides the scene's sampler)")
      ->check(CLI::PositiveNumber);
  app.add_option("--resdiv", resdiv, "Divide the film resolution by this integer")
      ->check(CLI::PositiveNumber);
  app.add_option("--cropwindow", crop, "Render only this part of the image: x0 x1 y0 y1 in [0,1]")
      ->expected(4);
  app.add_option("--nthreads", nthreads, "Threads to render with (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", seed, "Seed for every random choice (same seed, same image)");
  app.add_flag("-q,--quiet", quiet, "No progress bar or messages");
  app.add_flag("--stats", show_stats,
               "Print the effects simulated, rays traced, load/build/render times and peak memory");
  CLI11_PARSE(app, argc, argv);

  if (!crop.empty() && (crop[0] < 0 || crop[1] > 1 || crop[2] < 0 || crop[3] > 1 ||
                        crop[0] >= crop[1] || crop[2] >= crop[3]))
    return fail("error: --cropwindow needs 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1", 2);
  int threads = nthreads > 0 ? nthreads : int(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  auto t_start = std::chrono::steady_clock::now();

  pbrta::SceneArchive archive;
  std::string error;
  if (!archive.load(input, threads, &error)) return fail("error: " + error);
  double t_archive = seconds_since(t_start);

  rt::FilmOptions film_options;
  film_options.resdiv = resdiv;
  if (!crop.empty()) {
    film_options.has_crop = true;
    for (int i = 0; i < 4; ++i) film_options.crop[i] = crop[i];
  }
  rt::Film film;
  if (!film.build(archive, film_options, &error)) return fail(error);
  std::string out = outfile.empty() ? film.filename() : outfile;
  if (out.empty()) out = "pbrt.exr";
  if (!rt::check_output_path(out, &error)) return fail("error: " + error, 2);
  if (!preview.empty() && !rt::check_output_path(preview, &error))
    return fail("error: " + error, 2);

  rt::Camera camera;
  if (!camera.build(archive, film.full_resolution(), &error)) return fail(error);
  rt::IntegratorSettings settings;
  if (!rt::read_integrator(archive, &settings, &error)) return fail(error);

  auto t_build = std::chrono::steady_clock::now();
  rt::RenderScene scene;
  std::string warnings;
  if (!rt::load_render_scene(archive, &scene, &warnings, &error)) return fail(error);
  if ((scene.effects & pbrta::kEffectMedia) && !quiet)
    std::cerr << "Warning: Scene has scattering media but \""
              << archive.type_name(archive.scene().integrator)
              << "\" integrator doesn't support volume scattering. Consider using \"volpath\", "
                 "\"bdpt\", or \"mlt\".\n";
  if (!warnings.empty() && !quiet) std::cerr << warnings;

  std::unique_ptr<rt::Sampler> sampler =
      rt::make_sampler(archive, spp, seed, film.sample_bounds(), &error);
  if (!sampler) return fail(error);
  rt::Integrator integrator;
  if (!integrator.init(scene, settings, &error)) return fail(error);
  integrator.preprocess(sampler.get());
  double t_built = seconds_since(t_build);
  double t_to_render = seconds_since(t_start);

  rt::RenderOptions ro;
  ro.quiet = quiet;
  rt::RenderStats rs = rt::render(camera, *sampler, integrator, &film, ro);

  if (!film.write(out, &error)) return fail("error: " + error);
  if (!preview.empty() && !film.write(preview, &error)) return fail("error: " + error);
  if (rs.nonfinite_samples > 0)
    std::cerr << "pbrtrun: " << rs.nonfinite_samples
              << " samples had NaN or infinite radiance; they were counted as black\n";
  if (show_stats) {
    const rt::GeometryStats& gs = scene.geometry.stats();
    std::fprintf(stderr,
                 "pbrtrun statistics for %s\n"
                 "  effects simulated      %s\n"
                 "  integrator             %s (maxdepth %d)\n"
                 "  samples per pixel      %lld\n"
                 "  shapes                 %u triangles, %u quadrics, %u instances (%u meshes "
                 "copied)\n"
                 "  load archive           %.3f s\n"
                 "  build scene            %.3f s (Embree %.3f s, %.1f MiB)\n"
                 "  time to first pixels   %.3f s\n"
                 "  render                 %.3f s (%.3g samples/s)\n"
                 "  rays                   %llu camera, %llu intersection, %llu shadow\n"
                 "  non-finite samples     %llu\n"
                 "  threads                %d\n"
                 "  peak memory            %.1f MiB\n",
                 input.c_str(), rt::effect_names(scene.effects).c_str(),
                 std::string(archive.type_name(archive.scene().integrator)).c_str(),
                 settings.max_depth, (long long)sampler->samples_per_pixel(), gs.triangles,
                 gs.quadrics, gs.instances, gs.copied_meshes, t_archive, t_built, gs.build_seconds,
                 double(gs.embree_bytes) / (1 << 20), t_to_render + rs.first_tile_seconds,
                 rs.seconds, rs.seconds > 0 ? double(rs.samples) / rs.seconds : 0.0,
                 (unsigned long long)rs.camera_rays, (unsigned long long)rs.rays,
                 (unsigned long long)rs.shadow_rays, (unsigned long long)rs.nonfinite_samples,
                 threads, peak_memory_mib());
  }
  return 0;
}
