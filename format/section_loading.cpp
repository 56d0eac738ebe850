// ArchiveReader::load_sections (format/archive_reader.h): every section's checksum verified and
// its bytes decoded, on every thread. Opening a file and checking its header and table are in
// format/archive_reader.cpp.
//
// The work is cut into tasks of at most a few MiB: a raw section's 1 MiB chunks (checksummed in
// place) and a zstd section's frames (checksummed, decoded one-shot into place, unshuffled
// through a per-thread scratch block when shuffled). Each thread takes the largest task left, so
// one big section does not start last; the task that finishes a section's last part publishes
// it. Draco sections come after all others (see the header).
#include "format/archive_reader.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <zstd.h>

#include "format/checksum.h"
#include "format/draco_codec.h"
#include "format/isolated_jobs.h"
#include "format/zstd_frames.h"

namespace pbrta {

namespace {

using archive_detail::add_overflows;

// Loads that read and write fewer bytes than this (stored plus decoded) run on the calling
// thread: waking oneTBB's workers costs more (and, in a new process, starting them 0.5-3 ms).
// Both count: a flat texture's pyramid stores 0.5% of the 18 MB it decodes to, and writing those
// fresh pages is most of its load.
constexpr uint64_t kSerialLoadBytes = uint64_t{1} << 20;
// A raw section is only checksummed in place, which costs far less a byte than decoding: its
// bytes count 1/kRawWeight as much.
constexpr uint64_t kRawWeight = 8;
// A Draco section's slot has this much more room after its padding, where the decoder leaves the
// vertex and triangle counts the stream decoded to (two u32): from a child process (format/
// isolated_jobs.h) that is the only way back.
constexpr uint64_t kDracoCountsBytes = 16;
constexpr uint64_t kSlotAlignment = 64;  // no two threads write one cache line

// One loading thread's zstd context and scratch block, kept for its next load: mapping and
// zeroing them anew was half of a repeated 1 MB load. The block is heap memory, never a huge page,
// which would stay whole in memory for the thread's life (2 MiB of teapot's peak RSS).
struct ThreadDecoder {
  ZSTD_DCtx* dctx = nullptr;
  archive_detail::Buffer scratch{nullptr, {}};
  uint64_t scratch_size = 0;
  ~ThreadDecoder() { ZSTD_freeDCtx(dctx); }
  // A block of at least size bytes (at most kMaxFrameSize: the reader checked the frame size).
  uint8_t* block(uint64_t size) {
    if (scratch_size < size) {
      scratch = archive_detail::allocate(size, true);
      scratch_size = scratch ? size : 0;
    }
    return scratch.get();
  }
};

ThreadDecoder& thread_decoder() {
  thread_local ThreadDecoder decoder;
  return decoder;
}

}  // namespace

struct ArchiveReader::Task {
  uint32_t section;
  uint32_t part;  // the chunk's or the frame's index in its section
  uint64_t raw_offset;
  uint64_t raw_size;
  FrameRef frame;  // zstd only
  bool shuffled;   // zstd only
};

bool ArchiveReader::plan_frames(uint32_t i, std::vector<Task>* tasks, std::string* reason) const {
  const SectionEntry& e = entries_[i];
  const uint8_t* stored = base_ + e.offset;  // validate(): inside the file
  FrameIndex index;
  if (!read_frame_header(stored, e.stored_size, e.raw_size, &index, reason)) return false;
  if (checksum64(stored, index.index_bytes) != e.checksum) {
    *reason = "checksum mismatch";
    return false;
  }
  if (!read_frame_entries(stored, e.stored_size, &index, reason)) return false;
  for (uint32_t k = 0; k < index.frames.size(); ++k) {
    const uint64_t at = uint64_t{k} * index.frame_size;
    tasks->push_back(Task{i, k, at, std::min(index.frame_size, e.raw_size - at), index.frames[k],
                          index.shuffled});
  }
  return true;
}

bool ArchiveReader::run_task(const Task& t, uint8_t* out, uint64_t* chunk_sum,
                             std::string* reason) const {
  const uint8_t* stored = base_ + entries_[t.section].offset;
  if (entries_[t.section].codec == uint32_t(Codec::kRaw)) {
    // Nothing uses the bytes unless the chunks' checksums combine to the table's, which the
    // section's last task checks.
    *chunk_sum = checksum64(stored + t.raw_offset, t.raw_size);
    return true;
  }
  ThreadDecoder& d = thread_decoder();
  if (d.dctx == nullptr) d.dctx = ZSTD_createDCtx();
  uint8_t* scratch = t.shuffled ? d.block(t.raw_size) : nullptr;
  if (d.dctx == nullptr || (t.shuffled && scratch == nullptr)) {
    *reason = "cannot allocate a zstd decompression context";
    return false;
  }
  if (decode_frame(d.dctx, stored + t.frame.offset, t.frame, t.raw_size, t.shuffled, scratch,
                   out + t.raw_offset, reason))
    return true;
  *reason = "frame " + std::to_string(t.part) + ": " + *reason;
  return false;
}

bool ArchiveReader::load_draco(const std::vector<uint32_t>& draco, const std::vector<uint8_t*>& out,
                               int threads, std::vector<std::string>* errors) {
  // The streams' checksums here, before any child is forked: a damaged stream fails for the price
  // of hashing it (microseconds), not of a process (a millisecond or more).
  bool ok = true;
  for (uint32_t i : draco)
    if (checksum64(base_ + entries_[i].offset, entries_[i].stored_size) != entries_[i].checksum) {
      (*errors)[i] = section_error(i, "checksum mismatch");
      ok = false;
    }
  if (!ok || draco.empty()) return ok;
  // In child processes with a budget (format/isolated_jobs.h), whose outputs are then copied into
  // place: Draco never runs in this process. Jobs go in section order, so the section that stops
  // a child is reported before those it left.
  std::vector<uint64_t> input;
  for (uint32_t i : draco) input.push_back(entries_[i].stored_size);
  std::vector<std::vector<uint8_t>> decoded;
  std::vector<std::string> job_errors;
  std::vector<char> by_job;
  run_isolated_blobs(
      input, threads > 0 ? threads : int(std::thread::hardware_concurrency()), IsolationBudget{},
      [&](size_t j, std::vector<uint8_t>* to, std::string* why) {
        const SectionEntry& e = entries_[draco[j]];
        to->resize(e.raw_size + kSectionPadding + kDracoCountsBytes);  // validate() bounded it
        uint32_t counts[2] = {0, 0};
        if (!draco_decode_section(base_ + e.offset, e.stored_size, e.raw_size, to->data(), counts,
                                  why))
          return false;
        std::memcpy(to->data() + e.raw_size + kSectionPadding, counts, sizeof counts);
        return true;
      },
      &decoded, &job_errors, &by_job);
  for (size_t j = 0; j < draco.size(); ++j) {
    const uint32_t i = draco[j];
    if (!job_errors[j].empty()) {
      (*errors)[i] = section_error(i, by_job[j] ? job_errors[j] : "draco: " + job_errors[j]);
      ok = false;
      continue;
    }
    // The child may have been subverted by its stream: its output is checked like any input,
    // and the padding is this process's to set.
    const uint64_t size = entries_[i].raw_size + kSectionPadding + kDracoCountsBytes;
    if (decoded[j].size() != size) {
      (*errors)[i] = section_error(i, "draco: the decoder's output has the wrong size");
      ok = false;
      continue;
    }
    std::memcpy(out[i], decoded[j].data(), size);
    std::memset(out[i] + entries_[i].raw_size, 0, kSectionPadding);
    std::memcpy(sections_[i].decoded_counts, out[i] + entries_[i].raw_size + kSectionPadding,
                sizeof sections_[i].decoded_counts);
    sections_[i].data = out[i];
  }
  return ok;
}

bool ArchiveReader::load_sections(int threads, std::string* error,
                                  const std::vector<bool>& wanted) {
  if (base_ == nullptr) {
    *error = fail("no archive is open");
    return false;
  }
  if (!unchanged_size(error)) return false;
  const uint32_t n = section_count();

  // The sections this call decodes in one buffer, in table order, each followed by its padding.
  // validate() bounded the sizes; the sums are checked anyway.
  auto now = [&](uint32_t i) {
    return !sections_[i].skipped && !sections_[i].data && (wanted.empty() || wanted[i]);
  };
  std::vector<uint64_t> slot(n, 0);
  uint64_t total = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (!now(i) || entries_[i].codec == uint32_t(Codec::kRaw)) continue;
    slot[i] = total;
    const uint64_t after = entries_[i].codec == uint32_t(Codec::kDraco)
                               ? kSectionPadding + kDracoCountsBytes
                               : kSectionPadding;
    if (add_overflows(total, entries_[i].raw_size, &total) ||
        add_overflows(total, after + kSlotAlignment - 1, &total)) {
      *error = fail("the sections' decoded sizes overflow");
      return false;
    }
    total = total / kSlotAlignment * kSlotAlignment;
  }
  uint8_t* buffer = nullptr;
  if (total > 0) {
    decoded_.push_back(archive_detail::allocate(total));
    buffer = decoded_.back().get();
    if (!buffer) {
      *error = fail("cannot allocate " + std::to_string(total) + " bytes to decode the sections");
      return false;
    }
  }

