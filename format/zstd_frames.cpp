#include "format/zstd_frames.h"

#include <algorithm>
#include <cstring>

// For zstd's buffer-less streaming (ZSTD_decompressBegin, ZSTD_decompressContinue): exported by
// the shared library (Debian 12: 1.5.4).
#define ZSTD_STATIC_LINKING_ONLY
#include <zstd.h>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include "format/byte_shuffle.h"
#include "format/checksum.h"

namespace pbrta {

namespace {

// One encoding thread's compression context and shuffle buffer.
struct Encoder {
  ZSTD_CCtx* cctx = nullptr;
  std::vector<uint8_t> shuffled;
  Encoder() = default;
  Encoder(const Encoder&) {}  // a fresh one: contexts are per thread
  Encoder& operator=(const Encoder&) = delete;
  ~Encoder() { ZSTD_freeCCtx(cctx); }
};

}  // namespace

uint64_t frame_count(uint64_t raw_size, uint64_t block) {
  return raw_size / block + (raw_size % block != 0 ? 1 : 0);
}

bool encode_zstd_frames(const uint8_t* raw, uint64_t size, int level, uint64_t block,
                        std::vector<uint8_t>* stored, std::string* why) {
  const uint64_t n = frame_count(size, block);
  std::vector<std::vector<uint8_t>> frames(n);
  std::vector<std::string> errors(n);
  tbb::enumerable_thread_specific<Encoder> encoders;
  tbb::parallel_for(
      tbb::blocked_range<uint64_t>(0, n, 1), [&](const tbb::blocked_range<uint64_t>& r) {
        Encoder& e = encoders.local();
        if (e.cctx == nullptr) {
          e.cctx = ZSTD_createCCtx();
          if (e.cctx == nullptr) {
            for (uint64_t k = r.begin(); k != r.end(); ++k)
              errors[k] = "cannot create a zstd context";
            return;
          }
          // Each frame depends only on its block and the level (never on threading).
          ZSTD_CCtx_setParameter(e.cctx, ZSTD_c_compressionLevel, level);
          ZSTD_CCtx_setParameter(e.cctx, ZSTD_c_contentSizeFlag, 1);
          ZSTD_CCtx_setParameter(e.cctx, ZSTD_c_checksumFlag, 0);  // the index's XXH3 covers it
          e.shuffled.resize(block);
        }
        for (uint64_t k = r.begin(); k != r.end(); ++k) {
          const uint64_t at = k * block, m = std::min(block, size - at);
          shuffle4(raw + at, e.shuffled.data(), m);
          std::vector<uint8_t>& f = frames[k];
          f.resize(ZSTD_compressBound(m));
          const size_t got = ZSTD_compress2(e.cctx, f.data(), f.size(), e.shuffled.data(), m);
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
  uint64_t total = n * sizeof(FrameEntry);
  for (const std::vector<uint8_t>& f : frames) total += f.size();
  stored->assign(total, 0);
  uint8_t* out = stored->data() + n * sizeof(FrameEntry);
  for (uint64_t k = 0; k < n; ++k) {
    FrameEntry entry{};
    entry.stored_size = static_cast<uint32_t>(frames[k].size());  // <= compressBound(4 MiB)
    entry.checksum = checksum64(frames[k].data(), frames[k].size());
    std::memcpy(stored->data() + k * sizeof(FrameEntry), &entry, sizeof entry);
    std::memcpy(out, frames[k].data(), frames[k].size());
    out += frames[k].size();
  }
  return true;
}

bool read_frame_index(const uint8_t* index, uint64_t raw_size, uint64_t stored_size, uint64_t block,
                      std::vector<FrameRef>* frames, std::string* why) {
  const uint64_t n = frame_count(raw_size, block);
  frames->clear();
  // n <= 2^40 / 2^18 and sizeof(FrameEntry) = 16: no overflow.
  uint64_t at = n * sizeof(FrameEntry);
  if (at > stored_size) {
    *why = "the frame index of " + std::to_string(n) + " entries does not fit in " +
           std::to_string(stored_size) + " stored bytes";
    return false;
  }
  frames->reserve(n);
  for (uint64_t k = 0; k < n; ++k) {
    FrameEntry e;
    std::memcpy(&e, index + k * sizeof(FrameEntry), sizeof e);
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
    frames->push_back(FrameRef{at, e.stored_size, e.checksum});
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

uint32_t frame_piece_count(uint64_t block_size) {
  return static_cast<uint32_t>(frame_count(block_size, kShuffleBlock));
}

uint64_t frame_piece_end(uint32_t piece, uint64_t block_size) {
  return std::min(uint64_t{piece + 1} * kShuffleBlock, block_size);
}

bool decode_frame_shuffled(ZSTD_DCtx* dctx, const uint8_t* frame, const FrameRef& ref,
                           uint64_t block_size, uint8_t* scratch, std::atomic<uint64_t>* decoded,
                           std::string* why) {
  if (checksum64(frame, ref.size) != ref.checksum) {
    *why = "checksum mismatch";
    return false;
  }
  if (!is_one_zstd_frame(frame, ref.size, block_size,
                         "the block has " + std::to_string(block_size) + " bytes", why))
    return false;
  auto zstd_error = [&](size_t code) {
    *why = std::string("zstd: ") + ZSTD_getErrorName(code);
    return false;
  };
  // zstd's buffer-less streaming: the same block decoder as one-shot decoding, into the same
  // contiguous output (earlier output stays where later blocks refer to it, so there is no window
  // buffer to copy through), but returning after each block, so the pieces decoded so far can be
  // handed on.
  const size_t begun = ZSTD_decompressBegin(dctx);
  if (ZSTD_isError(begun)) return zstd_error(begun);
  uint64_t in = 0, out = 0;
  for (size_t need = ZSTD_nextSrcSizeToDecompress(dctx); need != 0;
       need = ZSTD_nextSrcSizeToDecompress(dctx)) {
    if (need > ref.size - in) {  // is_one_zstd_frame measured it, but a block may still lie
      *why = "zstd: the frame ends inside a block";
      return false;
    }
    const size_t got =
        ZSTD_decompressContinue(dctx, scratch + out, block_size - out, frame + in, need);
    if (ZSTD_isError(got)) return zstd_error(got);
    in += need;
    out += got;
    if (got != 0) decoded->store(out, std::memory_order_release);
  }
  if (out != block_size || in != ref.size) {
    *why = "zstd frame decoded to " + std::to_string(out) + " bytes but the block has " +
           std::to_string(block_size);
    return false;
  }
  return true;
}

void unshuffle_frame_piece(const uint8_t* scratch, uint8_t* dst, uint64_t block_size,
                           uint32_t piece, const WordBound* bounds, uint64_t num_bounds,
                           bool stream, std::vector<uint32_t>* exceeded) {
  const uint64_t at = uint64_t{piece} * kShuffleBlock, end = frame_piece_end(piece, block_size);
  // The bounds' parts inside this piece, relative to it. (Sorted by begin is all this needs:
  // overlapping bounds are each checked whole.)
  thread_local std::vector<WordBound> part;
  thread_local std::vector<uint32_t> from;
  part.clear();
  from.clear();
  for (uint64_t k = 0; k < num_bounds && bounds[k].begin < end; ++k) {
    if (bounds[k].end <= at) continue;
    part.push_back(WordBound{std::max(bounds[k].begin, at) - at, std::min(bounds[k].end, end) - at,
                             bounds[k].limit, false});
    from.push_back(static_cast<uint32_t>(k));
  }
  unshuffle4_block(scratch + at, dst + at, end - at, part.data(), part.size(), stream);
  for (size_t k = 0; k < part.size(); ++k)
    if (part[k].exceeded) exceeded->push_back(from[k]);
}

}  // namespace pbrta
