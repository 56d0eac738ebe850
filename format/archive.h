// format/archive.h — the on-disk structures of a pbrtc scene archive (.pbrta).
//
// The archive is the one contract between pbrtc (which writes it) and pbrtrun
// (which reads it); format/ARCHIVE.md is its specification, and this header
// is that document's structures as C++. Every structure here is plain data
// with fixed-width fields, stored little-endian, with reserved fields written
// as zero and checked on read; static_asserts pin their sizes. The archive
// is: a 64-byte Header, a table of SectionEntry, then the sections, each at a
// 16-byte aligned offset and followed by at least 16 zero bytes of padding
// (so an uncompressed section can be handed to Embree in place from a
// memory map: it reads vertex buffers with 16-byte loads past the last
// element).
//
// Sections hold arrays of the records below, or raw arrays (geometry, image
// texels, strings). References between records are uint32 indices into
// another section's array; kNoIndex (0xFFFFFFFF) means none.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pbrta {

inline constexpr uint8_t kMagic[8] = {0x89, 'P', 'B', 'R', 'T', 'A', 0x0D, 0x0A};
inline constexpr uint16_t kMajorVersion = 2;
inline constexpr uint16_t kMinorVersion = 1;
inline constexpr uint32_t kNoIndex = 0xFFFFFFFFu;
inline constexpr uint64_t kSectionAlignment = 16;
inline constexpr uint64_t kSectionPadding = 16;

// Effects the scene calls for (Header::effects): the runtime simulates only these.
enum Effect : uint64_t {
  kEffectMedia = 1u << 0,
  kEffectMotionBlur = 1u << 1,
  kEffectTextures = 1u << 2,
  kEffectAreaLights = 1u << 3,
  kEffectInfiniteLights = 1u << 4,
  kEffectSubsurface = 1u << 5,
  kEffectInstancing = 1u << 6,
  kEffectAlpha = 1u << 7,
  kEffectAll = (1u << 8) - 1,
};

struct Header {
  uint8_t magic[8];
  uint16_t major;
  uint16_t minor;
  uint32_t flags;  // reserved, 0 in 2.x
  uint64_t effects;
  uint32_t section_count;
  uint32_t reserved0;
  uint64_t table_offset;     // 64: the table follows the header
  uint64_t file_size;        // the whole file, padding included
  uint64_t table_checksum;   // XXH3-64 (seed 0) of the section table's bytes
  uint64_t header_checksum;  // XXH3-64 (seed 0) of bytes 0..55 of the header
};
static_assert(sizeof(Header) == 64, "Header is 64 bytes");

// How a section's bytes are stored (ARCHIVE.md section 5 says which sections use which, and why).
enum class Codec : uint32_t {
  kRaw = 0,    // the raw bytes, checksummed by kRawChunk chunks; usable in place from a mapping
  kZstd = 1,   // a FrameIndexHeader, a FrameEntry per frame, then independent zstd frames
  kDraco = 2,  // a Draco mesh stream (lossy); only a geometry section of one mesh
  kCount
};

// A raw section's checksum is XXH3-64 of the XXH3-64 values (u64 each, in order) of its bytes cut
// into chunks of this many bytes (the last shorter): the chunks hash on every thread at once.
inline constexpr uint64_t kRawChunk = uint64_t{1} << 20;

// A zstd section's stored bytes start with this header, then frame_count FrameEntry, one per
// block of frame_size raw bytes (the last shorter), then the frames in block order. The section's
// checksum covers the header and the entries; each entry's checksum covers its frame.
struct FrameIndexHeader {
  uint32_t frame_size;  // a power of two in [kMinFrameSize, kMaxFrameSize]
  uint32_t flags;       // FrameFlag
  uint64_t reserved;    // 0
};
static_assert(sizeof(FrameIndexHeader) == 16, "FrameIndexHeader is 16 bytes");
inline constexpr uint64_t kMinFrameSize = uint64_t{64} << 10;
inline constexpr uint64_t kMaxFrameSize = uint64_t{16} << 20;

enum FrameFlag : uint32_t {
  kFrameShuffle4 = 1u << 0,  // each block was byte-shuffled in 4-byte lanes before compression
};

struct FrameEntry {
  uint32_t stored_size;  // the frame's bytes
  uint32_t reserved;     // 0
  uint64_t checksum;     // XXH3-64 (seed 0) of the frame's bytes
};
static_assert(sizeof(FrameEntry) == 16, "FrameEntry is 16 bytes");