  // The tasks, and what each section waits for.
  std::vector<uint8_t*> out(n, nullptr);
  std::vector<std::string> errors(n);
  std::vector<Task> tasks;
  std::vector<uint32_t> draco;
  std::vector<uint64_t> chunk_sums, chunk_at(n, 0);
  auto chunks_match = [&](uint32_t i) {
    return combine_chunk_checksums(chunk_sums.data() + chunk_at[i],
                                   checksum_chunk_count(entries_[i].raw_size)) ==
           entries_[i].checksum;
  };
  auto publish = [&](uint32_t i) {
    if (entries_[i].codec == uint32_t(Codec::kRaw)) {
      if (!chunks_match(i)) return section_error(i, "checksum mismatch");
      sections_[i].data = base_ + entries_[i].offset;  // followed by its (zero) padding
      sections_[i].in_place = true;
    } else {
      std::memset(out[i] + entries_[i].raw_size, 0, kSectionPadding);
      sections_[i].data = out[i];
    }
    return std::string();
  };
  uint64_t work = 0;  // validate() bounded every size: no overflow
  for (uint32_t i = 0; i < n; ++i) {
    if (!now(i)) continue;
    const SectionEntry& e = entries_[i];
    const size_t first_task = tasks.size();
    if (e.codec == uint32_t(Codec::kRaw)) {
      const uint64_t chunks = checksum_chunk_count(e.raw_size);  // raw_size <= 2^40
      chunk_at[i] = chunk_sums.size();
      chunk_sums.resize(chunk_sums.size() + chunks);
      for (uint64_t k = 0; k < chunks; ++k)
        tasks.push_back(Task{i,
                             uint32_t(k),
                             k * kRawChunk,
                             std::min(kRawChunk, e.raw_size - k * kRawChunk),
                             {},
                             false});
      work += e.raw_size / kRawWeight;
    } else if (e.codec == uint32_t(Codec::kDraco)) {
      out[i] = buffer + slot[i];
      draco.push_back(i);
      continue;
    } else {
      out[i] = buffer + slot[i];
      std::string why;
      if (!plan_frames(i, &tasks, &why)) errors[i] = section_error(i, why);
      work += e.stored_size + e.raw_size;
    }
    if (tasks.size() == first_task && errors[i].empty()) errors[i] = publish(i);  // empty
  }
  std::unique_ptr<std::atomic<uint32_t>[]> parts_left(new std::atomic<uint32_t>[n]);
  std::unique_ptr<std::atomic<bool>[]> part_failed(new std::atomic<bool>[n]);
  for (uint32_t i = 0; i < n; ++i) {
    parts_left[i].store(0);
    part_failed[i].store(false);
  }
  for (const Task& t : tasks) parts_left[t.section].fetch_add(1);
  std::stable_sort(tasks.begin(), tasks.end(),
                   [](const Task& a, const Task& b) { return a.raw_size > b.raw_size; });

