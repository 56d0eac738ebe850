#include "runtime/render/render_job.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "runtime/core/clock.h"
#include "runtime/film/film.h"
#include "runtime/film/image_io.h"
#include "runtime/render/camera.h"
#include "runtime/render/effects.h"
#include "runtime/render/integrator.h"
#include "runtime/render/mlt.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/sppm.h"
#include "runtime/sampler/sampler.h"

namespace rt {

namespace {

// The integrator and light-strategy overrides of RenderJobOptions, on top of
// the scene's settings (so its maxdepth stays).
bool apply_overrides(const RenderJobOptions& o, IntegratorSettings* s, std::string* error) {
  if (!o.integrator.empty()) {
    static const struct {
      const char* name;
      IntegratorType type;
    } kTypes[] = {{"whitted", IntegratorType::kWhitted},
                  {"directlighting", IntegratorType::kDirectLighting},
                  {"path", IntegratorType::kPath},
                  {"volpath", IntegratorType::kVolPath},
                  {"ambientocclusion", IntegratorType::kAmbientOcclusion},
                  {"bdpt", IntegratorType::kBdpt},
                  {"mlt", IntegratorType::kMlt}};
    bool found = false;
    for (const auto& t : kTypes)
      if (o.integrator == t.name) {
        // Each integrator's own default light strategy (pbrt-v3: spatial for path, power for
        // bdpt) unless the scene's integrator was already that one.
        if (t.type != s->type)
          s->light_strategy = t.type == IntegratorType::kBdpt ? "power" : "spatial";
        s->type = t.type;
        found = true;
      }
    if (!found) {
      *error = "not supported yet: " + o.integrator + " integrator (override)";
      return false;
    }
  }
  if (!o.light_strategy.empty()) {
    if (s->type != IntegratorType::kPath && s->type != IntegratorType::kVolPath &&
        s->type != IntegratorType::kBdpt) {
      *error = "error: light strategy \"" + o.light_strategy +
               "\" given, but only the path, volpath and bdpt integrators sample lights by a "
               "strategy";
      return false;
    }
    s->light_strategy = o.light_strategy;
  }
  return true;
}

}  // namespace

bool render_archive(const pbrta::SceneArchive& archive, const RenderJobOptions& options,
                    RenderJobResult* result, std::string* error) {
  auto t_start = std::chrono::steady_clock::now();
  FilmOptions film_options;
  film_options.resdiv = options.resdiv;
  if (options.has_crop) {
    film_options.has_crop = true;
    for (int i = 0; i < 4; ++i) film_options.crop[i] = options.crop[i];
  }
  Film film;
  if (!film.build(archive, film_options, error)) return false;
  std::string out = options.outfile.empty() ? film.filename() : options.outfile;
  if (out.empty()) out = "pbrt.exr";
  result->outfile = out;
  for (const std::string* path : {static_cast<const std::string*>(&out), &options.preview}) {
    if (!options.write_files || path->empty() || check_output_path(*path, error)) continue;
    *error = "error: " + *error;
    result->bad_output = true;
    return false;
  }

  Camera camera;
  camera.set_sample_bounds(film.sample_bounds());
  if (!camera.build(archive, film.full_resolution(), error)) return false;
  IntegratorSettings settings;
  if (!read_integrator(archive, &settings, error)) return false;
  settings.light_nsamples_divisor = options.light_nsamples_divisor;
  if (!apply_overrides(options, &settings, error)) return false;

  auto t_build = std::chrono::steady_clock::now();
  RenderScene scene;
  scene.geometry.set_watertight(options.watertight);
  if (!load_render_scene(archive, &scene, error)) return false;
  result->integrator = std::string(archive.type_name(archive.scene().integrator));
  const bool media_ignored =
      (scene.effects & pbrta::kEffectMedia) && !simulates_media(settings.type);
  if (media_ignored && !options.quiet)
    std::cerr << "Warning: Scene has scattering media but \"" << result->integrator
              << "\" integrator doesn't support volume scattering. Consider using \"volpath\", "
                 "\"bdpt\", or \"mlt\".\n";

  const int sampler_spp = options.spp > 0 ? options.spp : options.quick ? 1 : 0;
  std::unique_ptr<Sampler> sampler = make_sampler(archive, sampler_spp, options.seed,
                                                  film.sample_bounds(), error, options.sampler);
  if (!sampler) return false;
  Integrator integrator;
  if (!integrator.init(scene, settings, error, &camera, &film)) return false;
  integrator.preprocess(sampler.get());
  result->build_seconds = seconds_since(t_build);
  result->setup_seconds = seconds_since(t_start);

  RenderOptions ro;
  ro.quiet = options.quiet;
  ro.differential_spp = options.differential_spp;
  long long spp = (long long)sampler->samples_per_pixel();
  if (settings.type == IntegratorType::kMlt) {
    MltSettings ms = mlt_settings(settings, options.spp, options.seed);
    if (options.quick && options.spp <= 0) {
      ms.mutations_per_pixel = std::max<int64_t>(1, ms.mutations_per_pixel / 16);
      ms.bootstrap_samples = std::max<int64_t>(1, ms.bootstrap_samples / 16);
    }
    spp = ms.mutations_per_pixel;
    if (!render_mlt(scene, camera, &film, ms, ro, &result->render, error)) return false;
  } else if (settings.type == IntegratorType::kSppm) {
    // pbrt-v3's --spp sets sppm's iteration count (one camera sample per pixel each).
    SppmSettings ss = sppm_settings(settings, options.spp, options.seed);
    if (options.quick && options.spp <= 0) ss.iterations = std::max(1, ss.iterations / 16);
    spp = ss.iterations;
    result->render = render_sppm(scene, camera, &film, ss, ro);
  } else {
    result->render = render(camera, *sampler, integrator, &film, ro);
  }

  if (options.keep_image) result->image = film.image();
  for (const std::string* path : {static_cast<const std::string*>(&out), &options.preview}) {
    if (!options.write_files || path->empty() || film.write(*path, error)) continue;
    *error = "error: " + *error;
    return false;
  }
  // bdpt's strategy images go beside the image, named as pbrt-v3 names them.
  if (options.write_files) {
    const size_t slash = out.find_last_of('/');
    if (!integrator.write_extra_images(slash == std::string::npos ? "" : out.substr(0, slash),
                                       error)) {
      *error = "error: " + *error;
      return false;
    }
  }
  if (result->render.nonfinite_samples > 0)
    std::cerr << options.program << ": " << result->render.nonfinite_samples
              << " samples had NaN or infinite radiance; they were counted as black\n";
  result->effects =
      effect_names(media_ignored ? scene.effects & ~pbrta::kEffectMedia : scene.effects);
  if (!media_ignored) result->media = scene.media.stats();
  result->max_depth = settings.max_depth;
  result->samples_per_pixel = spp;
  result->geometry = scene.geometry.stats();
  return true;
}

std::string format_render_stats(const std::string& input, const RenderJobResult& r,
                                double archive_seconds, int threads, double peak_memory_mib) {
  const GeometryStats& gs = r.geometry;
  const RenderStats& rs = r.render;
  char buf[2048];
  std::snprintf(
      buf, sizeof buf,
      "pbrtrun statistics for %s\n"
      "  effects simulated      %s\n"
      "  integrator             %s (maxdepth %d)\n"
      "  samples per pixel      %lld\n"
      "  shapes                 %u triangles, %u quadrics, %u curve pieces, %u instances (%u "
      "meshes copied)\n"
      "  load archive           %.3f s\n"
      "  build scene            %.3f s (Embree %.3f s, %.1f MiB)\n"
      "  time to first pixels   %.3f s\n"
      "  render                 %.3f s (%.3g samples/s)\n"
      "  rays                   %llu camera, %llu intersection, %llu shadow\n"
      "  non-finite samples     %llu\n"
      "  threads                %d\n"
      "  peak memory            %.1f MiB\n",
      input.c_str(), r.effects.c_str(), r.integrator.c_str(), r.max_depth, r.samples_per_pixel,
      gs.triangles, gs.quadrics, gs.curves, gs.instances, gs.copied_meshes, archive_seconds,
      r.build_seconds, gs.build_seconds, double(gs.embree_bytes) / (1 << 20),
      archive_seconds + r.setup_seconds + rs.first_tile_seconds, rs.seconds,
      rs.seconds > 0 ? double(rs.samples) / rs.seconds : 0.0, (unsigned long long)rs.camera_rays,
      (unsigned long long)rs.rays, (unsigned long long)rs.shadow_rays,
      (unsigned long long)rs.nonfinite_samples, threads, peak_memory_mib);
  std::string out = buf;
  if (rs.paths > 0) {
    std::snprintf(buf, sizeof buf,
                  "  strategies joined      %llu (s, t) paths, %.1f%% with no radiance\n",
                  (unsigned long long)rs.paths, 100.0 * double(rs.zero_radiance_paths) / rs.paths);
    out += buf;
  }
  if (rs.mutations > 0) {
    std::snprintf(buf, sizeof buf, "  mutations              %llu, %.1f%% accepted\n",
                  (unsigned long long)rs.mutations, 100.0 * double(rs.accepted) / rs.mutations);
    out += buf;
  }
  if (rs.iterations > 0) {
    std::snprintf(buf, sizeof buf, "  photons                %llu in %llu iterations\n",
                  (unsigned long long)rs.photons, (unsigned long long)rs.iterations);
    out += buf;
  }
  if (r.media.homogeneous + r.media.grids > 0) {
    std::snprintf(buf, sizeof buf,
                  "  media                  %u homogeneous, %u density grids (%llu majorant "
                  "cells)\n",
                  r.media.homogeneous, r.media.grids, (unsigned long long)r.media.grid_cells);
    out += buf;
  }
  return out;
}

}  // namespace rt