enum class SectionKind : uint32_t {
  kScene = 1,          // one SceneRecord
  kStrings = 2,        // string table (see ARCHIVE.md)
  kEntities = 3,       // EntityRecord[]
  kValues = 4,         // ValueRecord[]
  kWords = 5,          // uint32[]: entity data (float bits, ints, bools, string indices)
  kTransforms = 6,     // TransformRecord[]
  kTextures = 7,       // TextureRecord[]
  kMaterials = 8,      // MaterialRecord[]
  kMedia = 9,          // MediumRecord[]
  kLights = 10,        // LightRecord[]
  kAreaLights = 11,    // uint32[]: the entity of each area light
  kShapes = 12,        // ShapeRecord[]
  kObjects = 13,       // ObjectRecord[]
  kObjectShapes = 14,  // uint32[]: shape indices, ranges of ObjectRecord
  kInstances = 15,     // InstanceRecord[]
  kMeshes = 16,        // MeshRecord[]
  kGeometry = 17,      // raw mesh arrays; MeshRecord points into these
  kImages = 18,        // ImageRecord[]
  kTexels = 19,        // raw image data; ImageRecord points into these
  kProvenance = 20,    // ProvenanceRecord[], one per entity, then per object and instance
  kCount
};

struct SectionEntry {
  uint32_t kind;         // SectionKind
  uint32_t codec;        // Codec
  uint64_t offset;       // from the start of the file; a multiple of 16
  uint64_t stored_size;  // bytes in the file (before padding)
  uint64_t raw_size;     // bytes after decoding
  uint64_t checksum;     // by codec: chunked (raw), of the frame index (zstd), plain (draco)
  uint32_t count;        // records (or elements) in the section
  uint32_t reserved;     // 0
};
static_assert(sizeof(SectionEntry) == 48, "SectionEntry is 48 bytes");

// The scene's top level: render options and the counts every reader checks
// other sections against.
struct SceneRecord {
  uint32_t camera;            // entity
  uint32_t camera_transform;  // transform: camera from world (start/end)
  uint32_t camera_medium;     // medium or kNoIndex
  uint32_t film, filter, sampler, integrator, accelerator;  // entities
  uint32_t num_entities, num_values, num_words, num_strings;
  uint32_t num_transforms, num_textures, num_materials, num_media;
  uint32_t num_lights, num_area_lights, num_shapes, num_objects;
  uint32_t num_object_shapes, num_instances, num_meshes, num_images;
  uint32_t reserved[4];
};
static_assert(sizeof(SceneRecord) == 112, "SceneRecord is 112 bytes");

// An instance of a schema type (format/schema.h): category, type index, and
// one ValueRecord per schema parameter, in schema order, starting at
// first_value.
struct EntityRecord {
  uint8_t category;  // Category
  uint8_t reserved0;
  uint16_t type;  // index into the category's types
  uint32_t first_value;
  uint32_t num_values;  // the type's num_params when written (ARCHIVE.md: minor versions)
  uint32_t reserved1;
};
static_assert(sizeof(EntityRecord) == 16, "EntityRecord is 16 bytes");

enum ValueFlag : uint32_t {
  kValueGiven = 1u << 0,  // written in the scene; otherwise the schema default
};

// One parameter value: count elements of the schema kind, stored as 32-bit
// words starting at words[offset] (a point3 or rgb is 3 words; a string is one
// word holding a string index). texture is a texture index for kFloatTex and
// kSpectrumTex parameters bound to a texture, else kNoIndex.
struct ValueRecord {
  uint32_t offset;
  uint32_t count;
  uint32_t texture;
  uint32_t flags;  // ValueFlag
};
static_assert(sizeof(ValueRecord) == 16, "ValueRecord is 16 bytes");

// Row-major 4x4 matrices acting on column vectors, in double precision so
// scenes far from the origin keep their precision until the renderer picks
// its render space. start == end when not animated.
struct TransformRecord {
  double start[16];
  double end[16];
  double start_time;
  double end_time;
};
static_assert(sizeof(TransformRecord) == 272, "TransformRecord is 272 bytes");

// Names and file names are provenance (they say where data came from, not
// what it is): they live in the provenance section, not in these records.
struct TextureRecord {
  uint32_t entity;  // kFloatTexture or kSpectrumTexture
  uint32_t reserved;
  uint32_t transform;  // world from texture
  uint32_t image;      // decoded image (imagemap), or kNoIndex
};
static_assert(sizeof(TextureRecord) == 16, "TextureRecord is 16 bytes");

struct MaterialRecord {
  uint32_t entity;  // kMaterial; type "none" is the interface material ""
  uint32_t reserved;
  uint32_t mix[2];  // mix: namedmaterial1, namedmaterial2 as material indices
};
static_assert(sizeof(MaterialRecord) == 16, "MaterialRecord is 16 bytes");

struct MediumRecord {
  uint32_t entity;
  uint32_t transform;  // world from medium
  uint32_t reserved[2];
};
static_assert(sizeof(MediumRecord) == 16, "MediumRecord is 16 bytes");

struct LightRecord {
  uint32_t entity;
  uint32_t transform;  // world from light
  uint32_t medium;     // outside medium or kNoIndex
  uint32_t image;      // infinite/projection/goniometric map, or kNoIndex
};
static_assert(sizeof(LightRecord) == 16, "LightRecord is 16 bytes");

enum ShapeFlag : uint32_t {
  kShapeReverseOrientation = 1u << 0,
  kShapeSwapsHandedness = 1u << 1,  // world from object mirrors orientation
};

