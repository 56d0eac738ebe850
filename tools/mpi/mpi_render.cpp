// tools/mpi/mpi_render.cpp — see mpi_render.h.
#include "tools/mpi/mpi_render.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>
#include <thread>
#include <vector>

#include "runtime/render/renderer.h"
#include "runtime/render/tile_renderer.h"

namespace mpi_render {
namespace {

constexpr int kCounters = 7;

void get_counters(const rt::RenderStats& s, uint64_t out[kCounters]) {
  const uint64_t v[kCounters] = {
      s.samples, s.nonfinite_samples,  s.camera_rays, s.rays, s.shadow_rays,
      s.paths,   s.zero_radiance_paths};
  std::memcpy(out, v, sizeof v);
}

void add_counters(const uint64_t in[kCounters], rt::RenderStats* s) {
  s->samples += in[0];
  s->nonfinite_samples += in[1];
  s->camera_rays += in[2];
  s->rays += in[3];
  s->shadow_rays += in[4];
  s->paths += in[5];
  s->zero_radiance_paths += in[6];
}

void slow_down(const Slowdown& slow, int rank, int tiles) {
  if (slow.rank == rank && slow.seconds_per_tile > 0)
    std::this_thread::sleep_for(std::chrono::duration<double>(slow.seconds_per_tile * tiles));
}

// Every process's pending splats added into rank 0's (a collective call).
void reduce_splats(rt::Film* film, int rank, bool keep) {
  if (!film->has_splats()) return;
  std::vector<double> v = film->pending_splats();
  if (rank == 0) {
    MPI_Reduce(MPI_IN_PLACE, v.data(), int(v.size()), MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    if (keep) film->set_pending_splats(v);
  } else {
    MPI_Reduce(v.data(), nullptr, int(v.size()), MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    film->discard_splats();
  }
}

}  // namespace

rt::RenderStats lead(const rt::Camera& camera, const rt::Sampler& sampler,
                     const rt::Integrator& integrator, rt::Film* film,
                     const rt::RenderOptions& options, int size, int threads,
                     const Slowdown& slow) {
  rt::TileRenderer tiles(camera, sampler, integrator, film, options.differential_spp);
  film->keep_pass_splats_apart();  // each pass's splats are summed over the ranks
  const int ntiles = tiles.tile_count();
  // Per rank: the tiles it asks for at a time, and how many of its asks are unanswered.
  std::vector<int> chunk(size_t(size), 1), asks(size_t(size), 0);
  auto interrupted = [&] {
    return options.interrupt && options.interrupt->load(std::memory_order_relaxed);
  };
  std::vector<char> buffer;

  auto pass = [&](int64_t first, int64_t last, rt::ProgressBar* progress) {
    std::vector<std::unique_ptr<rt::FilmTile>> done{size_t(ntiles)};
    std::vector<std::unique_ptr<rt::FilmTile>> out;
    int next = 0, completed = 0, in_flight = 0;  // in_flight: tiles other ranks have
    // A rank gets tiles while it has requests open (up to three: the next tiles are there
    // when it is done), but not the last ones: once what is left is no more than the other
    // ranks hold, rank 0 renders the rest itself while they finish theirs, and nobody waits
    // at the end of the pass for tiles queued at one rank.
    auto hand_out = [&] {
      for (int r = 1; r < size; ++r)
        while (asks[size_t(r)] > 0 && ntiles - next > in_flight && !interrupted()) {
          const int b = next, e = std::min(ntiles, b + chunk[size_t(r)]);
          next = e;
          struct {
            int64_t first, last;
            int32_t begin, end;
          } msg{first, last, b, e};
          MPI_Send(&msg, int(sizeof msg), MPI_BYTE, r, kTiles, MPI_COMM_WORLD);
          in_flight += e - b;
          --asks[size_t(r)];
        }
    };
    // Every message waiting: asks and tile sums.
    auto receive = [&] {
      for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (!flag) return;
        int bytes = 0;
        MPI_Get_count(&st, MPI_BYTE, &bytes);
        buffer.resize(size_t(std::max(bytes, 1)));
        MPI_Recv(buffer.data(), bytes, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        if (st.MPI_TAG == kAsk) {
          int32_t n = 1;
          std::memcpy(&n, buffer.data(), sizeof n);
          chunk[size_t(st.MPI_SOURCE)] = std::max(1, n);
          ++asks[size_t(st.MPI_SOURCE)];
        } else if (st.MPI_TAG == kSums) {
          int32_t range[2];
          std::memcpy(range, buffer.data(), sizeof range);
          size_t at = sizeof range;
          for (int t = range[0]; t < range[1]; ++t) {
            const rt::Bounds2i tb = tiles.tile_bounds(t);
            std::unique_ptr<rt::FilmTile> tile = film->make_tile(tb);
            for (int h = 0; h < 2; ++h) {
              std::vector<rt::FilmPixelSum>& sums = tile->half_sums(h);
              std::memcpy(sums.data(), buffer.data() + at, sums.size() * sizeof(rt::FilmPixelSum));
              at += sums.size() * sizeof(rt::FilmPixelSum);
            }
            done[size_t(t)] = std::move(tile);
            if (progress) progress->add(tb.area() * (last - first));
          }
          completed += range[1] - range[0];
          in_flight -= range[1] - range[0];
        }
      }
    };
    // This thread talks MPI between its own chunks of tiles (one tile per thread), so it
    // answers within one tile's time while the other ranks work through queued requests.
    bool stopped = false;
    for (;;) {
      receive();
      hand_out();
      if (!stopped && next < ntiles && !interrupted()) {
        const int b = next, e = std::min(ntiles, b + threads);
        next = e;
        if (!tiles.render(first, last, b, e, &out, options.interrupt, progress)) {
          stopped = true;
          continue;
        }
        slow_down(slow, 0, e - b);
        for (int t = b; t < e; ++t) done[size_t(t)] = std::move(out[size_t(t - b)]);
        completed += e - b;
        continue;
      }
      if (completed == ntiles || (in_flight == 0 && (stopped || interrupted()))) break;
      std::this_thread::sleep_for(std::chrono::microseconds(50));  // other ranks' tiles
    }
    const bool whole = completed == ntiles && !interrupted();
    const int32_t keep = whole ? 1 : 0;
    for (int r = 1; r < size; ++r)
      MPI_Send(&keep, int(sizeof keep), MPI_BYTE, r, kPassEnd, MPI_COMM_WORLD);
    reduce_splats(film, 0, whole);
    if (!whole) return false;
    for (const auto& tile : done) film->merge_tile(*tile);
    return true;
  };

  rt::RenderStats stats =
      rt::run_passes(film, integrator, sampler.samples_per_pixel(), sampler.whole_count_patterns(),
                     tiles.pixel_count(), options, pass);
  tiles.add_counters(&stats);
  uint64_t mine[kCounters] = {}, sum[kCounters] = {};
  const char nothing = 0;
  for (int r = 1; r < size; ++r) MPI_Send(&nothing, 1, MPI_BYTE, r, kStop, MPI_COMM_WORLD);
  MPI_Reduce(mine, sum, kCounters, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  add_counters(sum, &stats);
  return stats;
}

rt::RenderStats follow(const rt::Camera& camera, const rt::Sampler& sampler,
                       const rt::Integrator& integrator, rt::Film* film,
                       const rt::RenderOptions& options, int rank, int threads,
                       const Slowdown& slow) {
  rt::TileRenderer tiles(camera, sampler, integrator, film, options.differential_spp);
  film->keep_pass_splats_apart();  // each pass's splats are summed over the ranks
  // Two tiles per thread per request: one per thread left the Cornell box 3-10% slower
  // than threads at 2 ranks x 1 thread (a message per 2-5 ms tile), two brought it to
  // 0.99-1.04x (README).
  const int32_t ask = 2 * threads;
  // Requests ahead of need (rank 0 decides how many it answers): the next tiles are here
  // when these are done.
  for (int i = 0; i < 3; ++i) MPI_Send(&ask, int(sizeof ask), MPI_BYTE, 0, kAsk, MPI_COMM_WORLD);
  std::vector<char> buffer(64), out[2];
  MPI_Request sent[2] = {MPI_REQUEST_NULL, MPI_REQUEST_NULL};
  int which = 0;
  std::vector<std::unique_ptr<rt::FilmTile>> rendered;
  for (;;) {
    MPI_Status st;
    MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
    int bytes = 0;
    MPI_Get_count(&st, MPI_BYTE, &bytes);
    buffer.resize(size_t(std::max(bytes, 1)));
    MPI_Recv(buffer.data(), bytes, MPI_BYTE, 0, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (st.MPI_TAG == kStop) break;
    if (st.MPI_TAG == kPassEnd) {
      reduce_splats(film, rank, false);
      continue;
    }
    struct {
      int64_t first, last;
      int32_t begin, end;
    } msg;
    std::memcpy(&msg, buffer.data(), sizeof msg);
    (void)tiles.render(msg.first, msg.last, msg.begin, msg.end, &rendered, nullptr, nullptr);
    slow_down(slow, rank, msg.end - msg.begin);
    // Sent without waiting for rank 0 to take it; the buffer of two sends ago is free.
    MPI_Wait(&sent[which], MPI_STATUS_IGNORE);
    std::vector<char>& o = out[which];
    const int32_t range[2] = {msg.begin, msg.end};
    o.assign(reinterpret_cast<const char*>(range), reinterpret_cast<const char*>(range + 2));
    for (const auto& tile : rendered)
      for (int h = 0; h < 2; ++h) {
        const std::vector<rt::FilmPixelSum>& sums = tile->half_sums(h);
        const char* p = reinterpret_cast<const char*>(sums.data());
        o.insert(o.end(), p, p + sums.size() * sizeof(rt::FilmPixelSum));
      }
    MPI_Isend(o.data(), int(o.size()), MPI_BYTE, 0, kSums, MPI_COMM_WORLD, &sent[which]);
    which ^= 1;
    MPI_Send(&ask, int(sizeof ask), MPI_BYTE, 0, kAsk, MPI_COMM_WORLD);
  }
  MPI_Waitall(2, sent, MPI_STATUSES_IGNORE);
  rt::RenderStats stats;
  tiles.add_counters(&stats);
  uint64_t mine[kCounters];
  get_counters(stats, mine);
  MPI_Reduce(mine, nullptr, kCounters, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  return stats;
}

}  // namespace mpi_render
