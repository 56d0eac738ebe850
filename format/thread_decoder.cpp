#include "format/thread_decoder.h"

#include <sys/mman.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <memory>

// For ZSTD_customMem and ZSTD_createDCtx_advanced: exported by the shared library since 1.3.
#define ZSTD_STATIC_LINKING_ONLY
#include <zstd.h>

#include "format/fresh_memory.h"

namespace pbrta::archive_detail {

namespace {

// zstd's allocator: its context and streaming window buffer are large and written at once, so
// they get huge pages like the decode buffers. A header before each block records how to free it.
constexpr size_t kZstdAllocHeader = 64;
void* zstd_alloc(void*, size_t size) {
  uint64_t mapped = 0;
  uint8_t* base = nullptr;
  if (size + kZstdAllocHeader >= kHugeBufferThreshold) {
    base = map_fresh(size + kZstdAllocHeader, &mapped);
  } else {
    base = static_cast<uint8_t*>(std::malloc(size + kZstdAllocHeader));
  }
  if (base == nullptr) return nullptr;
  std::memcpy(base, &mapped, sizeof mapped);
  return base + kZstdAllocHeader;
}
void zstd_free(void*, void* address) {
  if (address == nullptr) return;
  uint8_t* base = static_cast<uint8_t*>(address) - kZstdAllocHeader;
  uint64_t mapped = 0;
  std::memcpy(&mapped, base, sizeof mapped);
  if (mapped > 0)
    munmap(base, mapped);
  else
    std::free(base);
}

// Bytes of huge-page scratch blocks that loading threads keep between loads, in all: each thread
// keeps its block for the next load while the total stays within this.
constexpr uint64_t kKeptBufferBudget = uint64_t{32} << 20;
std::atomic<uint64_t> kept_buffer_bytes{0};

}  // namespace

Decoder::~Decoder() {
  ZSTD_freeDCtx(dctx_);
  free_scratch();
}

void Decoder::trim() {
  if (kept_buffer_bytes.load() > kKeptBufferBudget) free_scratch();
  if (dctx_ != nullptr && ZSTD_sizeof_DCtx(dctx_) > (size_t{1} << 20)) {
    ZSTD_freeDCtx(dctx_);
    dctx_ = nullptr;
    tried_ = false;
  }
}

ZSTD_DCtx* Decoder::context() {
  if (!tried_) {
    tried_ = true;
    dctx_ = ZSTD_createDCtx_advanced(ZSTD_customMem{zstd_alloc, zstd_free, nullptr});
    // Streaming, unlike one-shot decoding, refuses windows over 2^27 by default; every frame
    // one-shot decoding accepts must still load. zstd sizes its buffer by the smaller of the
    // window and the content size, which validate() bounded.
    if (dctx_ != nullptr) ZSTD_DCtx_setParameter(dctx_, ZSTD_d_windowLogMax, ZSTD_WINDOWLOG_MAX);
  }
  return dctx_;
}

uint8_t* Decoder::block(uint64_t bytes) {
  if (bytes > scratch_size_) {
    free_scratch();
    if (bytes >= kHugeBufferThreshold) {
      scratch_ = map_fresh(bytes, &scratch_mapped_);
      if (scratch_ == nullptr) scratch_mapped_ = 0;
      kept_buffer_bytes += scratch_mapped_;
    } else {
      scratch_ = static_cast<uint8_t*>(std::malloc(bytes));
      scratch_mapped_ = 0;
    }
    scratch_size_ = scratch_ != nullptr ? bytes : 0;
  }
  return scratch_;
}

void Decoder::free_scratch() {
  if (scratch_mapped_ > 0)
    munmap(scratch_, scratch_mapped_);
  else
    std::free(scratch_);
  kept_buffer_bytes -= scratch_mapped_;
  scratch_ = nullptr;
  scratch_size_ = scratch_mapped_ = 0;
}

// Owned through the thread's own storage, where leak checkers see it.
Decoder& thread_decoder() {
  thread_local std::unique_ptr<Decoder> decoder;
  if (!decoder) decoder = std::make_unique<Decoder>();
  return *decoder;
}

}  // namespace pbrta::archive_detail