struct ShapeRecord {
  uint32_t entity;
  uint32_t mesh;  // MeshRecord (trianglemesh, plymesh, refined shapes), or kNoIndex
  uint32_t material;
  uint32_t area_light;  // index into the area lights, or kNoIndex
  uint32_t inside_medium, outside_medium;
  uint32_t transform;  // world from object
  uint32_t object;     // the object definition it belongs to, or kNoIndex (world)
  uint32_t flags;      // ShapeFlag
  uint32_t reserved;
};
static_assert(sizeof(ShapeRecord) == 40, "ShapeRecord is 40 bytes");

struct ObjectRecord {
  uint32_t reserved;
  uint32_t first_shape;  // into the object-shapes array
  uint32_t num_shapes;
  uint32_t provenance;
};
static_assert(sizeof(ObjectRecord) == 16, "ObjectRecord is 16 bytes");

struct InstanceRecord {
  uint32_t object;
  uint32_t transform;  // world from instance
  uint32_t provenance;
  uint32_t reserved;
};
static_assert(sizeof(InstanceRecord) == 16, "InstanceRecord is 16 bytes");

enum MeshFlag : uint32_t {
  kMeshNormals = 1u << 0,
  kMeshTangents = 1u << 1,
  kMeshUV = 1u << 2,
  kMeshFaceIndices = 1u << 3,
};

// A triangle mesh's arrays inside one kGeometry section, each at a 16-byte
// aligned byte offset from the section's start (after decoding): positions
// float[3 * num_vertices]; normals, tangents float[3 * num_vertices]; uv
// float[2 * num_vertices]; indices uint32[3 * num_triangles]; face indices
// int32[num_triangles]. Absent arrays have offset 0 and their flag clear.
struct MeshRecord {
  uint32_t num_vertices;
  uint32_t num_triangles;
  uint32_t flags;    // MeshFlag
  uint32_t section;  // index of the kGeometry section in the table
  uint64_t positions, normals, tangents, uv, indices, face_indices;
  uint32_t refine_level;  // loopsubdiv levels / nurbs tessellation used, 0 if none
  uint32_t source_shape;  // the shape this mesh was refined from, or kNoIndex
};
static_assert(sizeof(MeshRecord) == 72, "MeshRecord is 72 bytes");

// Where a record came from. The provenance section is self-contained:
//   u32 num_records, u32 num_strings, ProvenanceRecord[num_records],
//   u32 string_offsets[num_strings + 1], then the characters;
// its strings are indices into that local table, so the rest of the archive
// does not depend on file or entity names (an archive recompiled from its
// own dump is byte-identical outside this section).
struct ProvenanceRecord {
  uint32_t file;  // local string: the scene file, relative to the top-level scene's directory
  uint32_t line;  // 1-based; 0 for defaults the scene did not write
  uint32_t name;  // local string: the name given (texture, material, medium, object), or 0
  uint32_t path;  // local string: the file a file-name parameter named (mesh, image), or 0
};
static_assert(sizeof(ProvenanceRecord) == 16, "ProvenanceRecord is 16 bytes");

enum class PixelFormat : uint32_t { kFloat32 = 0, kHalf16 = 1, kUnorm8 = 2 };

// A decoded image with its MIP pyramid: level 0 is width x height, each next
// level halves (rounding down, at least 1), channels interleaved, rows top
// to bottom. All levels lie in one kTexels section starting at offset, level
// after level, each level 16-byte aligned.
struct ImageRecord {
  uint32_t width, height;
  uint32_t channels;  // 1 or 3
  uint32_t levels;
  uint32_t format;        // PixelFormat
  uint32_t section;       // the kTexels section
  uint64_t offset;        // of level 0
  uint32_t wrap;          // 0 repeat, 1 black, 2 clamp
  uint32_t distribution;  // for environment maps: the image index of the sampling
                          // distribution (kNoIndex if none)
  // The decoded file's own size, before resampling to powers of two: the
  // projection light takes its aspect ratio from it, as pbrt-v3 does.
  uint32_t source_width, source_height;
  // The image as decoded, before resampling (another ImageRecord: levels 1,
  // source_width x source_height), or kNoIndex when level 0 already is it.
  // The pyramid cannot be undone, so this is what lets pbrtc --dump write a
  // file that compiles back to the same pyramid and source size.
  uint32_t source_image;
  uint32_t reserved[3];
};
static_assert(sizeof(ImageRecord) == 64, "ImageRecord is 64 bytes");

// The levels of pbrt-v3's MIPMap over a level 0 of width x height: 1 + floor(log2 of the larger
// side). pbrtc builds that many, and the reader checks that textures and light maps have them.
inline constexpr uint32_t full_pyramid_levels(uint32_t width, uint32_t height) {
  uint32_t levels = 1;
  for (uint32_t side = width > height ? width : height; side > 1; side >>= 1) ++levels;
  return levels;
}

}  // namespace pbrta
