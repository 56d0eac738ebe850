#include "runtime/render/render_job.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "runtime/core/clock.h"
#include "runtime/core/code_pages.h"
#include "runtime/film/atomic_file.h"
#include "runtime/film/error_estimate.h"
#include "runtime/film/film.h"
#include "runtime/film/image_io.h"
#include "runtime/film/render_state.h"
#include "runtime/render/camera.h"
#include "runtime/render/effects.h"
#include "runtime/render/integrator.h"
#include "runtime/render/mlt.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/sppm.h"
#include "runtime/render/stop_flags.h"
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

bool render_integrator(const RenderScene& scene, const Camera& camera, const Sampler& sampler,
                       const Integrator& integrator, Film* film, int spp_override, uint64_t seed,
                       bool quick, const RenderOptions& options, RenderStats* stats, long long* spp,
                       std::string* error, const RenderJobOptions* job) {
  const IntegratorSettings& settings = integrator.settings();
  if (settings.type == IntegratorType::kMlt) {
    MltSettings ms = mlt_settings(settings, spp_override, seed);
    if (quick && spp_override <= 0) {
      ms.mutations_per_pixel = std::max<int64_t>(1, ms.mutations_per_pixel / 16);
      ms.bootstrap_samples = std::max<int64_t>(1, ms.bootstrap_samples / 16);
    }
    *spp = ms.mutations_per_pixel;
    return render_mlt(scene, camera, film, ms, options, stats, error);
  }
  if (settings.type == IntegratorType::kSppm) {
    // pbrt-v3's --spp sets sppm's iteration count (one camera sample per pixel each).
    SppmSettings ss = sppm_settings(settings, spp_override, seed);
    if (quick && spp_override <= 0) ss.iterations = std::max(1, ss.iterations / 16);
    *spp = ss.iterations;
    *stats = render_sppm(scene, camera, film, ss, options);
    return true;
  }
  *stats = job && job->render_loop ? job->render_loop(camera, sampler, integrator, film, options)
                                   : render(camera, sampler, integrator, film, options);
  *spp = stats->samples_per_pixel;
  return true;
}

const char* stop_text(StopReason r) {
  switch (r) {
    case StopReason::kSamples:
      return "all samples rendered";
    case StopReason::kTargetError:
      return "target error reached";
    case StopReason::kTimeLimit:
      return "time limit";
    case StopReason::kInterrupted:
      return "interrupted";
    case StopReason::kError:
      return "failed";
  }
  return "";
}

