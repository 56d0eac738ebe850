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
// yet: ..." and the like, exit code 1).
#pragma once

#include <cstdint>
#include <string>

#include "format/scene_archive.h"
#include "runtime/film/image_io.h"
#include "runtime/geometry/scene_geometry.h"
#include "runtime/medium/media.h"
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
  ImageRgb image;  // with options.keep_image
};

[[nodiscard]] bool render_archive(const pbrta::SceneArchive& archive,
                                  const RenderJobOptions& options, RenderJobResult* result,
                                  std::string* error);

// pbrtrun's --stats block for one render: `input` names the scene, archive_seconds is the
// time taken to load it, threads the thread count used.
std::string format_render_stats(const std::string& input, const RenderJobResult& r,
                                double archive_seconds, int threads, double peak_memory_mib);

}  // namespace rt
