// runtime/render/render_job.h — one whole render of a loaded archive, start to file.
//
// render_archive() is the sequence pbrtrun and pbrt both run once the archive is
// loaded: film (with resolution divisor and crop), output-path check, camera,
// integrator settings, the render scene (Embree), sampler (with spp override and
// seed), integrator preprocess, the tile-parallel render, and the EXR (and
// optional PNG preview) written. Sharing it is what makes the two commands give
// the same pixels by construction. Scene warnings (media without a volume
// integrator, loader warnings) go to stderr unless quiet, as pbrtrun prints them.
//
// Failure: false with *error, and result->bad_output set when the cause is the
// output path (pbrtrun's exit code 2) rather than the scene ("not supported
// yet: ..." and the like, exit code 1). An interrupted render writes the image
// (and state) of the passes done, then returns false with result->interrupted.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "format/scene_archive.h"
#include "runtime/film/image_io.h"
#include "runtime/geometry/scene_geometry.h"
#include "runtime/medium/media.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/renderer.h"

namespace rt {

struct RenderJobOptions {
  std::string outfile;  // "" : the film's "filename", else pbrt.exr
  std::string preview;  // "" : none; else also an sRGB PNG here
  int spp = 0;          // > 0 replaces the scene's samples per pixel
  int resdiv = 1;       // film resolution divisor
  bool has_crop = false;
  float crop[4] = {0, 1, 0, 1};    // x0 x1 y0 y1, checked by the caller
  int light_nsamples_divisor = 1;  // pbrt --quick divides light "nsamples" by 4
  // pbrt --quick, as pbrt-v3 applies it where spp does not: 1 sample per pixel, sppm's
  // iterations and mlt's mutations per pixel and bootstrap samples divided by 16 (at least 1).
  bool quick = false;
  uint64_t seed = 0;
  bool quiet = false;
  bool watertight = false;  // SceneGeometry::set_watertight: close Embree's vertex cracks
  // > 0: scale camera ray differentials by 1/sqrt(this) instead of 1/sqrt(spp),
  // so a render averaged with others filters textures as the total would.
  int differential_spp = 0;
  std::string program = "pbrtrun";  // prefixes the non-finite sample note
  // Configuration overrides for tools that compare configurations (tools/accuracy):
  // "" keeps the scene's own. sampler: a make_sampler() type; integrator: a
  // read_integrator() type (the scene's maxdepth stays); light_strategy: the path
  // integrator's lightsamplestrategy (an error with any other integrator).
  std::string sampler, integrator, light_strategy;
  bool write_files = true;  // false: no EXR/PNG (outfile and preview unused)
  bool keep_image = false;  // result->image receives the film's pixels
  // Passes and stopping (renderer.h): target_error a fraction, time_limit and
  // checkpoint_every seconds (from time_origin), 0 for none. Checkpoints write the image
  // (and the state, with save_state) so far. error_layer adds the per-pixel error
  // estimate to the EXR as layer "error". save_state: the raw sums at the end (and at
  // checkpoints) to this file (render_state.h); resume: continue the render a state holds.
  // These need a sample-based integrator (not mlt or sppm).
  double target_error = 0, time_limit = 0, checkpoint_every = 0;
  std::chrono::steady_clock::time_point time_origin = std::chrono::steady_clock::now();
  bool error_layer = false;
  std::string save_state, resume;
  const std::atomic<bool>* interrupt = nullptr;  // set (SIGINT): stop, write what is done
  // > 0: render only the samples from this index on (a later part of the sequence, for a
  // state to merge with the earlier part's); not with resume.
  int64_t first_sample = 0;
  // shards > 0: render only the shard-th (0-based) of `shards` equal sample ranges of the
  // planned count (--shard K/N), for a state that pbrt-merge joins with the others'.
  int shard = 0, shards = 0;
  std::function<void(const Film&, int64_t, double)> on_pass;  // RenderOptions::on_pass
  // Replaces render() as the loop of the sample-based integrators (an MPI render's
  // processes: tools/mpi); called with everything built, as render() would be.
  std::function<RenderStats(const Camera&, const Sampler&, const Integrator&, Film*,
                            const RenderOptions&)>
      render_loop;
};

struct RenderJobResult {
  std::string outfile;     // the image written
  std::string effects;     // effect_names() of the scene
  std::string integrator;  // its type name
  int max_depth = 0;
  long long samples_per_pixel = 0;
  GeometryStats geometry;
  MediumStats media;  // empty unless the integrator simulates the scene's media
  RenderStats render;
  double build_seconds = 0;  // render scene, sampler and integrator
  double setup_seconds = 0;  // everything before the render loop (film through preprocess)
  bool bad_output = false;
  bool interrupted = false;  // stopped by options.interrupt; the files were written
  ImageRgb image;            // with options.keep_image
};

[[nodiscard]] bool render_archive(const pbrta::SceneArchive& archive,
                                  const RenderJobOptions& options, RenderJobResult* result,
                                  std::string* error);

// The render loop the integrator calls for, once film, camera, scene, sampler and integrator
// are built (and preprocess() ran): mlt and sppm render the whole image their own way (spp
// override: mutations per pixel, iterations), the others through render() in passes. quick:
// pbrt's --quick where the sample count does not reach (sppm iterations, mlt mutations and
// bootstrap / 16). *spp: the samples per pixel (or iterations, mutations) rendered.
[[nodiscard]] bool render_integrator(const RenderScene& scene, const Camera& camera,
                                     const Sampler& sampler, const Integrator& integrator,
                                     Film* film, int spp_override, uint64_t seed, bool quick,
                                     const RenderOptions& options, RenderStats* stats,
                                     long long* spp, std::string* error,
                                     const RenderJobOptions* job = nullptr);

const char* stop_text(StopReason r);  // "target error reached" and the like

// pbrtrun's --stats block for one render: `input` names the scene, archive_seconds is the
// time taken to load it, threads the thread count used.
std::string format_render_stats(const std::string& input, const RenderJobResult& r,
                                double archive_seconds, int threads, double peak_memory_mib);

// This process's peak resident memory in MiB, for --stats.
double peak_memory_mib();

// The exit status of a render_archive() that failed: 128 + the signal when SIGINT or SIGTERM
// stopped it (the image so far was written), 2 when an output could not be written, else 1.
// *print says whether to print its error: an interrupted render says nothing under --quiet.
int failed_render_status(const RenderJobResult& r, bool quiet, bool* print);

}  // namespace rt
