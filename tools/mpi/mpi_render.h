// tools/mpi/mpi_render.h — one image rendered by the processes of an MPI job.
//
// Every rank builds the same scene, film, camera, sampler and integrator (render_job.h);
// rank 0 runs the pass loop (renderer.h: stopping rules, error estimate, checkpoints,
// states, files) and, for each pass, hands out tiles on request: a rank asks for twice
// as many tiles as it has threads and gets that many consecutive tiles (so fast and slow
// ranks finish a pass together), sends their sums back and asks again; each rank keeps
// three requests open, so its next tiles are there when it is done. Rank 0 renders tiles
// too, one per thread between answering requests, and keeps a pass's last tiles to
// itself once the others hold as many. When every tile of a pass is back, the ranks add
// their pending splats (bdpt) to rank 0's with one MPI_Reduce, and rank 0 merges the
// tiles in tile order: the image of a given seed is the single-process image, bit for
// bit (splats aside, which are summed in another order). At the end the ranks' counters
// are summed into rank 0's statistics.
//
// Messages (tags below), all between rank 0 and one other rank:
//   kAsk     r -> 0  int32 tiles wanted (2 x threads) (ready for tiles; three outstanding)
//   kTiles   0 -> r  int64 first, last; int32 begin, end   (render these tiles of a pass)
//   kSums    r -> 0  int32 begin, end; then per tile, half 0 then 1, the FilmPixelSums
//                    of its pixel bounds (4 doubles each); then the rank asks again
//   kPassEnd 0 -> r  int32 keep (1: the pass is whole; 0: abandoned)   then the splat reduce
//   kStop    0 -> r  (no more passes)                                  then the counter reduce
// A rank that dies takes the job with it (MPI's default error handler): rank 0's
// checkpoints (--checkpoint-every with --save-state) are what a rerun --resumes from.
#pragma once

#include <mpi.h>

#include "runtime/render/render_job.h"

namespace mpi_render {

enum Tag : int { kAsk = 1, kTiles, kSums, kPassEnd, kStop };

// Test hook: this rank sleeps this long after each tile (a slow node).
struct Slowdown {
  int rank = -1;
  double seconds_per_tile = 0;
};

// rank 0's render loop (RenderJobOptions::render_loop), for a job of `size` ranks.
rt::RenderStats lead(const rt::Camera& camera, const rt::Sampler& sampler,
                     const rt::Integrator& integrator, rt::Film* film,
                     const rt::RenderOptions& options, int size, int threads, const Slowdown& slow);

// Every other rank's render loop: serves rank 0 until it says stop.
rt::RenderStats follow(const rt::Camera& camera, const rt::Sampler& sampler,
                       const rt::Integrator& integrator, rt::Film* film,
                       const rt::RenderOptions& options, int rank, int threads,
                       const Slowdown& slow);

}  // namespace mpi_render
