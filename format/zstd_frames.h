// format/zstd_frames.h — the zstd codec (ARCHIVE.md section 5): a section as independent frames.
//
// The raw bytes are cut into blocks of frame_size bytes (the last shorter; none when empty), each
// block optionally byte-shuffled (below), then compressed into its own zstd frame that records its
// content size. The stored bytes are a FrameIndexHeader, one FrameEntry per block, then the frames
// back to back in block order. The section table's checksum covers the header and the entries;
// each entry's checksum covers its frame.
//
// Why frames: the frames of one large section decode on every thread at once, each one-shot
// while its bytes are in cache. Why the shuffle: grouping the bytes of 4-byte numbers by
// significance lets zstd find their redundancy (mesh geometry shrinks by a third or more).
//
// Failure: the reader functions take untrusted bytes; they return false with the reason in *why
// (no path or section: the caller adds them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <zstd.h>

#include "format/archive.h"

namespace pbrta {

// The shuffle of a block of size bytes: all byte-0s of its size / 4 little-endian 4-byte words,
// then all byte-1s, byte-2s, byte-3s, then its size % 4 tail bytes as they are. src and dst must
// not overlap.
void shuffle4(const uint8_t* src, uint8_t* dst, uint64_t size);
void unshuffle4(const uint8_t* src, uint8_t* dst, uint64_t size);

// Frames (and index entries) of a section of raw_size bytes in frames of frame_size bytes.
uint64_t frame_count(uint64_t raw_size, uint64_t frame_size);

// The stored bytes for size raw bytes, at a zstd level, in frames of frame_size bytes (a power of
// two in [kMinFrameSize, kMaxFrameSize]), shuffled or not; parallel over frames on the caller's
// oneTBB arena, and the same bytes whatever the thread count. False only when zstd fails (out of
// memory).
bool encode_zstd_frames(const uint8_t* raw, uint64_t size, int level, uint64_t frame_size,
                        bool shuffle, std::vector<uint8_t>* stored, std::string* why);

// One frame: where it lies within the stored bytes and what its bytes hash to.
struct FrameRef {
  uint64_t offset;
  uint64_t size;
  uint64_t checksum;
};

// A section's frame index, read from its stored bytes (stored_size of them): the header's frame
// size and flags, and the frames tiling the bytes after the index exactly.
struct FrameIndex {
  uint64_t frame_size = 0;
  bool shuffled = false;
  uint64_t index_bytes = 0;  // header and entries: what the section table's checksum covers
  std::vector<FrameRef> frames;
};

// The header and where the index ends: false when the header is malformed (a frame size that is
// not a power of two in [kMinFrameSize, kMaxFrameSize], an unknown flag, reserved bits set) or
// the index does not fit in the stored bytes.
bool read_frame_header(const uint8_t* stored, uint64_t stored_size, uint64_t raw_size,
                       FrameIndex* index, std::string* why);
// Then the entries (after the caller has verified index_bytes against the section's checksum):
// every entry's reserved field zero, no frame empty, and the frames tiling the rest exactly.
bool read_frame_entries(const uint8_t* stored, uint64_t stored_size, FrameIndex* index,
                        std::string* why);

// True when src holds exactly one zstd frame that records a content size of content_size. Else
// the reason, naming `expected` ("the block has 123 bytes") where the recorded size differs.
bool is_one_zstd_frame(const uint8_t* src, uint64_t size, uint64_t content_size,
                       const std::string& expected, std::string* why);

// Verifies one frame's checksum and that it is one zstd frame of block_size bytes, then decodes it
// into dst (block_size bytes), through scratch (block_size bytes) when shuffled.
bool decode_frame(ZSTD_DCtx* dctx, const uint8_t* frame, const FrameRef& ref, uint64_t block_size,
                  bool shuffled, uint8_t* scratch, uint8_t* dst, std::string* why);

}  // namespace pbrta
