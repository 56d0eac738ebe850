// format/thread_decoder.h — one loading thread's zstd context and buffers, kept between loads
// (internal to format/: the archive reader's section loading uses it).
//
// Kept across load_sections calls and across loads (and readers) for the life of the thread: the
// decompression context (reused across sections, so a streaming window buffer is allocated
// once) and the block that shuffled data is decoded into before it is unshuffled into place.
// Each is made on first need: a thread that only decodes small record sections never maps a
// scratch block. Keeping the buffers matters in a VM: mapping, zeroing and unmapping fresh huge
// pages for them was half of a 0.75 ms load of killeroo-simple, repeated. Together the threads
// keep at most 32 MiB of such buffers.
#pragma once

#include <cstdint>
#include <vector>

#include "format/byte_shuffle.h"

struct ZSTD_DCtx_s;

namespace pbrta::archive_detail {

struct Decoder {
  std::vector<WordBound> bounds;  // the current frame's bounds (load_sections' run)
  std::vector<uint32_t> bound_ids;

  Decoder() = default;
  Decoder(const Decoder&) = delete;
  Decoder& operator=(const Decoder&) = delete;
  ~Decoder();
  // After a load: frees the scratch block unless it fits the process's budget for kept blocks, and
  // the context if a streamed (codec 2) section grew its window buffer past 1 MiB.
  void trim();
  // The context, or nullptr when out of memory.
  ZSTD_DCtx_s* context();
  // A scratch block of at least bytes to decode shuffled data into (codec 2: kShuffleBlock, codec
  // 4: its frame's block), or nullptr when out of memory. Sized by need: a small frame (a records
  // section) takes a heap block, not fresh huge pages; a full frame takes exactly two huge pages.
  uint8_t* block(uint64_t bytes);

 private:
  void free_scratch();

  ZSTD_DCtx_s* dctx_ = nullptr;
  bool tried_ = false;
  uint8_t* scratch_ = nullptr;
  uint64_t scratch_size_ = 0;
  uint64_t scratch_mapped_ = 0;  // 0: scratch is on the heap
};

// This thread's decoder, made on first need and freed when the thread ends; the loading tasks of
// every reader that run on this thread share it (a thread runs one load task at a time).
Decoder& thread_decoder();

}  // namespace pbrta::archive_detail
