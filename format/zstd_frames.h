// format/zstd_frames.h — codecs 4 and 6 (kZstdShuffle4Frames, kZstdShuffle4Frames1M): a section
// as independent zstd frames.
//
// The raw bytes are cut into blocks of kFrameBlock bytes (4 MiB; codec 6: kSmallFrameBlock, 1 MiB;
// the last shorter; none when empty), each block is byte-shuffled on its own in kShuffleBlock
// pieces (format/byte_shuffle.h) and compressed into its own zstd frame, which records its content
// size. The stored bytes are a FrameEntry index (format/ archive.h), one entry per block, then the
// frames back to back in block order. The section table's checksum covers the index, each entry's
// checksum its frame.
//
// Why: a block is then read, verified, decoded and unshuffled while it sits in cache, one-shot
// (no streaming window to copy through), and the blocks of one large section decode on every
// thread at once instead of one section per thread.
//
// Failure: the reader functions take untrusted bytes; they return false with the reason in *why
// (no path or section: the caller adds them).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include <zstd.h>

#include "format/archive.h"
#include "format/byte_shuffle.h"

namespace pbrta {

// Raw bytes per frame (the last frame holds the rest), a multiple of kShuffleBlock. Measured on
// mesh200 (4.5M triangles), 256 KiB / 1 / 2 / 4 / 8 MiB frames: archives 38.7 / 32.7 / 29.5 /
// 26.1 / 24.8 MB (one frame per 16 MiB section: 24.3 MB); a frame cannot refer to an earlier one,
// and a scene repeats whole meshes (killeroo-simple includes one twice: 53% at 256 KiB, 28% at
// 4 MiB). 4 MiB keeps the size within 7% of one frame, loaded fastest, and still gives two
// threads four frames of a 16 MiB section to share.
inline constexpr uint64_t kFrameBlock = uint64_t{4} << 20;

// Codec 6's frames: for a section of a few MiB, which in 4 MiB frames would decode on one thread
// however many the reader has (caustic glass's 2 MiB of geometry: its archive loads on 2 threads
// in 0.68-0.76 ms as codec 4, 0.40-0.43 ms as codec 6). A frame cannot refer to bytes in another,
// so they cost some compression; the writer keeps them only where that is small
// (ArchiveWriter::choose_frame_size in format/archive_writer.h).
inline constexpr uint64_t kSmallFrameBlock = uint64_t{1} << 20;

// The block size of a framed codec (4 or 6); 0 for any other.
constexpr uint64_t frame_block(Codec codec) {
  return codec == Codec::kZstdShuffle4Frames     ? kFrameBlock
         : codec == Codec::kZstdShuffle4Frames1M ? kSmallFrameBlock
                                                 : 0;
}

// Frames (and index entries) of a section of raw_size bytes cut into blocks of block bytes.
uint64_t frame_count(uint64_t raw_size, uint64_t block);

// The stored bytes of codec 4 (block kFrameBlock) or 6 (kSmallFrameBlock) for size raw bytes, at
// a zstd level; parallel over blocks on the caller's oneTBB arena, and the same bytes whatever the
// thread count. False only when zstd fails (out of memory).
bool encode_zstd_frames(const uint8_t* raw, uint64_t size, int level, uint64_t block,
                        std::vector<uint8_t>* stored, std::string* why);

// One frame: where it lies within the stored bytes and what its bytes hash to.
struct FrameRef {
  uint64_t offset;
  uint64_t size;
  uint64_t checksum;
};

// Lays out the frames from an index (frame_count(raw_size, block) entries, already verified against
// the section's checksum): every entry's reserved field zero, no frame empty, and the frames tiling
// the stored bytes after the index exactly.
bool read_frame_index(const uint8_t* index, uint64_t raw_size, uint64_t stored_size, uint64_t block,
                      std::vector<FrameRef>* frames, std::string* why);

// True when src holds exactly one zstd frame that records a content size of content_size
// (codecs 1 and 2: the whole section; codec 4: each frame). Else the reason, naming `expected`
// ("the table says 123") where the recorded size differs.
bool is_one_zstd_frame(const uint8_t* src, uint64_t size, uint64_t content_size,
                       const std::string& expected, std::string* why);

// A frame is decoded in two steps, which may run on different threads: decode_frame_shuffled
// decodes it into a scratch block, and unshuffle_frame_piece then unshuffles each of its pieces
// (kShuffleBlock bytes; the last may be shorter) from there into place. A piece may be unshuffled
// as soon as its bytes have decoded, while the rest of the frame still decodes.

// Pieces of a frame of block_size bytes, and where piece `piece` ends (it starts at
// piece * kShuffleBlock).
uint32_t frame_piece_count(uint64_t block_size);
uint64_t frame_piece_end(uint32_t piece, uint64_t block_size);

// Verifies a frame's checksum and that it is exactly one zstd frame recording block_size bytes,
// then decodes it into scratch (at least block_size bytes), one zstd block at a time: after each,
// *decoded holds (stored with release order) how many bytes of scratch are final. It ends at
// block_size, or false with the reason (the frame held other than block_size bytes, or is
// corrupt).
bool decode_frame_shuffled(ZSTD_DCtx* dctx, const uint8_t* frame, const FrameRef& ref,
                           uint64_t block_size, uint8_t* scratch, std::atomic<uint64_t>* decoded,
                           std::string* why);

// Unshuffles piece `piece` of a decoded frame of block_size bytes from scratch into dst (each the
// start of the frame's block), checking the parts of the bounds (byte offsets in the block, sorted
// by begin) that lie in it. Appends to *exceeded the index of each bound that has a word at or
// above its limit in this piece. stream: see unshuffle4_block.
void unshuffle_frame_piece(const uint8_t* scratch, uint8_t* dst, uint64_t block_size,
                           uint32_t piece, const WordBound* bounds, uint64_t num_bounds,
                           bool stream, std::vector<uint32_t>* exceeded);

}  // namespace pbrta
