#include "format/frame_pieces.h"

#include <thread>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace pbrta::archive_detail {

namespace {

constexpr uint64_t kPieceBits = 8;
constexpr uint64_t kPieceMask = (uint64_t{1} << kPieceBits) - 1;

uint32_t pieces_of(uint64_t claim) {
  return static_cast<uint32_t>((claim >> kPieceBits) & kPieceMask);
}
uint32_t next_of(uint64_t claim) {
  return static_cast<uint32_t>(claim & kPieceMask);
}

}  // namespace

void relax(int* spins) {
  if (++*spins < 64) {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
    return;
  }
  std::this_thread::yield();
}

void FramePieces::open(const void* work, uint32_t pieces) {
  work_ = work;
  pieces_ = pieces;
  decoded_.store(0, std::memory_order_relaxed);
  done_.store(0, std::memory_order_relaxed);
  failed_.store(false, std::memory_order_relaxed);
  ++generation_;
  // Publishes the fields above to whichever thread claims a piece.
  claim_.store(generation_ << (2 * kPieceBits) | uint64_t{pieces} << kPieceBits,
               std::memory_order_release);
}

bool FramePieces::try_claim(uint32_t* piece, const void** work) {
  uint64_t c = claim_.load(std::memory_order_acquire);
  while (next_of(c) < pieces_of(c)) {
    // The generation is part of c, so a claim on a frame replaced meanwhile fails here.
    if (claim_.compare_exchange_weak(c, c + 1, std::memory_order_acq_rel,
                                     std::memory_order_acquire)) {
      *piece = next_of(c);
      *work = work_;  // the opener's, published by its release of claim_
      return true;
    }
  }
  return false;
}

bool FramePieces::claim_own(uint32_t* piece) {
  const void* unused = nullptr;
  return try_claim(piece, &unused);
}

void FramePieces::fail() {
  failed_.store(true, std::memory_order_release);
  uint64_t c = claim_.load(std::memory_order_acquire);
  while (next_of(c) < pieces_of(c)) {
    if (claim_.compare_exchange_weak(c, (c & ~kPieceMask) | pieces_of(c), std::memory_order_acq_rel,
                                     std::memory_order_acquire)) {
      done_.fetch_add(pieces_of(c) - next_of(c), std::memory_order_acq_rel);
      return;
    }
  }
}

void FramePieces::wait_all_done() {
  int spins = 0;
  while (done_.load(std::memory_order_acquire) < pieces_) relax(&spins);
}

bool FramePieces::wait_decoded(uint64_t bytes) const {
  int spins = 0;
  while (decoded_.load(std::memory_order_acquire) < bytes) {
    if (failed_.load(std::memory_order_acquire)) return false;
    relax(&spins);
  }
  return true;
}

}  // namespace pbrta::archive_detail