bool render_archive(const pbrta::SceneArchive& archive, const RenderJobOptions& options,
                    RenderJobResult* result, std::string* error) {
  release_code_pages();  // starting the program and reading the archive: done
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
  if (options.write_files && !options.save_state.empty() &&
      !check_writable(options.save_state, "render state", error)) {
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
  release_code_pages();  // the loader's and the BVH builders' code: rendering runs none of it
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
  const bool passes_asked = options.first_sample > 0 || options.shards > 0 ||
                            options.target_error > 0 || options.time_limit > 0 ||
                            options.checkpoint_every > 0 || !options.save_state.empty() ||
                            !options.resume.empty() || options.error_layer;
  if (passes_asked &&
      (settings.type == IntegratorType::kMlt || settings.type == IntegratorType::kSppm)) {
    *error =
        "not supported yet: --target-error, --time-limit, --checkpoint-every, --save-state, "
        "--resume and --error-layer with the " +
        result->integrator + " integrator (it does not render in passes of samples)";
    return false;
  }

  // The image (and state) of what the film holds now: the checkpoints and the end.
  RenderState state_base;
  state_base.archive_id = archive.header().table_checksum;
  state_base.seed = options.seed;
  state_base.planned = spp;
  state_base.config = "integrator=" + result->integrator + " override=" + options.integrator +
                      " sampler=" + (options.sampler.empty() ? "scene" : options.sampler) +
                      " lightstrategy=" + settings.light_strategy + " spp=" + std::to_string(spp) +
                      " differentialspp=" + std::to_string(options.differential_spp) +
                      " watertight=" + std::to_string(options.watertight) +
                      " lightnsamplesdivisor=" + std::to_string(options.light_nsamples_divisor);
  if (!options.resume.empty()) {
    RenderState st;
    if (!read_render_state(options.resume, &st, error)) {
      *error = "error: " + *error;
      return false;
    }
    std::string why;
    if (st.archive_id != state_base.archive_id)
      why = "it was rendered from another archive";
    else if (st.config != state_base.config)
      why = "it was rendered with other settings (\"" + st.config + "\", this render \"" +
            state_base.config + "\")";
    else if (!st.resumable())
      why = "it is a merge of several renders, not one render to continue";
    else if (st.seed != options.seed)
      why = "it was rendered with --seed " + std::to_string(st.seed);
    else if (!restore_state(st, &film, &why)) {
    }
    if (!why.empty()) {
      *error = "error: " + options.resume + ": cannot resume: " + why;
      return false;
    }
    ro.first_sample = st.end;
  } else if (options.shards > 0) {
    if (options.shard < 0 || options.shard >= options.shards || options.shards > spp) {
      *error = "error: shard " + std::to_string(options.shard + 1) + "/" +
               std::to_string(options.shards) + " of " + std::to_string(spp) +
               " samples per pixel: give 1 <= K <= N <= the sample count";
      return false;
    }
    ro.first_sample = spp * options.shard / options.shards;
    ro.end_sample = spp * (options.shard + 1) / options.shards;
  } else {
    ro.first_sample = std::min<int64_t>(options.first_sample, spp);
  }
  const int64_t range_first = options.resume.empty() ? ro.first_sample : 0;
  const bool pass_render =
      settings.type != IntegratorType::kMlt && settings.type != IntegratorType::kSppm;
  auto write_outputs = [&](std::string* err) {
    // Interrupted before the first pass: nothing to write.
    if (!options.write_files || (pass_render && film.sample_count() == 0)) return true;
    ImageRgb image = film.image();
    if (options.error_layer) {
      image.layer = "error";
      estimate_error(film, &image.layer_rgb);
    }
    for (const std::string* path : {static_cast<const std::string*>(&out), &options.preview})
      if (!path->empty() && !write_image(*path, image, err)) return false;
    if (!options.save_state.empty()) {
      RenderState st = capture_state(film);
      st.archive_id = state_base.archive_id;
      st.seed = state_base.seed;
      st.planned = state_base.planned;
      st.config = state_base.config;
      st.first = range_first;
      st.end = range_first + film.sample_count();
      if (!write_render_state(options.save_state, st, err)) return false;
    }
    return true;
  };

  ro.target_error = options.target_error;
  ro.time_limit = options.time_limit;
  ro.time_spent = seconds_since(options.time_origin);
  ro.checkpoint_every = options.checkpoint_every;
  ro.checkpoint = write_outputs;
  ro.interrupt = options.interrupt;
  // A state names the samples every pixel holds: only whole passes.
  ro.whole_passes_only = !options.save_state.empty();
  ro.on_pass = options.on_pass;
  if (!render_integrator(scene, camera, *sampler, integrator, &film, options.spp, options.seed,
                         options.quick, ro, &result->render, &spp, error, &options))
    return false;
  if (result->render.stop == StopReason::kError) {
    *error = "error: " + result->render.error;
    return false;
  }

  if (options.keep_image) result->image = film.image();
  release_code_pages();  // the renderer's: writing the image runs other code
  if (!write_outputs(error)) {
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
  const RenderStats& rs = result->render;
  if (!options.quiet && rs.has_error_estimate)
    std::cerr << options.program << ": estimated error " << error_percent(rs.error_estimate)
              << " after " << rs.samples_per_pixel << " samples per pixel (" << stop_text(rs.stop)
              << ")\n";
  if (rs.stop == StopReason::kInterrupted) {
    result->interrupted = true;
    *error = rs.samples_per_pixel == 0
                 ? "interrupted before the first pass ended: no image written (stratified, "
                   "02sequence and maxmindist render in one pass unless --checkpoint-every, "
                   "--target-error or --time-limit is given)"
                 : "interrupted: wrote the image of the " + std::to_string(rs.samples_per_pixel) +
                       " samples per pixel done" +
                       (ro.whole_passes_only ? "" : " (and the tiles the last pass finished)") +
                       " to " + out;
    return false;
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
      "placed in the world; %u meshes copied)\n"
      "  load archive           %.3f s\n"
      "  build scene            %.3f s (Embree %.3f s, %.1f MiB)\n"
      "  time to first pixels   %.3f s\n"
      "  render                 %.3f s (%.3g samples/s)\n"
      "  rays                   %llu camera, %llu intersection, %llu shadow\n"
      "  non-finite samples     %llu\n"
      "  threads                %d\n"
      "  peak memory            %.1f MiB\n",
      input.c_str(), r.effects.c_str(), r.integrator.c_str(), r.max_depth, r.samples_per_pixel,
      gs.triangles, gs.quadrics, gs.curves, gs.instances, gs.placed_instances, gs.copied_meshes,
      archive_seconds, r.build_seconds, gs.build_seconds, double(gs.embree_bytes) / (1 << 20),
      archive_seconds + r.setup_seconds + rs.first_tile_seconds, rs.seconds,
      rs.seconds > 0 ? double(rs.samples) / rs.seconds : 0.0, (unsigned long long)rs.camera_rays,
      (unsigned long long)rs.rays, (unsigned long long)rs.shadow_rays,
      (unsigned long long)rs.nonfinite_samples, threads, peak_memory_mib);
  std::string out = buf;
  if (gs.listed == 0) {
    out += "  traversal              Embree's tree\n";
  } else {
    std::snprintf(buf, sizeof buf, "  traversal              %u primitives tested each, %s\n",
                  gs.listed,
                  gs.listed == gs.triangles + gs.quadrics ? "no tree (a small scene)"
                                                          : "the rest in Embree's tree");
    out += buf;
  }
  if (gs.sampled_motions > 0) {
    std::snprintf(buf, sizeof buf,
                  "  motion time steps      %u moving meshes or instances sampled (shear, or "
                  "inside objects)\n",
                  gs.sampled_motions);
    out += buf;
  }
  if (rs.passes > 0) {
    std::snprintf(buf, sizeof buf, "  passes                 %d (%s)%s\n", rs.passes,
                  stop_text(rs.stop), rs.checkpoints ? ", with checkpoints" : "");
    out += buf;
  }
  if (rs.has_error_estimate) {
    std::snprintf(buf, sizeof buf,
                  "  estimated error        %s (relative RMS, from the half images)\n",
                  error_percent(rs.error_estimate).c_str());
    out += buf;
  }
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

double peak_memory_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

int failed_render_status(const RenderJobResult& r, bool quiet, bool* print) {
  *print = !(r.interrupted && quiet);
  if (r.interrupted) return 128 + interrupt_signal();
  return r.bad_output ? 2 : 1;
}

}  // namespace rt
