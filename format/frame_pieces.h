// format/frame_pieces.h — one loading thread's codec-4 (or codec-6) frame in progress, whose
// pieces other threads may unshuffle (internal to format/: the archive reader's section loading
// uses it).
//
// zstd decodes a frame on one thread, but the frame is then unshuffled piece by piece
// (format/zstd_frames.h), and a piece need not wait for the rest of the frame, nor for the thread
// that decodes it. When a load has fewer tasks left than threads (caustic glass: one 2 MiB frame
// and a few hundred bytes of records; the last frames of any large load), the threads with nothing
// to take unshuffle the pieces of the frames in progress as they decode, so that decoding and
// unshuffling (which faults in the section's fresh pages) run side by side.
//
// Protocol. The decoding thread opens its slot for a frame (open), reports progress (decoded),
// then claims the pieces nobody took (claim_own) and unshuffles them, and waits (wait_all_done)
// until every piece it opened is done before it reuses its scratch block or publishes the
// section; on failure it calls fail instead of claiming. Any other thread may try_claim a piece
// of an open slot, wait_decoded for its bytes and report piece_done. A claim names the slot's
// generation, so a helper can never take a piece of a frame that has since been replaced.
#pragma once

#include <atomic>
#include <cstdint>

namespace pbrta::archive_detail {

class FramePieces {
 public:
  // Decoding thread. work is whatever a helper needs to unshuffle a piece; it is read only by a
  // thread that claimed a piece of this frame, and must stay valid until wait_all_done returns.
  void open(const void* work, uint32_t pieces);
  // Where the decoder stores, with release order, how many of the frame's bytes are final
  // (decode_frame_shuffled in format/zstd_frames.h does).
  std::atomic<uint64_t>* decoded_counter() { return &decoded_; }
  bool claim_own(uint32_t* piece);  // the next unclaimed piece, if any
  void fail();                      // decoding failed: the unclaimed pieces are dropped
  void wait_all_done();             // every piece done (the slot is then closed)

  // Any thread.
  bool try_claim(uint32_t* piece, const void** work);  // a piece of the open frame, if any left
  // Waits until the frame's first `bytes` bytes have decoded; false if decoding failed first.
  bool wait_decoded(uint64_t bytes) const;
  void piece_done() { done_.fetch_add(1, std::memory_order_acq_rel); }

 private:
  // generation << 16 | pieces << 8 | next piece. A frame has at most 4 MiB / 256 KiB = 16 pieces.
  std::atomic<uint64_t> claim_{0};
  std::atomic<uint64_t> decoded_{0};
  std::atomic<uint32_t> done_{0};
  std::atomic<bool> failed_{false};
  const void* work_ = nullptr;  // written before claim_ opens the frame, read after a claim
  uint64_t generation_ = 0;
  uint32_t pieces_ = 0;
};

// One turn of a wait on another thread's progress: a few pauses first (a piece takes tens of
// microseconds), then yielding, so that a load with more threads than cores does not starve the
// thread waited for. *spins counts the turns of one wait (start it at 0).
void relax(int* spins);

}  // namespace pbrta::archive_detail
