#include "format/zstd_frames.h"

#include <algorithm>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include "format/checksum.h"

namespace pbrta {

void shuffle4(const uint8_t* src, uint8_t* dst, uint64_t size) {
  const uint64_t words = size / 4;
  for (uint64_t w = 0; w < words; ++w)
    for (uint64_t k = 0; k < 4; ++k) dst[k * words + w] = src[4 * w + k];
  std::memcpy(dst + 4 * words, src + 4 * words, size - 4 * words);
}

void unshuffle4(const uint8_t* src, uint8_t* dst, uint64_t size) {
  const uint64_t words = size / 4;
  const uint8_t *s0 = src, *s1 = src + words, *s2 = src + 2 * words, *s3 = src + 3 * words;
  uint64_t w = 0;
#if defined(__SSE2__)
  // 16 words at a time (every x86-64 CPU has SSE2): interleave the bytes of lanes 0 and 1, and
  // of 2 and 3, then the 16-bit pairs. Loading decodes as fast as zstd writes, this keeps up.
  for (; w + 16 <= words; w += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s0 + w));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s1 + w));
    const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s2 + w));
    const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s3 + w));
    const __m128i ab_lo = _mm_unpacklo_epi8(a, b), ab_hi = _mm_unpackhi_epi8(a, b);
    const __m128i cd_lo = _mm_unpacklo_epi8(c, d), cd_hi = _mm_unpackhi_epi8(c, d);
    __m128i* out = reinterpret_cast<__m128i*>(dst + 4 * w);
    _mm_storeu_si128(out + 0, _mm_unpacklo_epi16(ab_lo, cd_lo));
    _mm_storeu_si128(out + 1, _mm_unpackhi_epi16(ab_lo, cd_lo));
    _mm_storeu_si128(out + 2, _mm_unpacklo_epi16(ab_hi, cd_hi));
    _mm_storeu_si128(out + 3, _mm_unpackhi_epi16(ab_hi, cd_hi));
  }
#endif
  for (; w < words; ++w) {
    dst[4 * w] = s0[w];
    dst[4 * w + 1] = s1[w];
    dst[4 * w + 2] = s2[w];
    dst[4 * w + 3] = s3[w];
  }
  std::memcpy(dst + 4 * words, src + 4 * words, size - 4 * words);
}

uint64_t frame_count(uint64_t raw_size, uint64_t frame_size) {
  return raw_size / frame_size + (raw_size % frame_size != 0 ? 1 : 0);
}

namespace {
// One encoding thread's compression context and shuffle buffer, kept for its next section: a
// fresh context allocates and zeroes megabytes of tables, and on mesh200 (57 sections) those
// first touches were a third of pbrtc's page faults.
struct Encoder {
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  std::vector<uint8_t> shuffled;
  ~Encoder() { ZSTD_freeCCtx(cctx); }
};
Encoder& thread_encoder() {
  thread_local Encoder encoder;
  return encoder;
}
}  // namespace

bool encode_zstd_frames(const uint8_t* raw, uint64_t size, int level, uint64_t frame_size,
                        bool shuffle, std::vector<uint8_t>* stored, std::string* why) {
  const uint64_t n = frame_count(size, frame_size);
  std::vector<std::vector<uint8_t>> frames(n);
  std::vector<std::string> errors(n);
  tbb::parallel_for(
      tbb::blocked_range<uint64_t>(0, n, 1), [&](const tbb::blocked_range<uint64_t>& r) {
        Encoder& e = thread_encoder();
        if (e.cctx == nullptr) {
          for (uint64_t k = r.begin(); k != r.end(); ++k)
            errors[k] = "cannot create a zstd context";
          return;
        }
        // Each frame depends only on its block and the level (never on threading).
        ZSTD_CCtx_reset(e.cctx, ZSTD_reset_session_and_parameters);
        ZSTD_CCtx_setParameter(e.cctx, ZSTD_c_compressionLevel, level);
        ZSTD_CCtx_setParameter(e.cctx, ZSTD_c_contentSizeFlag, 1);
        ZSTD_CCtx_setParameter(e.cctx, ZSTD_c_checksumFlag, 0);  // the index's XXH3 covers it
        if (shuffle && e.shuffled.size() < frame_size) e.shuffled.resize(frame_size);
        for (uint64_t k = r.begin(); k != r.end(); ++k) {
          const uint64_t at = k * frame_size, m = std::min(frame_size, size - at);
          const uint8_t* src = raw + at;
          if (shuffle) {
            shuffle4(src, e.shuffled.data(), m);
            src = e.shuffled.data();
          }
          std::vector<uint8_t>& f = frames[k];
          f.resize(ZSTD_compressBound(m));
          const size_t got = ZSTD_compress2(e.cctx, f.data(), f.size(), src, m);
          if (ZSTD_isError(got)) {
            errors[k] = std::string("zstd: ") + ZSTD_getErrorName(got);
            continue;
          }
          f.resize(got);
        }
      });
  for (const std::string& e : errors)
    if (!e.empty()) {
      *why = e;
      return false;
    }
  const uint64_t index = sizeof(FrameIndexHeader) + n * sizeof(FrameEntry);
  uint64_t total = index;
  for (const std::vector<uint8_t>& f : frames) total += f.size();
  stored->assign(total, 0);
  const FrameIndexHeader header{uint32_t(frame_size), shuffle ? uint32_t(kFrameShuffle4) : 0, 0};
  std::memcpy(stored->data(), &header, sizeof header);
  uint8_t* out = stored->data() + index;
  for (uint64_t k = 0; k < n; ++k) {
    FrameEntry entry{};
    entry.stored_size = uint32_t(frames[k].size());  // <= compressBound(16 MiB)
    entry.checksum = checksum64(frames[k].data(), frames[k].size());
    std::memcpy(stored->data() + sizeof header + k * sizeof(FrameEntry), &entry, sizeof entry);
    std::memcpy(out, frames[k].data(), frames[k].size());
    out += frames[k].size();
  }
  return true;
}