  std::vector<std::string> task_errors(tasks.size());
  auto run = [&](size_t k) {
    const Task& t = tasks[k];
    std::string why;
    uint64_t* sum = entries_[t.section].codec == uint32_t(Codec::kRaw)
                        ? &chunk_sums[chunk_at[t.section] + t.part]
                        : nullptr;
    if (!run_task(t, out[t.section], sum, &why)) {
      task_errors[k] = section_error(t.section, why);
      part_failed[t.section].store(true, std::memory_order_relaxed);
    }
    if (parts_left[t.section].fetch_sub(1, std::memory_order_acq_rel) == 1 &&
        !part_failed[t.section].load(std::memory_order_relaxed))
      task_errors[k] = publish(t.section);
  };
  std::atomic<size_t> next{0};
  auto take_all = [&] {
    for (size_t k = next++; k < tasks.size(); k = next++) run(k);
  };
  if (threads == 1 || work < kSerialLoadBytes || tasks.size() < 2) {
    take_all();
  } else {
    // int(): a value, not a reference to the constant (which has no definition to link to).
    tbb::task_arena arena(threads > 0 ? threads : int(tbb::task_arena::automatic));
    arena.execute([&] { tbb::parallel_for(0, arena.max_concurrency(), [&](int) { take_all(); }); });
  }
  // Past the sections, the huge page a load partly fills goes back: teapot's 1.1 MiB of peak RSS
  // for 20 us of its load.
  if (buffer) archive_detail::shrink(&decoded_.back(), total);
  // Each section's first failure: its lowest-numbered failing part. (A section whose planning
  // failed has no tasks; one whose checksums do not combine has no other failure.)
  std::vector<uint32_t> failed_part(n, UINT32_MAX);
  for (size_t k = 0; k < tasks.size(); ++k) {
    const uint32_t i = tasks[k].section;
    if (!task_errors[k].empty() && tasks[k].part < failed_part[i]) {
      errors[i] = task_errors[k];
      failed_part[i] = tasks[k].part;
    }
  }
  bool ok =
      std::all_of(errors.begin(), errors.end(), [](const std::string& e) { return e.empty(); });
  if (ok) ok = load_draco(draco, out, threads, &errors);
  if (ok) {
    // The compressed bytes are not read again: their pages of the file's mapping leave this
    // process's memory (the page cache keeps them; a later read faults them back in). On
    // hm-lights/goniometric that is 11.5 MB of peak RSS.
    if (map_ != nullptr) {
      const uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
      for (uint32_t i = 0; i < n; ++i) {
        const SectionEntry& e = entries_[i];
        if (e.codec == uint32_t(Codec::kRaw) || !out[i]) continue;  // or not loaded now
        const uintptr_t begin = reinterpret_cast<uintptr_t>(base_ + e.offset);
        const uintptr_t first = (begin + page - 1) / page * page;
        const uintptr_t last = (begin + e.stored_size) / page * page;
        if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
      }
    }
    return true;
  }
  for (uint32_t i = 0; i < n; ++i)
    if (!errors[i].empty()) {
      *error = errors[i];
      break;
    }
  for (Section& s : sections_) {  // all or nothing
    s.data = nullptr;
    s.in_place = false;
    s.decoded_counts[0] = s.decoded_counts[1] = 0;
  }
  decoded_.clear();
  return false;
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
