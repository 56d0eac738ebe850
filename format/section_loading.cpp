// ArchiveReader's section loading: load_sections and the per-section and per-frame work it
// schedules on the loading threads (format/archive_reader.h). Opening a file and checking its
// header and table are in format/archive_reader.cpp.
#include "format/archive_reader.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <zstd.h>

#include "format/byte_shuffle.h"
#include "format/checksum.h"
#include "format/draco_codec.h"
#include "format/frame_pieces.h"
#include "format/fresh_memory.h"
#include "format/isolated_jobs.h"
#include "format/thread_decoder.h"
#include "format/zstd_frames.h"

namespace pbrta {

namespace {

using archive_detail::add_overflows;
using archive_detail::kBufferAlignment;
using archive_detail::thread_decoder;

// Codec-4 sections from this size on are unshuffled with non-temporal stores (unshuffle4_block):
// far larger than the cache, so ordinary stores would read in every line only to overwrite it
// and see it evicted before the renderer reads it. mesh200 (109 MB, 2 threads, paired best of
// 15): 16.8-18.8 -> 15.6-16.6 ms; f10-1ac (40 MB): 8.5-8.9 -> 7.8-8.5 ms.
constexpr uint64_t kStreamSectionSize = uint64_t{8} << 20;
// Loads that read and write fewer bytes than this (stored plus decoded) run on the calling
// thread. Both count: a flat texture's pyramid stores 0.5% of the 18 MB it decodes to, and
// writing those fresh pages is most of its load (f3-18: 5.1 ms on one thread, 3.6 on two).
constexpr uint64_t kSerialLoadBytes = uint64_t{1} << 20;
// An uncompressed section is only checksummed in place, which costs far less a byte than
// decoding: its bytes count 1/kChecksumOnlyWeight as much. The --codec none archives of teapot,
// caustic glass, killeroo and 2d-mappings (0.9-4.2 MB) loaded no faster on two threads than on
// one in a process that loads repeatedly, and in a new process, where the second thread meant
// starting oneTBB's workers, took 1.1-1.6 ms against 0.45-0.9 ms on one; mesh200's 109 MB (8
// geometry sections) loads in 8.1 ms on two, 10.7 on one.
constexpr uint64_t kChecksumOnlyWeight = 8;
// A Draco section's slot has this much more room after its padding, where load_one leaves the
// vertex and triangle counts the stream decoded to (two u32): in a child process (format/
// isolated_jobs.h) that is the only way back, and the in-process path does the same.
constexpr uint64_t kDracoCountsBytes = 16;

}  // namespace

bool ArchiveReader::load_one(uint32_t index, uint8_t* out, archive_detail::Decoder* decoder,
                             std::string* reason) {
  const SectionEntry& e = entries_[index];
  Section& s = sections_[index];
  auto bad = [&](const std::string& why) {
    *reason = why;
    return false;
  };
  const Codec codec = static_cast<Codec>(e.codec);
  // Compressed or not, the stored bytes are read through the mapping (validate(): inside the
  // file). A pread copy into a staging buffer was cheaper when each fault mapped one 4 KiB page;
  // ext4 now caches pbrtc's output in large folios, one fault maps a whole folio (see
  // kSmallFileSize in archive_reader.cpp), and the copy was 12% of mesh200's load CPU. Copy ->
  // mapping, 2 threads, interleaved: mesh200 16.1-16.2 -> 15.2-15.3 ms (a copy read back from
  // disk: 15.1-15.3 -> 14.6-14.7), best of 30, 3 rounds; medians of 10 rounds of best of 100:
  // killeroo 0.36 -> 0.34 ms, caustic glass 0.41 -> 0.38 ms, teapot 0.58 -> 0.57 ms.
  const uint8_t* src = base_ + e.offset;
  // Before anything decodes these bytes.
  if (checksum64(src, e.stored_size) != e.checksum) return bad("checksum mismatch");
  if (codec == Codec::kNone) {
    // validate() guarantees 16 bytes of (zero) padding after it inside the file.
    s.data = src;
    s.in_place = true;
    return true;
  }
  const uint64_t raw = e.raw_size;
  std::memset(out + raw, 0, kSectionPadding);
  if (codec == Codec::kDraco) {
    // validate() bounds raw_size; draco_decode_section checks the mesh lays out to exactly it.
    std::string why;
    uint32_t counts[2] = {0, 0};
    if (!draco_decode_section(src, e.stored_size, raw, out, counts, &why)) return bad(why);
    std::memcpy(out + raw + kSectionPadding, counts, sizeof counts);
    s.data = out;
    return true;
  }
  std::string why;
  if (!is_one_zstd_frame(src, e.stored_size, raw, "the table says " + std::to_string(raw), &why))
    return bad(why);
  ZSTD_DCtx* dctx = decoder->context();
  if (dctx == nullptr) return bad("zstd: cannot create a decompression context");
  auto decoded_to = [&](uint64_t got) {
    return bad("zstd frame decoded to " + std::to_string(got) + " bytes but the table says " +
               std::to_string(raw));
  };

  if (codec == Codec::kZstd) {
    const size_t got = ZSTD_decompressDCtx(dctx, out, raw, src, e.stored_size);
    if (ZSTD_isError(got)) return bad(std::string("zstd: ") + ZSTD_getErrorName(got));
    if (got != raw) return decoded_to(got);
    s.data = out;
    return true;
  }

  // Shuffled: stream one shuffle block at a time into the scratch block, which stays in cache,
  // and unshuffle it from there into its place. Decoding into `out` and unshuffling there would
  // write the section twice and read it back once; zstd's window buffer, reused across the
  // section, is small enough to stay in cache too.
  uint8_t* scratch = decoder->block(kShuffleBlock);
  if (scratch == nullptr) return bad("cannot allocate a block to decode it through");
  ZSTD_DCtx_reset(dctx, ZSTD_reset_session_only);
  ZSTD_inBuffer in{src, static_cast<size_t>(e.stored_size), 0};
  size_t hint = 1;  // ZSTD_decompressStream's result: 0 once the frame is complete and flushed
  for (uint64_t at = 0; at < raw; at += kShuffleBlock) {
    const size_t n = static_cast<size_t>(std::min(kShuffleBlock, raw - at));
    ZSTD_outBuffer block{scratch, n, 0};
    while (block.pos < n) {
      const size_t in_before = in.pos, out_before = block.pos;
      hint = ZSTD_decompressStream(dctx, &block, &in);
      if (ZSTD_isError(hint)) return bad(std::string("zstd: ") + ZSTD_getErrorName(hint));
      if (block.pos < n && (hint == 0 || (in.pos == in_before && block.pos == out_before)))
        return decoded_to(at + block.pos);  // ended (or stalled) short of raw_size
    }
    unshuffle4_block(scratch, out + at, n);
  }
  if (hint != 0) {
    // The output ended where the frame should: zstd must agree that nothing is left.
    uint8_t extra = 0;
    ZSTD_outBuffer probe{&extra, 1, 0};
    hint = ZSTD_decompressStream(dctx, &probe, &in);
    if (ZSTD_isError(hint)) return bad(std::string("zstd: ") + ZSTD_getErrorName(hint));
    if (probe.pos != 0 || hint != 0) return decoded_to(raw + probe.pos);
  }
  s.data = out;
  return true;
}

// Branch-free within blocks of 1024 so the compiler vectorizes it (with plain SSE2 too, which has
// no unsigned compare).
uint64_t first_at_or_above(const uint32_t* v, uint64_t n, uint32_t limit) {
  constexpr uint64_t kBlock = 1024;
  for (uint64_t at = 0; at < n; at += kBlock) {
    const uint64_t end = std::min(n, at + kBlock);
    uint32_t any = 0;
    for (uint64_t k = at; k < end; ++k) any |= static_cast<uint32_t>(v[k] >= limit);
    if (any != 0)
      for (uint64_t k = at; k < end; ++k)
        if (v[k] >= limit) return k;
  }
  return n;
}

// One unit of parallel loading: a whole section, one frame of a codec-4 (or 6) section or one chunk
// of a codec-5 section.
struct ArchiveReader::LoadTask {
  uint32_t section;
  uint32_t frame;       // kWholeSection, or the frame's (the chunk's) index
  uint64_t raw_offset;  // of the block (the chunk) within the section
  uint64_t raw_size;
  FrameRef ref;  // codecs 4 and 6 only
};

// What unshuffling a piece of a frame needs: FramePieces' work, made by the decoding thread.
struct ArchiveReader::FrameWork {
  const uint8_t* scratch;     // the frame's decoded, shuffled bytes
  uint8_t* section;           // the section's buffer
  uint64_t raw_offset;        // of the frame's block in the section
  uint64_t size;              // of the block
  const WordBound* bounds;    // relative to the block, sorted by begin
  const uint32_t* bound_ids;  // each one's index in the load's bounds
  uint64_t num_bounds;
  bool stream;
};

bool ArchiveReader::load_frame(const LoadTask& t, archive_detail::Decoder* decoder,
                               archive_detail::FramePieces* slot, FrameWork* work,
                               std::string* error) {
  const SectionEntry& e = entries_[t.section];
  auto bad = [&](const std::string& reason) {
    *error = section_error(t.section, "frame " + std::to_string(t.frame) + ": " + reason);
    return false;
  };
  ZSTD_DCtx* dctx = decoder->context();
  uint8_t* scratch = decoder->block(t.raw_size);
  if (dctx == nullptr || scratch == nullptr)
    return bad("zstd: cannot allocate a decompression context");
  // Through the mapping, as load_one reads (validate(): inside the file).
  const uint8_t* src = base_ + e.offset + t.ref.offset;
  work->scratch = scratch;
  slot->open(work, frame_piece_count(t.raw_size));
  std::string why;
  if (!decode_frame_shuffled(dctx, src, t.ref, t.raw_size, scratch, slot->decoded_counter(),
                             &why)) {
    slot->fail();
    slot->wait_all_done();
    return bad(why);
  }
  return true;
}

bool ArchiveReader::load_sections(int threads, std::string* error) {
  std::vector<uint32_t> all(section_count());
  for (uint32_t i = 0; i < section_count(); ++i) all[i] = i;
  std::vector<uint64_t> unused;
  return load_sections(threads, all, std::vector<U32Bound>{}, &unused, error);
}

bool ArchiveReader::load_sections(int threads, const std::vector<uint32_t>& which,
                                  const std::vector<U32Bound>& bounds,
                                  std::vector<uint64_t>* first_out, std::string* error) {
  // Nothing to wait for: the plan is made before any section starts.
  const BoundPlan plan{{}, which, [&]() -> const std::vector<U32Bound>& { return bounds; },
                       {}, {},    false};
  return load_sections(threads, which, plan, first_out, error);
}

bool ArchiveReader::load_sections(int threads, const std::vector<uint32_t>& which,
                                  const BoundPlan& plan, std::vector<uint64_t>* first_out,
                                  std::string* error) {
  if (base_ == nullptr) {
    *error = fail("no archive is open");
    return false;
  }
  if (!unchanged_size(error)) return false;
  const uint32_t n = section_count();
  std::vector<uint32_t> order;
  std::vector<uint8_t> wanted(n, 0);
  for (uint32_t i : which)
    if (i < n && !wanted[i] && !sections_[i].skipped && sections_[i].data == nullptr) {
      wanted[i] = 1;
      order.push_back(i);
    }
  std::sort(order.begin(), order.end());
  // When each section may start: any time, before the plan (its tasks are taken first), or only
  // after it.
  enum Role : uint8_t { kAnyTime, kBeforePlan, kAfterPlan };
  std::vector<uint8_t> role(n, kAnyTime);
  for (uint32_t i : plan.gated)
    if (i < n && wanted[i]) role[i] = kAfterPlan;
  for (uint32_t i : plan.first) {
    if (i >= n || !wanted[i]) continue;
    // A Draco section loads after all others, so nothing could wait for it.
    if (role[i] == kAfterPlan || entries_[i].codec == static_cast<uint32_t>(Codec::kDraco)) {
      *error = fail("internal error: section " + std::to_string(i) +
                    " cannot be loaded before the plan");
      return false;
    }
    role[i] = kBeforePlan;
  }
  std::vector<uint8_t> needed(n, 0);  // read by when_loaded()
  for (uint32_t i : plan.needs) {
    if (i >= n || !wanted[i]) continue;
    if (entries_[i].codec == static_cast<uint32_t>(Codec::kDraco)) {
      *error = fail("internal error: section " + std::to_string(i) +
                    " cannot be loaded before when_loaded()");
      return false;
    }
    needed[i] = 1;
  }

  // Every decoded section in one buffer, in table order, each at a 64-byte boundary (no two
  // threads write one cache line) and followed by its padding; but those the plan waits for in
  // a buffer of their own, so that none of them is held up faulting in a huge page the sections
  // after it share (killeroo: its 288 bytes of mesh records took 63 us, not 5, and the geometry
  // waited). validate() bounded the sizes; the sums are checked anyway.
  std::vector<uint64_t> slot(n, 0);
  uint64_t total[2] = {0, 0};  // [0]: before the plan, [1]: the rest
  for (uint32_t i : order) {
    if (stores_raw(static_cast<Codec>(entries_[i].codec))) continue;
    uint64_t& t = total[role[i] == kBeforePlan ? 0 : 1];
    slot[i] = t;
    uint64_t end = 0;
    const uint64_t after = entries_[i].codec == static_cast<uint32_t>(Codec::kDraco)
                               ? kSectionPadding + kDracoCountsBytes
                               : kSectionPadding;
    if (add_overflows(t, entries_[i].raw_size, &end) ||
        add_overflows(end, after + kBufferAlignment, &end)) {
      *error = fail("the sections' decoded sizes overflow");
      return false;
    }
    t = end / kBufferAlignment * kBufferAlignment;
  }

  // The tasks: codec-4 and codec-6 sections by frame (their indexes read and checked here, on this
  // thread: 16 bytes per frame), codec-5 sections by checksum chunk, every other section whole.
  std::vector<std::string> errors(n);
  std::vector<LoadTask> tasks;
  // Each codec-4 (codec-5) section's frames (chunks) still to do: the task that finishes its last
  // one publishes the section, as load_one publishes a whole section, unless one of its frames
  // failed or, for codec 5, the chunks' checksums do not combine to the table's.
  std::unique_ptr<std::atomic<uint32_t>[]> frames_left(new std::atomic<uint32_t>[n]);
  std::unique_ptr<std::atomic<bool>[]> frame_failed(new std::atomic<bool>[n]);
  for (uint32_t i = 0; i < n; ++i) {
    frames_left[i].store(0);
    frame_failed[i].store(false);
  }
  // Codec 5's chunk checksums, each section's from chunk_sum_at[i] on.
  std::vector<uint64_t> chunk_sums, chunk_sum_at(n, 0);
  auto chunks_match = [&](uint32_t i) {
    return combine_chunk_checksums(chunk_sums.data() + chunk_sum_at[i],
                                   checksum_chunk_count(entries_[i].raw_size)) ==
           entries_[i].checksum;
  };
  for (uint32_t i : order) {
    const SectionEntry& e = entries_[i];
    if (e.codec == static_cast<uint32_t>(Codec::kNoneChunked)) {
      const uint64_t chunks = checksum_chunk_count(e.raw_size);  // validate(): raw_size <= 2^40
      chunk_sum_at[i] = chunk_sums.size();
      chunk_sums.resize(chunk_sums.size() + chunks);
      if (chunks == 0) {  // empty: its checksum is that of no chunk checksums, checked here
        if (!chunks_match(i)) {
          errors[i] = section_error(i, "checksum mismatch");
        } else {
          sections_[i].data = base_ + e.offset;
          sections_[i].in_place = true;
        }
        continue;
      }
      for (uint64_t k = 0; k < chunks; ++k) {
        const uint64_t begin = k * kChecksumChunk;
        tasks.push_back(
            LoadTask{i, uint32_t(k), begin, std::min(kChecksumChunk, e.raw_size - begin), {}});
      }
      frames_left[i].store(uint32_t(chunks));
      continue;
    }
    const uint64_t block = frame_block(static_cast<Codec>(e.codec));
    if (block == 0) {
      tasks.push_back(LoadTask{i, kWholeSection, 0, e.raw_size, {}});
      continue;
    }
    // validate(): the index fits in the stored bytes; read through the mapping, as the frames
    // are, after unchanged_size() above.
    const uint64_t index_bytes = frame_count(e.raw_size, block) * sizeof(FrameEntry);
    const uint8_t* at = base_ + e.offset;
    std::string why;
    std::vector<FrameRef> frames;
    if (checksum64(at, index_bytes) != e.checksum) {
      errors[i] = section_error(i, "checksum mismatch");
    } else if (!read_frame_index(at, e.raw_size, e.stored_size, block, &frames, &why)) {
      errors[i] = section_error(i, why);
    } else {
      for (uint32_t k = 0; k < frames.size(); ++k) {
        const uint64_t begin = uint64_t{k} * block;
        tasks.push_back(LoadTask{i, k, begin, std::min(block, e.raw_size - begin), frames[k]});
      }
      frames_left[i].store(uint32_t(frames.size()));
    }
  }

  // The bounds, once planned: by section, each inside a gated section loaded here (any section
  // loaded here when nothing comes before the plan), on 4-byte boundaries.
  static const std::vector<U32Bound> kNoBounds;
  const std::vector<U32Bound>* bounds = &kNoBounds;
  std::vector<std::vector<uint32_t>> bounds_of(n);
  std::unique_ptr<std::atomic<uint64_t>[]> first;
  std::string plan_error;
  std::atomic<bool> planned{false};
  size_t before_plan = 0;  // tasks
  for (const LoadTask& t : tasks) before_plan += role[t.section] == kBeforePlan;
  const bool plan_first = before_plan == 0;
  auto make_plan = [&] {
    const std::vector<U32Bound>& b = plan.plan ? plan.plan() : kNoBounds;
    for (uint32_t k = 0; k < b.size() && plan_error.empty(); ++k) {
      const U32Bound& u = b[k];
      if (u.section >= n || !wanted[u.section] || (!plan_first && role[u.section] != kAfterPlan) ||
          u.begin > u.end || u.end > entries_[u.section].raw_size || u.begin % 4 != 0 ||
          u.end % 4 != 0)
        plan_error = fail("internal error: bound " + std::to_string(k) +
                          " does not lie in a section loaded here after the plan");
      else if (u.begin < u.end)  // an empty one holds nothing to check
        bounds_of[u.section].push_back(k);
    }
    if (plan_error.empty()) {
      for (std::vector<uint32_t>& list : bounds_of)  // decode_frame wants them sorted by begin
        std::sort(list.begin(), list.end(),
                  [&](uint32_t x, uint32_t y) { return b[x].begin < b[y].begin; });
      first.reset(new std::atomic<uint64_t>[b.size()]);
      for (uint32_t k = 0; k < b.size(); ++k) first[k].store(b[k].end);
      bounds = &b;
    } else {
      for (std::vector<uint32_t>& list : bounds_of) list.clear();
    }
    planned.store(true, std::memory_order_release);
  };
  if (plan_first) {
    make_plan();
    if (!plan_error.empty()) {
      *error = plan_error;
      return false;
    }
  }

  // The buffers, added to decoded_ (and taken back on failure).
  uint8_t* buffer_of[2] = {nullptr, nullptr};
  size_t buffers = 0;
  for (int g = 0; g < 2; ++g) {
    if (total[g] == 0) continue;
    Buffer buffer = allocate(total[g]);
    if (!buffer) {
      for (; buffers > 0; --buffers) decoded_.pop_back();
      *error =
          fail("cannot allocate " + std::to_string(total[g]) + " bytes to decode the sections");
      return false;
    }
    buffer_of[g] = buffer.get();
    decoded_.push_back(std::move(buffer));
    ++buffers;
  }
  std::vector<uint8_t*> out_of(n, nullptr);  // where each decoded section goes
  for (uint32_t i : order)
    if (!stores_raw(static_cast<Codec>(entries_[i].codec)))
      out_of[i] = buffer_of[role[i] == kBeforePlan ? 0 : 1] + slot[i];
  // An empty framed section is padded and published here; any other by its last frame's task,
  // since here its padding would fault in a fresh page for each section, on this thread alone,
  // before any work is shared.
  for (uint32_t i : order)
    if (frame_block(static_cast<Codec>(entries_[i].codec)) != 0 && errors[i].empty() &&
        frames_left[i].load() == 0) {
      std::memset(out_of[i] + entries_[i].raw_size, 0, kSectionPadding);
      sections_[i].data = out_of[i];
    }

  // A small load (the records of a scene) runs on this thread: waking the workers costs more.
  uint64_t work_bytes = 0;  // validate() bounded every size: no overflow
  for (uint32_t i : order)
    work_bytes += stores_raw(static_cast<Codec>(entries_[i].codec))
                      ? entries_[i].raw_size / kChecksumOnlyWeight
                      : entries_[i].stored_size + entries_[i].raw_size;
  const bool serial = threads == 1 || work_bytes < kSerialLoadBytes || tasks.size() < 2;
  std::optional<tbb::task_arena> arena;
  // int(): a value, not a reference to the constant (which has no definition to link to).
  if (!serial) arena.emplace(threads > 0 ? threads : int(tbb::task_arena::automatic));

  std::vector<std::string> task_errors(tasks.size());
  // Records the first value >= limit of bound b in [lo, hi) of data (the section's bytes).
  auto scan = [&](uint32_t b, const uint8_t* data, uint64_t lo, uint64_t hi) {
    const uint32_t limit = (*bounds)[b].limit;
    const uint64_t k4 =
        first_at_or_above(reinterpret_cast<const uint32_t*>(data + lo), (hi - lo) / 4, limit);
    if (k4 == (hi - lo) / 4) return;
    const uint64_t found = lo + 4 * k4;
    uint64_t seen = first[b].load(std::memory_order_relaxed);
    while (found < seen && !first[b].compare_exchange_weak(seen, found)) {
    }
  };
  // One piece of a decoded frame into place, on whichever thread claimed it; a bound exceeded in
  // it is searched there for its first offender.
  auto unshuffle_piece = [&](const FrameWork& w, uint32_t piece) {
    thread_local std::vector<uint32_t> exceeded;
    exceeded.clear();
    unshuffle_frame_piece(w.scratch, w.section + w.raw_offset, w.size, piece, w.bounds,
                          w.num_bounds, w.stream, &exceeded);
    const uint64_t at = uint64_t{piece} * kShuffleBlock, end = frame_piece_end(piece, w.size);
    for (uint32_t j : exceeded)
      scan(w.bound_ids[j], w.section, w.raw_offset + std::max(w.bounds[j].begin, at),
           w.raw_offset + std::min(w.bounds[j].end, end));
  };
  // Each loading thread's frame in progress, by its index in on_each_thread.
  const int workers = serial ? 1 : arena->max_concurrency();
  std::vector<archive_detail::FramePieces> slots(workers);
  std::atomic<int> frames_running{0};  // frame tasks taken and not yet done
  auto run_task = [&](uint32_t k, int worker) {
    const LoadTask& t = tasks[k];
    uint8_t* out = out_of[t.section];
    archive_detail::Decoder& decoder = thread_decoder();
    if (t.frame == kWholeSection) {
      if (!load_one(t.section, out, &decoder, &task_errors[k])) {
        task_errors[k] = section_error(t.section, task_errors[k]);
        return;
      }
      const uint8_t* data = sections_[t.section].data;
      for (uint32_t b : bounds_of[t.section]) scan(b, data, (*bounds)[b].begin, (*bounds)[b].end);
      return;
    }
    const uint64_t block_end = t.raw_offset + t.raw_size;
    if (entries_[t.section].codec == static_cast<uint32_t>(Codec::kNoneChunked)) {
      // One chunk, checksummed in place (faulting its pages in) and, while in cache, searched for
      // the bounds over it. Nothing uses the bytes unless the chunks' checksums combine to the
      // table's, which the last chunk's task checks.
      const uint8_t* data = base_ + entries_[t.section].offset;
      chunk_sums[chunk_sum_at[t.section] + t.frame] = checksum64(data + t.raw_offset, t.raw_size);
      for (uint32_t b : bounds_of[t.section]) {
        const uint64_t lo = std::max((*bounds)[b].begin, t.raw_offset);
        const uint64_t hi = std::min((*bounds)[b].end, block_end);
        if (lo < hi) scan(b, data, lo, hi);
      }
      if (frames_left[t.section].fetch_sub(1, std::memory_order_acq_rel) != 1) return;
      if (!chunks_match(t.section)) {
        task_errors[k] = section_error(t.section, "checksum mismatch");
        return;
      }
      sections_[t.section].in_place = true;
      sections_[t.section].data = data;
      return;
    }
    // The bounds over this frame's block, relative to it: checked as its pieces unshuffle, and
    // searched for the first offender only in a piece where one is exceeded.
    std::vector<WordBound>& local = decoder.bounds;
    std::vector<uint32_t>& which_bound = decoder.bound_ids;
    local.clear();
    which_bound.clear();
    for (uint32_t b : bounds_of[t.section]) {
      const uint64_t lo = std::max((*bounds)[b].begin, t.raw_offset);
      const uint64_t hi = std::min((*bounds)[b].end, block_end);
      if (lo >= hi) continue;
      local.push_back(WordBound{lo - t.raw_offset, hi - t.raw_offset, (*bounds)[b].limit, false});
      which_bound.push_back(b);
    }
    FrameWork work{nullptr,      out,
                   t.raw_offset, t.raw_size,
                   local.data(), which_bound.data(),
                   local.size(), entries_[t.section].raw_size >= kStreamSectionSize};
    archive_detail::FramePieces& slot = slots[worker];
    if (load_frame(t, &decoder, &slot, &work, &task_errors[k])) {
      for (uint32_t piece; slot.claim_own(&piece);) {
        unshuffle_piece(work, piece);
        slot.piece_done();
      }
      slot.wait_all_done();  // the helpers' pieces, before the scratch block is reused
      const uint64_t section_size = entries_[t.section].raw_size;
      if (block_end == section_size) std::memset(out + section_size, 0, kSectionPadding);
    } else {
      frame_failed[t.section].store(true, std::memory_order_relaxed);
    }
    if (frames_left[t.section].fetch_sub(1, std::memory_order_acq_rel) == 1 &&
        !frame_failed[t.section].load(std::memory_order_relaxed))
      sections_[t.section].data = out;
  };
  // A thread with no task left to take unshuffles pieces of the frames other threads decode,
  // while any is decoding (format/frame_pieces.h); its own slot has nothing left to claim by then.
  auto help = [&] {
    int spins = 0;
    while (frames_running.load(std::memory_order_acquire) > 0) {
      bool helped = false;
      for (archive_detail::FramePieces& slot : slots) {
        uint32_t piece = 0;
        const void* claimed = nullptr;
        if (!slot.try_claim(&piece, &claimed)) continue;
        const FrameWork& work = *static_cast<const FrameWork*>(claimed);
        if (slot.wait_decoded(frame_piece_end(piece, work.size))) unshuffle_piece(work, piece);
        slot.piece_done();
        helped = true;
      }
      if (helped)
        spins = 0;
      else
        archive_detail::relax(&spins);
    }
  };
  // Two queues, each largest first (so one big section does not start last and leave the other
  // threads idle): the tasks that may start now, those the plan waits for at its head, and the
  // gated ones, which a thread takes once the plan is made when theirs is the larger next task,
  // or when nothing else is left (then it waits for the plan, as a barrier would have). Draco
  // sections go last, and only when every other section decoded: Draco's own work on a forged
  // stream is not bounded (format/draco_codec.h: seconds from a few KB), so a file with any other
  // fault fails without running it.
  std::vector<uint32_t> now, gated, draco;
  for (uint32_t k = 0; k < tasks.size(); ++k)
    (entries_[tasks[k].section].codec == static_cast<uint32_t>(Codec::kDraco) ? draco
     : role[tasks[k].section] == kAfterPlan                                   ? gated
                                                                              : now)
        .push_back(k);
  auto larger = [&](uint32_t a, uint32_t b) { return tasks[a].raw_size > tasks[b].raw_size; };
  // Those the plan waits for, then (with needs_first) those when_loaded() reads, then the rest.
  auto rank = [&](uint32_t k) {
    return role[tasks[k].section] == kBeforePlan          ? 0
           : plan.needs_first && needed[tasks[k].section] ? 1
                                                          : 2;
  };
  std::stable_sort(now.begin(), now.end(), [&](uint32_t a, uint32_t b) {
    return rank(a) != rank(b) ? rank(a) < rank(b) : larger(a, b);
  });
  std::stable_sort(gated.begin(), gated.end(), larger);
  std::stable_sort(draco.begin(), draco.end(), larger);
  std::atomic<size_t> next_now{0}, next_gated{0};
  auto take = [&](uint32_t* k) {
    for (;;) {
      const size_t a = next_now.load(std::memory_order_relaxed);
      const size_t g = next_gated.load(std::memory_order_relaxed);
      const bool now_left = a < now.size(), gated_left = g < gated.size();
      if (!now_left && !gated_left) return false;
      const bool use_gated =
          gated_left &&
          (!now_left || (planned.load(std::memory_order_acquire) && !larger(now[a], gated[g])));
      std::atomic<size_t>& next = use_gated ? next_gated : next_now;
      const std::vector<uint32_t>& queue = use_gated ? gated : now;
      const size_t got = next.fetch_add(1);
      if (got < queue.size()) {
        *k = queue[got];
        return true;
      }
      // Another thread took the last one of that queue: look again.
    }
  };
  // A gated task waits for the plan; the last task before it makes the plan, by which time every
  // section it reads has been published (75k meshes make a codec-4 section of 5 MB of records).
  // The last task of the needed sections calls when_loaded() likewise, unless one of them failed.
  std::atomic<size_t> before_left{before_plan};
  size_t needed_tasks = 0;
  for (const LoadTask& t : tasks) needed_tasks += needed[t.section];
  std::atomic<size_t> needed_left{needed_tasks};
  std::atomic<bool> needed_failed{false};  // a needed section's index already failed above
  for (uint32_t i : order)
    if (needed[i] && !errors[i].empty()) needed_failed.store(true);
  // What the other threads have left to decode, for when_loaded() (an estimate: they take more
  // meanwhile). Draco sections come after the whole pass, so they do not count.
  auto bytes_not_started = [&] {
    uint64_t left = 0;
    for (size_t q = next_now.load(); q < now.size(); ++q) left += tasks[now[q]].raw_size;
    for (size_t q = next_gated.load(); q < gated.size(); ++q) left += tasks[gated[q]].raw_size;
    return left;
  };
  auto run = [&](uint32_t k, int worker) {
    const uint8_t r = role[tasks[k].section];
    if (r == kAfterPlan)
      while (!planned.load(std::memory_order_acquire)) std::this_thread::yield();
    run_task(k, worker);
    if (r == kBeforePlan && before_left.fetch_sub(1, std::memory_order_acq_rel) == 1) make_plan();
    if (!needed[tasks[k].section]) return;
    if (!task_errors[k].empty()) needed_failed.store(true, std::memory_order_relaxed);
    if (needed_left.fetch_sub(1, std::memory_order_acq_rel) == 1 &&
        !needed_failed.load(std::memory_order_relaxed) && plan.when_loaded)
      plan.when_loaded(bytes_not_started());
  };
  if (needed_tasks == 0 && !needed_failed.load() && plan.when_loaded)
    plan.when_loaded(bytes_not_started());

  // Runs on every thread, given its index (its slot in slots).
  auto on_each_thread = [&](auto work) {
    if (serial) {
      work(0);
      thread_decoder().trim();
      return;
    }
    arena->execute([&] {
      tbb::parallel_for(0, arena->max_concurrency(), [&](int worker) {
        work(worker);
        thread_decoder().trim();
      });
    });
  };
  // Each thread takes the next task until none is left, then helps the frames still decoding.
  auto is_frame = [&](uint32_t k) {
    return frame_block(static_cast<Codec>(entries_[tasks[k].section].codec)) != 0;
  };
  on_each_thread([&](int worker) {
    for (;;) {
      // Counted from before take, so that a helper never leaves between a take and its run.
      frames_running.fetch_add(1, std::memory_order_acq_rel);
      uint32_t k = 0;
      const bool took = take(&k), frame = took && is_frame(k);
      if (!frame) frames_running.fetch_sub(1, std::memory_order_acq_rel);
      if (took) run(k, worker);
      if (frame) frames_running.fetch_sub(1, std::memory_order_acq_rel);
      if (!took) break;
    }
    if (!serial) help();
  });
  bool failed = !plan_error.empty();
  for (uint32_t i : order) failed |= !errors[i].empty();
  for (uint32_t k : now) failed |= !task_errors[k].empty();
  for (uint32_t k : gated) failed |= !task_errors[k].empty();
  // The Draco streams' checksums, here and before any child is forked: a damaged stream fails
  // for the price of hashing it (microseconds), not of a process (a millisecond or more).
  if (!failed) {
    for (uint32_t k : draco) {
      const uint32_t i = tasks[k].section;
      const SectionEntry& e = entries_[i];
      if (checksum64(base_ + e.offset, e.stored_size) != e.checksum) {
        task_errors[k] = section_error(i, "checksum mismatch");
        failed = true;
      }
    }
  }
  if (!failed && !draco.empty()) {
    if (isolation_enabled()) {
      // In child processes with a budget (format/isolated_jobs.h), each decoding into shared
      // memory that is then copied into place: Draco never runs in this process. Jobs go in
      // section order, so the section that stops a child is reported before those it left.
      std::vector<uint32_t> job_task = draco;
      std::sort(job_task.begin(), job_task.end(),
                [&](uint32_t a, uint32_t b) { return tasks[a].section < tasks[b].section; });
      std::vector<IsolatedJob> jobs;
      std::vector<uint8_t*> dst;
      for (uint32_t k : job_task) {
        const uint32_t i = tasks[k].section;
        jobs.push_back(IsolatedJob{entries_[i].raw_size + kSectionPadding + kDracoCountsBytes,
                                   entries_[i].stored_size});
        dst.push_back(out_of[i]);
      }
      std::vector<std::string> job_errors;
      std::vector<char> by_job;
      const int processes = threads > 0 ? threads : int(std::thread::hardware_concurrency());
      run_isolated(
          jobs, dst, processes, IsolationBudget{},
          [&](size_t j, uint8_t* out, std::string* why) {
            return load_one(tasks[job_task[j]].section, out, &thread_decoder(), why);
          },
          &job_errors, &by_job);
      for (size_t j = 0; j < jobs.size(); ++j) {
        const uint32_t i = tasks[job_task[j]].section;
        if (!job_errors[j].empty()) {
          task_errors[job_task[j]] =
              section_error(i, by_job[j] ? job_errors[j] : "draco: " + job_errors[j]);
          continue;
        }
        // The child may have been subverted by its stream: the padding is this process's to set,
        // and what validate() checks is checked here as for any section.
        std::memset(out_of[i] + entries_[i].raw_size, 0, kSectionPadding);
        sections_[i].data = out_of[i];
        sections_[i].in_place = false;
        for (uint32_t b : bounds_of[i])
          scan(b, sections_[i].data, (*bounds)[b].begin, (*bounds)[b].end);
      }
    } else {
      std::atomic<size_t> next{0};
      on_each_thread([&](int worker) {
        for (size_t j = next++; j < draco.size(); j = next++) run(draco[j], worker);
      });
    }
    for (uint32_t k : draco) {
      const uint32_t i = tasks[k].section;
      if (sections_[i].data != nullptr)
        std::memcpy(sections_[i].decoded_counts, out_of[i] + entries_[i].raw_size + kSectionPadding,
                    sizeof sections_[i].decoded_counts);
    }
  }
  // The lowest-numbered failing section's first failure (tasks are in section, frame order).
  for (uint32_t k = 0; k < tasks.size(); ++k) {
    const uint32_t i = tasks[k].section;
    if (!task_errors[k].empty() && (errors[i].empty())) errors[i] = task_errors[k];
  }
  std::string first_error = plan_error;
  for (uint32_t i : order)
    if (first_error.empty() && !errors[i].empty()) first_error = errors[i];
  if (!first_error.empty()) {
    *error = first_error;
    for (uint32_t j : order) {  // all or nothing
      sections_[j].data = nullptr;
      sections_[j].in_place = false;
      sections_[j].decoded_counts[0] = sections_[j].decoded_counts[1] = 0;
    }
    for (; buffers > 0; --buffers) decoded_.pop_back();
    return false;
  }
  first_out->resize(bounds->size());
  for (uint32_t b = 0; b < bounds->size(); ++b) (*first_out)[b] = first[b].load();
  return true;
}

bool ArchiveReader::typed_array_bytes(uint32_t section, size_t elem_size, size_t elem_align,
                                      const void** out, uint32_t* count, std::string* error) const {
  if (section >= entries_.size()) {
    *error = fail("section #" + std::to_string(section) + " does not exist (the archive has " +
                  std::to_string(entries_.size()) + ")");
    return false;
  }
  const SectionEntry& e = entries_[section];
  const uint8_t* data = sections_[section].data;
  if (data == nullptr) {
    *error = section_error(section, "not loaded");
    return false;
  }
  if (e.raw_size != uint64_t{e.count} * elem_size) {
    *error = section_error(section, std::to_string(e.raw_size) + " bytes is not " +
                                        std::to_string(e.count) + " records of " +
                                        std::to_string(elem_size) + " bytes");
    return false;
  }
  if (reinterpret_cast<uintptr_t>(data) % elem_align != 0) {
    *error =
        section_error(section, "data is not aligned to " + std::to_string(elem_align) + " bytes");
    return false;
  }
  *out = data;
  *count = e.count;
  return true;
}

}  // namespace pbrta
