// runtime/film/render_state.h — a render's raw sums in a file: save, resume, merge.
//
// A render state is everything a film has accumulated, before any division: per
// cropped pixel and per half (the two halves of its samples, film.h) the filter-
// weighted RGB sums and weight sums, and the committed splats; with them the samples
// per pixel of each half, the sample range rendered, the seed, the archive's identity
// (its section-table checksum, ARCHIVE.md) and the film's windows. Resuming loads it
// into the film and renders on from `end`; merging adds the sums of renders of the
// same archive and film made with different seeds or disjoint sample ranges, so the
// merged image is the image of all their samples (up to the order of float additions).
//
// File layout (little-endian; a stranger can write a reader from this):
//
//   offset  size  field
//   0       8     magic "PBRTRST1"
//   8       4     u32 version, 1
//   12      4     u32 flags: bit 0 = splats present
//   16      8     u64 archive identity: the archive header's table_checksum
//   24      8     u64 seed (of the first render merged in)
//   32      8     i64 samples per pixel in half 0
//   40      8     i64 samples per pixel in half 1
//   48      8     i64 first sample index rendered (-1: several ranges, after a merge)
//   56      8     i64 end of the sample range (exclusive; -1 likewise)
//   64      8     i64 planned samples per pixel (the sampler's count)
//   72      8     f64 the film's "scale" (applied to the sums' image)
//   80      8     i32 x 2: full resolution
//   88      16    i32 x 4: cropped pixel bounds min x, min y, max x, max y (max exclusive)
//   104     4     u32 n: length of the configuration text
//   108     n     configuration text (integrator, sampler, overrides; must match to merge)
//   ...     A     per half (0, then 1), per pixel in row order: f64 r, g, b, weight
//                 (A = 2 * 32 * pixels bytes)
//   ...     S     with splats, per half, per pixel: f64 r, g, b (S = 2 * 24 * pixels)
//   end-8   8     u64 XXH3-64 (seed 0) of every byte before it
//
// A pixel's value is, as Film::pixel computes it: max(0, (sum0 + sum1) / (weight0 +
// weight1)) (0 when the weights are 0) plus (splat0 + splat1) / samples, times scale.
//
// Files are written to a temporary name and renamed, so a reader sees the old state
// or the new one, never half of one. Every failure is false with a message naming
// the file and what is wrong.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/film/film.h"

namespace rt {

struct RenderState {
  uint64_t archive_id = 0, seed = 0;
  int64_t half_samples[2] = {0, 0};
  int64_t first = 0, end = 0;  // -1 after a merge of ranges that do not join
  int64_t planned = 0;
  double scale = 1;
  Point2i full_resolution;
  Bounds2i cropped;
  std::string config;
  std::vector<FilmPixelSum> sums[2];
  std::vector<double> splats[2];  // empty without splats

  int64_t samples() const { return half_samples[0] + half_samples[1]; }
  bool resumable() const { return first == 0 && end >= 0; }
};

// The film's sums as a state (the caller fills archive_id, seed, first, end, planned,
// config).
RenderState capture_state(const Film& film);
// A film that holds the state's sums and nothing else (no filter): for its image and
// error estimate (pbrt-merge).
[[nodiscard]] bool film_of_state(const RenderState& state, Film* film, std::string* error);
// Loads a state's sums into a film of the same windows (and splats, when the state has
// them); false with a message otherwise.
[[nodiscard]] bool restore_state(const RenderState& state, Film* film, std::string* error);

[[nodiscard]] bool write_render_state(const std::string& path, const RenderState& state,
                                      std::string* error);
[[nodiscard]] bool read_render_state(const std::string& path, RenderState* state,
                                     std::string* error);

// Adds `from` (read from from_name, for messages) into `into`: refused for another
// archive, another film or configuration, or the same seed over overlapping samples.
[[nodiscard]] bool merge_state(RenderState* into, const RenderState& from,
                               const std::string& from_name, std::string* error);

}  // namespace rt