bool read_frame_header(const uint8_t* stored, uint64_t stored_size, uint64_t raw_size,
                       FrameIndex* index, std::string* why) {
  FrameIndexHeader h;
  if (stored_size < sizeof h) {
    *why = "the frame index header does not fit in " + std::to_string(stored_size) + " bytes";
    return false;
  }
  std::memcpy(&h, stored, sizeof h);
  if (h.frame_size < kMinFrameSize || h.frame_size > kMaxFrameSize ||
      (h.frame_size & (h.frame_size - 1)) != 0) {
    *why = "frame size " + std::to_string(h.frame_size) +
           " is not a power of two from 64 KiB to 16 MiB";
    return false;
  }
  if ((h.flags & ~uint32_t(kFrameShuffle4)) != 0 || h.reserved != 0) {
    *why = "unknown frame flags or reserved bits set";
    return false;
  }
  // raw_size <= 2^40 (the reader checked it) and frame_size >= 2^16: no overflow.
  const uint64_t n = frame_count(raw_size, h.frame_size);
  index->frame_size = h.frame_size;
  index->shuffled = (h.flags & kFrameShuffle4) != 0;
  index->index_bytes = sizeof h + n * sizeof(FrameEntry);
  index->frames.clear();
  if (index->index_bytes > stored_size) {
    *why = "the frame index of " + std::to_string(n) + " entries does not fit in " +
           std::to_string(stored_size) + " stored bytes";
    return false;
  }
  return true;
}

bool read_frame_entries(const uint8_t* stored, uint64_t stored_size, FrameIndex* index,
                        std::string* why) {
  const uint64_t n = (index->index_bytes - sizeof(FrameIndexHeader)) / sizeof(FrameEntry);
  uint64_t at = index->index_bytes;
  index->frames.reserve(n);
  for (uint64_t k = 0; k < n; ++k) {
    FrameEntry e;
    std::memcpy(&e, stored + sizeof(FrameIndexHeader) + k * sizeof(FrameEntry), sizeof e);
    if (e.reserved != 0) {
      *why = "frame " + std::to_string(k) + ": reserved field is not zero";
      return false;
    }
    if (e.stored_size == 0 || e.stored_size > stored_size - at) {
      *why = "frame " + std::to_string(k) + ": " + std::to_string(e.stored_size) +
             " bytes at offset " + std::to_string(at) + " do not fit in the " +
             std::to_string(stored_size) + " stored bytes";
      return false;
    }
    index->frames.push_back(FrameRef{at, e.stored_size, e.checksum});
    at += e.stored_size;
  }
  if (at != stored_size) {
    *why = std::to_string(stored_size - at) + " stored bytes follow the last frame";
    return false;
  }
  return true;
}

bool is_one_zstd_frame(const uint8_t* src, uint64_t size, uint64_t content_size,
                       const std::string& expected, std::string* why) {
  // A skippable frame (magic 0x184D2A5?) would pass as content size 0: only a data frame will do.
  uint32_t magic = 0;
  if (size >= 4) std::memcpy(&magic, src, 4);  // a little-endian host (archive_reader.cpp)
  const unsigned long long content =
      magic == ZSTD_MAGICNUMBER ? ZSTD_getFrameContentSize(src, size) : ZSTD_CONTENTSIZE_ERROR;
  if (content == ZSTD_CONTENTSIZE_ERROR) {
    *why = "zstd: not a zstd frame";
    return false;
  }
  if (content == ZSTD_CONTENTSIZE_UNKNOWN) {
    *why = "zstd: the frame does not record its size";
    return false;
  }
  if (content != content_size) {
    *why = "zstd frame content size is " + std::to_string(content) + " but " + expected;
    return false;
  }
  const size_t whole = ZSTD_findFrameCompressedSize(src, size);
  if (ZSTD_isError(whole)) {
    *why = std::string("zstd: ") + ZSTD_getErrorName(whole);
    return false;
  }
  if (whole != size) {
    *why = std::to_string(size - whole) + " bytes follow the zstd frame";
    return false;
  }
  return true;
}

bool decode_frame(ZSTD_DCtx* dctx, const uint8_t* frame, const FrameRef& ref, uint64_t block_size,
                  bool shuffled, uint8_t* scratch, uint8_t* dst, std::string* why) {
  if (checksum64(frame, ref.size) != ref.checksum) {
    *why = "checksum mismatch";
    return false;
  }
  if (!is_one_zstd_frame(frame, ref.size, block_size,
                         "the block has " + std::to_string(block_size) + " bytes", why))
    return false;
  uint8_t* out = shuffled ? scratch : dst;
  const size_t got = ZSTD_decompressDCtx(dctx, out, block_size, frame, ref.size);
  if (ZSTD_isError(got)) {
    *why = std::string("zstd: ") + ZSTD_getErrorName(got);
    return false;
  }
  if (got != block_size) {
    *why = "zstd frame decoded to " + std::to_string(got) + " bytes but the block has " +
           std::to_string(block_size);
    return false;
  }
  if (shuffled) unshuffle4(scratch, dst, block_size);
  return true;
}

}  // namespace pbrta
