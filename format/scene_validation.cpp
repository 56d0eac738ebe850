// SceneArchive::validate_records and validate_geometry: every record of a loaded archive checked
// against the schema and against every other record it names, before anything reads it
// (format/scene_archive.h).
// Loading and the accessors are in format/scene_archive.cpp.
#include "format/scene_archive.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <optional>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PBRTA_CHECKS_AVX2 1  // built with a target attribute, chosen at run time
#endif

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "format/archive_names.h"
#include "format/check_threads.h"
#include "format/draco_codec.h"
#include "format/entity_rules.h"
#include "format/fourier_table.h"
#include "format/schema_digest.h"
#include "format/texel_format.h"

namespace pbrta {

namespace {

// Collects the first failure with its section; checks read as sentences.
class Checker {
 public:
  Checker(const std::string& path, const ArchiveReader& r) : path_(path), r_(r) {}

  // Sets the section later failures are reported against.
  void in(int section) { section_ = section; }

  bool fail(const std::string& what) {
    if (!failed_) {
      failed_ = true;
      message_ = path_ + ": ";
      if (section_ >= 0)
        message_ += "section '" +
                    std::string(section_kind_name(SectionKind(r_.entry(uint32_t(section_)).kind))) +
                    "' (#" + std::to_string(section_) + "): ";
      message_ += what;
    }
    return false;
  }
  // index < count, or NONE when allowed. Inline: the record loops call it ~10 times per shape.
  bool index(uint32_t i, uint32_t count, const char* record, uint32_t at, const char* field,
             const char* array, bool none_ok) {
    return i < count || (i == kNoIndex && none_ok) ||
           index_failed(i, count, record, at, field, array);
  }
  [[gnu::noinline]] bool index_failed(uint32_t i, uint32_t count, const char* record, uint32_t at,
                                      const char* field, const char* array) {
    return fail(
        std::string(record) + " " + std::to_string(at) + ": " + field + " " +
        (i == kNoIndex ? std::string("is missing") : std::to_string(i)) +
        (i == kNoIndex ? "" : " out of range (" + std::to_string(count) + " " + array + ")"));
  }
  bool failed() const { return failed_; }
  const std::string& message() const { return message_; }
  // One for another thread: same file and section, no failure yet.
  Checker blank() const {
    Checker b(path_, r_);
    b.section_ = section_;
    return b;
  }

 private:
  const std::string& path_;
  const ArchiveReader& r_;
  int section_ = -1;
  bool failed_ = false;
  std::string message_;
};

// The record flags this reader knows; any other bit refuses the record.
constexpr uint32_t kKnownShapeFlags = kShapeReverseOrientation | kShapeSwapsHandedness;
constexpr uint32_t kKnownMeshFlags = kMeshNormals | kMeshTangents | kMeshUV | kMeshFaceIndices;

// What the entity checks read most, held by value: through references, each entity would first
// walk from the closure to the archive to the span (the rare checks' calls keep the compiler from
// hoisting those loads out of the loop).
struct EntityInputs {
  const EntityRecord* entities;
  const ValueRecord* values;
  const uint32_t* words;
  const TextureRecord* textures;
  const SchemaDigest* digest;
  uint32_t num_textures, num_words, num_values, num_strings;
  uint16_t minor;
  bool avx2;
};

#if defined(PBRTA_CHECKS_AVX2)
// Entities [from, to) in order, up to the first that might be unsound, which it returns (or to).
// The ones it passes are sound, as entity_sound() in validate_records() judges them: a known
// type without count rules or string parameters, exactly its parameter count of values, and
// values with no texture, no unknown flag, a count the parameter's arity allows and words inside
// [0, num_words). The caller judges the entity it stops at by entity_sound().
//
// Why it is shaped so: it runs once per entity (150k for 100k shapes), and checked one by one,
// each value's checks (3 to 8 values in a typical scene) cost 17 vector operations a pair and a
// call per entity. Here the values go two per vector, against the type's lanes
// (TypeDigest::value_lanes), in 12 operations a pair; the lanes make the value after an odd
// count pass (it belongs to the next entity). An entity whose last pair would run past the last
// value is left to entity_sound(). Pairs, not groups of eight values: 1.61-1.66 ms of validation
// for same100k on one thread, against 1.81-1.85 for groups of eight (interleaved runs).
[[gnu::target("avx2")]] uint32_t plain_entities_avx2(const EntityInputs& in, uint32_t from,
                                                     uint32_t to) {
  const __m256i zero = _mm256_setzero_si256();
  // Lanes of a pair: offset, count, texture, flags; offset, count, texture, flags. Turns "no
  // texture" (kNoIndex) into 0.
  const __m256i texture_lanes = _mm256_setr_epi32(0, 0, -1, 0, 0, 0, -1, 0);
  const __m256i limit = _mm256_set1_epi64x(int64_t(in.num_words));
  const __m256i ones = _mm256_cmpeq_epi32(zero, zero);
  for (uint32_t i = from; i < to; ++i) {
    const EntityRecord& e = in.entities[i];
    if (e.type >= in.digest->num_types(e.category)) return i;
    const TypeDigest& t = in.digest->type(e.category, e.type);
    const uint32_t n = t.num_params;
    if ((t.has_rules | t.has_strings | e.reserved0) != 0 ||
        (e.reserved1 | (e.num_values ^ n)) != 0 ||
        uint64_t(e.first_value) + ((n + 1) & ~1u) > in.num_values)
      return i;
    const __m256i* v = reinterpret_cast<const __m256i*>(in.values + e.first_value);
    const __m256i* lanes = reinterpret_cast<const __m256i*>(t.value_lanes);
    __m256i ok = ones, past = zero;
    for (uint32_t pair = 0; pair < (n + 1) / 2; ++pair, ++v, lanes += 4) {
      const __m256i x = _mm256_loadu_si256(v);
      // Lane by lane, (y & mask) == 0 or y == expect: the texture 0 after the xor, the count 0
      // or the arity (or anything: mask 0), the flags none but kValueGiven.
      const __m256i y = _mm256_xor_si256(x, texture_lanes);
      ok = _mm256_and_si256(
          ok,
          _mm256_or_si256(_mm256_cmpeq_epi32(_mm256_and_si256(y, _mm256_load_si256(lanes)), zero),
                          _mm256_cmpeq_epi32(y, _mm256_load_si256(lanes + 1))));
      // offset + count * width, in 64 bits (64-bit lanes 0 and 2; 0 in the others), within
      // num_words.
      const __m256i end = _mm256_add_epi64(
          _mm256_and_si256(x, _mm256_load_si256(lanes + 2)),
          _mm256_mul_epu32(_mm256_srli_epi64(x, 32), _mm256_load_si256(lanes + 3)));
      past = _mm256_or_si256(past, _mm256_cmpgt_epi64(end, limit));
    }
    if (!_mm256_testc_si256(ok, ones) || !_mm256_testz_si256(past, past)) return i;
  }
  return to;
}

// What plain_shapes_avx2() reads: the shapes, the entities they name, and the bounds of a
// ShapeRecord's first eight fields (entity, mesh, material, area light, inside and outside medium,
// transform, object) in their order.
struct ShapeInputs {
  const ShapeRecord* shapes;
  const EntityRecord* entities;
  uint32_t bounds[8];
};
static_assert(offsetof(ShapeRecord, entity) == 0 && offsetof(ShapeRecord, object) == 28,
              "plain_shapes_avx2 reads a ShapeRecord's eight index fields as one vector");

// Shapes [from, to) in order, up to the first that might be unsound, which it returns (or to):
// the ones it passes are sound as the shape check in validate_records() judges them (every index
// in range, kNoIndex where a field may be absent, known flags, reserved zero, a shape entity).
// The eight index fields are one vector: 3.7 ns a shape one field at a time (100k shapes).
[[gnu::target("avx2")]] uint32_t plain_shapes_avx2(const ShapeInputs& in, uint32_t from,
                                                   uint32_t to) {
  // x < bound unsigned is (x ^ 2^31) < (bound ^ 2^31) signed.
  const __m256i bias = _mm256_set1_epi32(INT32_MIN);
  const __m256i limits =
      _mm256_xor_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(in.bounds)), bias);
  const __m256i none = _mm256_set1_epi32(-1);
  const __m256i may_be_none = _mm256_setr_epi32(0, -1, 0, -1, -1, -1, 0, -1);
  for (uint32_t i = from; i < to; ++i) {
    const ShapeRecord& s = in.shapes[i];
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&s));
    const __m256i ok = _mm256_or_si256(_mm256_cmpgt_epi32(limits, _mm256_xor_si256(x, bias)),
                                       _mm256_and_si256(_mm256_cmpeq_epi32(x, none), may_be_none));
    if (_mm256_movemask_epi8(ok) != -1 || ((s.flags & ~kKnownShapeFlags) | s.reserved) != 0 ||
        in.entities[s.entity].category != uint8_t(Category::kShape))
      return i;
  }
  return to;
}

bool have_avx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}
#endif

// A string table's n + 1 offsets (n >= 1) over data_size bytes of characters, as ARCHIVE.md
// section 6 has both tables (strings, provenance): from 0, never decreasing, ending at the
// data's end, and string 0 empty.
bool check_string_offsets(const uint32_t* offsets, uint32_t n, uint64_t data_size, Checker& c) {
  if (offsets[0] != 0) return c.fail("first string offset is not 0");
  for (uint32_t i = 0; i < n; ++i)
    if (offsets[i + 1] < offsets[i])
      return c.fail("string offsets decrease at string " + std::to_string(i));
  if (offsets[n] != data_size)
    return c.fail("string data is " + std::to_string(data_size) + " bytes, offsets say " +
                  std::to_string(offsets[n]));
  return offsets[1] == 0 || c.fail("string 0 is not empty");
}

// The first i in [0, n) at which scan stops, or n; 0, checking nothing, when c has already
// failed. scan(from, to, checker) checks records [from, to) in order and returns the first that
// fails, or to. A large n is checked in blocks on the arena's threads (no arena: on this one),
// each block stopping at its first failure; the lowest failing record is then checked again on c
// for the message, so the error is the one a serial check reports (100k shapes: 150k entities
// and 750k values, 100k shape and 50k mesh records).
template <class Scan>
uint32_t first_failure_scan(uint32_t n, tbb::task_arena* arena, Checker& c, Scan scan) {
  if (c.failed()) return 0;
  constexpr uint32_t kBlock = 8192;
  std::atomic<uint32_t> first_bad{n};
  // A block gives up once an earlier one has failed, looking every kStride records: an atomic
  // read per record would make the compiler reload everything a check reads, every time.
  constexpr uint32_t kStride = 512;
  auto check_block = [&](uint32_t begin, uint32_t end) {
    Checker local = c.blank();
    for (uint32_t from = begin; from < end; from += kStride) {
      if (from >= first_bad.load(std::memory_order_relaxed)) return;
      const uint32_t to = std::min(end, from + kStride);
      const uint32_t i = scan(from, to, local);
      if (i < to) {
        uint32_t seen = first_bad.load();
        while (i < seen && !first_bad.compare_exchange_weak(seen, i)) {
        }
        return;
      }
    }
  };
  if (arena == nullptr || n < 4 * kBlock) {
    check_block(0, n);
  } else {
    arena->execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<uint32_t>(0, n, kBlock),
          [&](const tbb::blocked_range<uint32_t>& b) { check_block(b.begin(), b.end()); });
    });
  }
  const uint32_t bad = first_bad.load();
  if (bad < n) scan(bad, bad + 1, c);
  return bad;
}

// A scan of records [from, to) by sound(i), stopping at the first it refuses.
template <class Sound>
auto each_record(Sound sound) {
  return [sound](uint32_t from, uint32_t to) {
    for (uint32_t i = from; i < to; ++i)
      if (!sound(i)) return i;
    return to;
  };
}

// first_failure_scan() one record at a time: check(i, checker) is false when record i fails.
template <class Check>
uint32_t first_failure(uint32_t n, tbb::task_arena* arena, Checker& c, Check check) {
  return first_failure_scan(n, arena, c, [&](uint32_t from, uint32_t to, Checker& local) {
    return each_record([&](uint32_t i) { return check(i, local); })(from, to);
  });
}

// A scan of records [from, to) by a fast path, fast(from, to), which passes a run of records and
// returns the first it cannot vouch for (or to); that one is judged by sound(i), and the scan
// goes on after it. The verdicts are sound()'s: the fuzz tree (PBRTA_CROSSCHECK_VALIDATION)
// stops should fast() pass a record sound() refuses.
template <class Fast, class Sound>
uint32_t fast_path_scan(Fast fast, Sound sound, uint32_t from, uint32_t to) {
  for (uint32_t i = from;; ++i) {
    const uint32_t stop = fast(i, to);
#if defined(PBRTA_CROSSCHECK_VALIDATION)
    for (uint32_t k = i; k < stop; ++k)
      if (!sound(k)) __builtin_trap();
#endif
    if (stop == to || !sound(stop)) return stop;
    i = stop;
  }
}

// first_failure() for the record kinds a large scene has most of, with two checks of each record:
// sound(from, to), branch-light and message-free, decides (it returns the first record in
// [from, to) it refuses, or to; each_record() makes one from a check of one record);
// explain(i, checker) is the readable check that names what is wrong, run only on the record
// sound() refused. The two must judge every record alike. The fuzz tree
// (PBRTA_CROSSCHECK_VALIDATION) runs both on every record and stops on any disagreement; should
// explain() find nothing, the load still fails.
template <class Sound, class Explain>
uint32_t first_failure(uint32_t n, tbb::task_arena* arena, Checker& c, const char* record,
                       Sound sound, Explain explain) {
#if defined(PBRTA_CROSSCHECK_VALIDATION)
  (void)record;
  auto both = [&](uint32_t i, Checker& local) {
    Checker scratch = local.blank();
    const bool verdict = sound(i, i + 1) == i + 1;
    if (verdict != explain(i, scratch)) __builtin_trap();
    return verdict || explain(i, local);
  };
  return first_failure(n, arena, c, both);
#else
  if (c.failed()) return 0;
  auto sound_in = [&](uint32_t from, uint32_t to, Checker&) { return sound(from, to); };
  Checker quiet = c.blank();
  const uint32_t bad = first_failure_scan(n, arena, quiet, sound_in);
  if (bad < n && explain(bad, c))
    c.fail(std::string(record) + " " + std::to_string(bad) +
           ": refused by a check that names no reason");
  return bad;
#endif
}

// Index soundness without messages, for the sound() checks: below the count, or kNoIndex.
inline bool optional_bad(uint32_t i, uint32_t count) {
  return (i >= count) & (i != kNoIndex);
}

// A mesh's arrays against its geometry section's size, and its source shape: true when any is
// wrong. A missing array has offset 0; a present one is aligned and inside the section. (Each
// term is computed whole: size - offset may wrap, but then offset > size says so.)
inline bool layout_bad(const MeshRecord& m, uint64_t size, uint32_t num_shapes) {
  auto array_bad = [size](bool present, uint64_t offset, uint64_t bytes) {
    return present ? (offset % 16 != 0) | (offset > size) | (bytes > size - offset) : offset != 0;
  };
  const uint64_t nv = m.num_vertices, nt = m.num_triangles;
  return array_bad(true, m.positions, nv * 12) |
         array_bad(m.flags & kMeshNormals, m.normals, nv * 12) |
         array_bad(m.flags & kMeshTangents, m.tangents, nv * 12) |
         array_bad(m.flags & kMeshUV, m.uv, nv * 8) | array_bad(true, m.indices, nt * 12) |
         array_bad(m.flags & kMeshFaceIndices, m.face_indices, nt * 4) |
         optional_bad(m.source_shape, num_shapes);
}

// What tiny_mesh_sound() reads, held by value (as EntityInputs).
struct TinyMeshInputs {
  struct Area {
    const uint8_t* data = nullptr;  // nullptr: not a loaded geometry section, or a Draco one
    uint64_t size = 0;
  };
  const MeshRecord* meshes;
  const Area* areas;  // by section
  uint32_t num_sections, num_shapes;
};

// True when mesh i certainly passes validate_geometry(): at most four triangles, in a geometry
// section that is not Draco's, with a sound layout and indices below its vertex count. False
// says nothing: the full check then judges it.
inline bool tiny_mesh_sound(const TinyMeshInputs& in, uint32_t i) {
  const MeshRecord& m = in.meshes[i];
  if (m.section >= in.num_sections || m.num_triangles > 4) return false;
  const TinyMeshInputs::Area& a = in.areas[m.section];
  if (a.data == nullptr || (m.flags & ~kKnownMeshFlags) != 0 ||
      layout_bad(m, a.size, in.num_shapes))
    return false;
  const uint32_t* v = reinterpret_cast<const uint32_t*>(a.data + m.indices);
  bool bad = false;
  for (uint32_t k = 0; k < m.num_triangles * 3; ++k) bad |= v[k] >= m.num_vertices;
  return !bad;
}

}  // namespace

bool SceneArchive::validate_records(CheckThreads* threads, std::string* error) {
  tbb::task_arena* const par = threads->arena();
  Checker c(path_, reader_);
  const ArchiveReader& r = reader_;
  // Which section holds each kind (once, except geometry and texels).
  int where_kind[uint32_t(SectionKind::kCount)];
  for (int& w : where_kind) w = -1;
  for (uint32_t i = 0; i < r.section_count(); ++i) {
    uint32_t k = r.entry(i).kind;
    if (k == 0 || k >= uint32_t(SectionKind::kCount)) continue;  // newer minor: ignored
    if (k == uint32_t(SectionKind::kGeometry) || k == uint32_t(SectionKind::kTexels)) continue;
    if (where_kind[k] >= 0) {
      c.in(int(i));
      c.fail("appears twice (first as #" + std::to_string(where_kind[k]) + ")");
      *error = c.message();
      return false;
    }
    where_kind[k] = int(i);
  }
  auto sec = [&](SectionKind k) { return where_kind[uint32_t(k)]; };
  if (sec(SectionKind::kScene) < 0 || sec(SectionKind::kStrings) < 0) {
    *error = path_ + ": no " + std::string(sec(SectionKind::kScene) < 0 ? "scene" : "strings") +
             " section";
    return false;
  }
  // The scene record.
  c.in(sec(SectionKind::kScene));
  {
    uint32_t s = uint32_t(sec(SectionKind::kScene));
    if (r.section_size(s) != sizeof(SceneRecord) || r.entry(s).count != 1) {
      c.fail("size " + std::to_string(r.section_size(s)) + " is not one SceneRecord (" +
             std::to_string(sizeof(SceneRecord)) + " bytes)");
      *error = c.message();
      return false;
    }
    std::memcpy(&scene_, r.section_data(s), sizeof scene_);
    for (uint32_t v : scene_.reserved)
      if (v != 0) {
        c.fail("reserved field is not zero");
        *error = c.message();
        return false;
      }
  }
  // Strings.
  {
    uint32_t s = uint32_t(sec(SectionKind::kStrings));
    c.in(int(s));
    const uint8_t* d = r.section_data(s);
    uint64_t size = r.section_size(s);
    uint32_t n = 0;
    if (size >= 4) std::memcpy(&n, d, 4);
    uint64_t head = 4 + (uint64_t(n) + 1) * 4;
    if (size < 4 || head > size) {
      c.fail("string table header does not fit (" + std::to_string(size) + " bytes)");
    } else if (n != scene_.num_strings || n != r.entry(s).count || n == 0) {
      c.fail("string count " + std::to_string(n) + " does not match the scene's " +
             std::to_string(scene_.num_strings));
    } else {
      // Offsets must be aligned in memory to read them as uint32: they start
      // at byte 4 of a 16-byte aligned section.
      string_offsets_ = reinterpret_cast<const uint32_t*>(d + 4);
      string_data_ = reinterpret_cast<const char*>(d + head);
      check_string_offsets(string_offsets_, n, size - head, c);
      num_strings_ = n;
    }
    if (c.failed()) {
      *error = c.message();
      return false;
    }
  }
  // Typed arrays: size and count agree with the scene record.
  auto array = [&](SectionKind k, auto* span, uint32_t expected, bool required) -> bool {
    using T = std::remove_const_t<std::remove_pointer_t<decltype(span->data)>>;
    int s = sec(k);
    if (s < 0) {
      if (expected != 0 || required) {
        c.in(-1);
        return c.fail("no " + std::string(section_kind_name(k)) + " section, but the scene has " +
                      std::to_string(expected) + " of them");
      }
      span->data = nullptr;
      span->size = 0;
      return true;
    }
    c.in(s);
    uint32_t count = r.entry(uint32_t(s)).count;
    if (count != expected)
      return c.fail("holds " + std::to_string(count) + " records, the scene says " +
                    std::to_string(expected));
    if (r.section_size(uint32_t(s)) != uint64_t(count) * sizeof(T))
      return c.fail("size " + std::to_string(r.section_size(uint32_t(s))) + " is not " +
                    std::to_string(count) + " records of " + std::to_string(sizeof(T)) + " bytes");
    // A kind these checks do not read (the transforms) may still be loading: validate_geometry()
    // points at it.
    span->data = read_by_record_checks(uint32_t(k))
                     ? reinterpret_cast<const T*>(r.section_data(uint32_t(s)))
                     : nullptr;
    span->size = count;
    return true;
  };
  const SceneRecord& sr = scene_;
  bool ok = array(SectionKind::kEntities, &entities, sr.num_entities, true) &&
            array(SectionKind::kValues, &values, sr.num_values, false) &&
            array(SectionKind::kWords, &words, sr.num_words, false) &&
            array(SectionKind::kTransforms, &transforms, sr.num_transforms, true) &&
            array(SectionKind::kTextures, &textures, sr.num_textures, false) &&
            array(SectionKind::kMaterials, &materials, sr.num_materials, false) &&
            array(SectionKind::kMedia, &media, sr.num_media, false) &&
            array(SectionKind::kLights, &lights, sr.num_lights, false) &&
            array(SectionKind::kAreaLights, &area_lights, sr.num_area_lights, false) &&
            array(SectionKind::kShapes, &shapes, sr.num_shapes, false) &&
            array(SectionKind::kObjects, &objects, sr.num_objects, false) &&
            array(SectionKind::kObjectShapes, &object_shapes, sr.num_object_shapes, false) &&
            array(SectionKind::kInstances, &instances, sr.num_instances, false) &&
            array(SectionKind::kMeshes, &meshes, sr.num_meshes, false) &&
            array(SectionKind::kImages, &images, sr.num_images, false);
  if (ok) {
    // Provenance: u32 records, u32 strings, records, string offsets, characters.
    int s = sec(SectionKind::kProvenance);
    uint32_t expected = sr.num_entities + sr.num_objects + sr.num_instances;
    if (s < 0) {
      c.in(-1);
      ok = c.fail("no provenance section");
    } else {
      c.in(s);
      const uint8_t* d = r.section_data(uint32_t(s));
      uint64_t size = r.section_size(uint32_t(s));
      uint32_t nrec = 0, nstr = 0;
      if (size >= 8) {
        std::memcpy(&nrec, d, 4);
        std::memcpy(&nstr, d + 4, 4);
      }
      uint64_t records_end = 8 + uint64_t(nrec) * sizeof(ProvenanceRecord);
      uint64_t head = records_end + (uint64_t(nstr) + 1) * 4;
      if (size < 8 || head > size) {
        ok = c.fail("provenance tables do not fit (" + std::to_string(size) + " bytes)");
      } else if (nrec != r.entry(uint32_t(s)).count || nrec < expected || nstr == 0) {
        ok = c.fail("has " + std::to_string(nrec) + " records, needs " + std::to_string(expected));
      } else {
        provenance.data = reinterpret_cast<const ProvenanceRecord*>(d + 8);
        provenance.size = nrec;
        pstring_offsets_ = reinterpret_cast<const uint32_t*>(d + records_end);
        pstring_data_ = reinterpret_cast<const char*>(d + head);
        num_pstrings_ = nstr;
        ok = check_string_offsets(pstring_offsets_, nstr, size - head, c);
        const ProvenanceRecord* records = provenance.data;
        auto record_sound = [records, nstr](uint32_t i) {
          const ProvenanceRecord& p = records[i];
          return !((p.file >= nstr) | (p.name >= nstr) | (p.path >= nstr));
        };
        first_failure(nrec, par, c, "record", each_record(record_sound),
                      [&](uint32_t i, Checker& c) {
                        return record_sound(i) ||
                               c.fail("record " + std::to_string(i) + ": string out of range (" +
                                      std::to_string(nstr) + " strings)");
                      });
        ok = !c.failed();
      }
    }
  }
  if (!ok) {
    *error = c.message();
    return false;
  }

  // Textures first: an entity's texture bindings, checked with its values, read them.
  c.in(sec(SectionKind::kTextures));
  first_failure(textures.size, par, c, [&](uint32_t i, Checker& c) {
    const TextureRecord& t = textures[i];
    if (!c.index(t.entity, entities.size, "texture", i, "entity", "entities", false)) return false;
    uint8_t cat = entities[t.entity].category;
    if (cat != uint8_t(Category::kFloatTexture) && cat != uint8_t(Category::kSpectrumTexture))
      return c.fail("texture " + std::to_string(i) + ": entity is not a texture");
    return (t.reserved == 0 ||
            c.fail("texture " + std::to_string(i) + ": reserved field is not zero")) &&
           c.index(t.transform, transforms.size, "texture", i, "transform", "transforms", false) &&
           c.index(t.image, images.size, "texture", i, "image", "images", true);
  });
  // Entities and their values: one entity's checks, false (with the reason in c) on failure.
  const uint16_t minor = r.header().minor;
  auto check_entity = [&](uint32_t i, Checker& c) -> bool {
    const EntityRecord& e = entities[i];
    // Messages are built only on failure: this loop runs once per entity.
    auto at = [&]() { return "entity " + std::to_string(i) + ": "; };
    if (e.category >= uint8_t(Category::kCount)) {
      c.fail(at() + "category " + std::to_string(e.category) + " unknown");
      return false;
    }
    const CategorySpec& cs = category_spec(Category(e.category));
    if (e.type >= cs.num_types) {
      c.fail(at() + std::string(cs.name) + " type " + std::to_string(e.type) + " unknown (" +
             std::to_string(cs.num_types) + " types)");
      return false;
    }
    const TypeSpec& ts = cs.types[e.type];
    if (e.reserved0 || e.reserved1) {
      c.fail(at() + "reserved field is not zero");
      return false;
    }
    // Parameters are only ever appended to a type (a minor change): a newer minor may have
    // more than this reader knows (it ignores them), an older one fewer (they read as absent).
    if (minor == kMinorVersion  ? e.num_values != ts.num_params
        : minor > kMinorVersion ? e.num_values < ts.num_params
                                : e.num_values > ts.num_params) {
      c.fail(at() + std::string(ts.name) + " has " + std::to_string(ts.num_params) +
             " parameters, the record " + std::to_string(e.num_values) + " (archive version " +
             std::to_string(r.header().major) + "." + std::to_string(minor) + ")");
      return false;
    }
    if (uint64_t(e.first_value) + e.num_values > values.size) {
      c.fail(at() + "values " + std::to_string(e.first_value) + "+" + std::to_string(e.num_values) +
             " out of range (" + std::to_string(values.size) + " values)");
      return false;
    }
    const uint32_t known = std::min<uint32_t>(e.num_values, ts.num_params);
    for (uint32_t p = 0; p < known; ++p) {
      const ValueRecord& v = values[e.first_value + p];
      const ParamSpec& ps = ts.params[p];
      auto vat = [&]() {
        return at() + std::string(ts.name) + " \"" + std::string(ps.name) + "\": ";
      };
      uint64_t width = uint64_t(kind_width(ps.kind));
      if (v.flags & ~uint32_t(kValueGiven)) {
        c.fail(vat() + "unknown value flags");
        return false;
      }
      if (uint64_t(v.offset) + uint64_t(v.count) * width > words.size) {
        c.fail(vat() + "words out of range");
        return false;
      }
      if (ps.arity > 0 && v.count != 0 && v.count != ps.arity) {
        c.fail(vat() + std::to_string(v.count) + " values, the schema says " +
               std::to_string(ps.arity));
        return false;
      }
      if (v.texture != kNoIndex) {
        bool tex_kind = ps.kind == Kind::kFloatTex || ps.kind == Kind::kSpectrumTex;
        if (!tex_kind) {
          c.fail(vat() + "a texture on a parameter that takes none");
          return false;
        }
        if (v.texture >= textures.size) {
          c.fail(vat() + "texture " + std::to_string(v.texture) + " out of range (" +
                 std::to_string(textures.size) + " textures)");
          return false;
        }
      }
      if (ps.kind == Kind::kString)
        for (uint32_t k = 0; k < v.count; ++k)
          if (words[v.offset + k] >= num_strings_) {
            c.fail(vat() + "string " + std::to_string(words[v.offset + k]) + " out of range");
            return false;
          }
    }
    // Counts tied to other parameters (format/entity_rules.h), now that every value is sound.
    RuleViolation rule;
    const CountRule count_rule = count_rule_of(Category(e.category), e.type);
    if (count_rule == CountRule::kCurve) {
      CurveCounts cc;
      cc.degree = get_int(i, "degree", 3);
      cc.basis = get_string(i, "basis");
      const ValueRecord* P = value(i, "P");
      const ValueRecord* N = value(i, "N");
      cc.control_points = P ? P->count : 0;
      cc.type = get_string(i, "type");
      cc.normals_given = given(i, "N");
      cc.normals = N ? N->count : 0;
      if (!check_curve_rules(cc, &rule)) return c.fail(at() + rule.message);
    } else if (count_rule == CountRule::kDensity) {
      const ValueRecord* d = value(i, "density");
      if (!check_density_rule(get_int(i, "nx", 1), get_int(i, "ny", 1), get_int(i, "nz", 1),
                              d ? d->count : 0, &rule))
        return c.fail(at() + rule.message);
    } else if (count_rule == CountRule::kFourierTable) {
      // The renderer indexes the table (derived from the material's file) without checks, so its
      // arrays must agree. One written before version 1.1 has none (the renderer reports that).
      const ValueRecord* mu = value(i, "bsdfmu");
      FourierTableView t;
      std::string why;
      if (mu != nullptr && mu->count != 0 &&
          (!fourier_table_of(*this, i, &t, &why) || !check_fourier_table(t, &why)))
        return c.fail(at() + "fourier table " + why);
    }
    return true;
  };
  // Texture bindings must match the parameter's class (after check_entity: the indices are in
  // range).
  auto check_bindings = [&](uint32_t i, Checker& c) {
    const EntityRecord& e = entities[i];
    const TypeSpec& ts = category_spec(Category(e.category)).types[e.type];
    const uint32_t known = std::min<uint32_t>(e.num_values, ts.num_params);
    for (uint32_t p = 0; p < known; ++p) {
      const ValueRecord& v = values[e.first_value + p];
      if (v.texture == kNoIndex) continue;
      Category want = ts.params[p].kind == Kind::kFloatTex ? Category::kFloatTexture
                                                           : Category::kSpectrumTexture;
      if (entities[textures[v.texture].entity].category != uint8_t(want))
        return c.fail("entity " + std::to_string(i) + " \"" + std::string(ts.params[p].name) +
                      "\": texture " + std::to_string(v.texture) + " is not a " +
                      std::string(category_name(want)));
    }
    return true;
  };
  const SchemaDigest& digest = schema_digest();
  const uint32_t num_textures = textures.size, num_words = words.size, num_values = values.size;
  const uint32_t num_strings = num_strings_;
  const Checker unreported = c.blank();  // for sound()'s fallbacks, whose messages are dropped
#if defined(PBRTA_CHECKS_AVX2)
  const bool avx2 = have_avx2();
#else
  const bool avx2 = false;
#endif
  const EntityInputs hot{entities.data, values.data,  words.data, textures.data,
                         &digest,       num_textures, num_words,  num_values,
                         num_strings,   minor,        avx2};
  auto slow_sound = [&](uint32_t i) {
    Checker scratch = unreported;
    return check_entity(i, scratch) && check_bindings(i, scratch);
  };
  auto entity_sound = [hot, &slow_sound](uint32_t i) -> bool {
    const EntityRecord& e = hot.entities[i];
    if (e.type >= hot.digest->num_types(e.category)) return false;
    const TypeDigest& t = hot.digest->type(e.category, e.type);
    if (t.has_rules) return slow_sound(i);
    const bool count_bad = hot.minor == kMinorVersion  ? e.num_values != t.num_params
                           : hot.minor > kMinorVersion ? e.num_values < t.num_params
                                                       : e.num_values > t.num_params;
    if ((e.reserved0 | e.reserved1) != 0 || count_bad ||
        uint64_t(e.first_value) + e.num_values > hot.num_values)
      return false;
    const uint32_t known = std::min<uint32_t>(e.num_values, t.num_params);
    const ValueRecord* v = hot.values + e.first_value;
    uint32_t bad = 0;
    for (uint32_t p = 0; p < known; ++p) {
      const ParamDigest& pd = t.params[p];
      bad |= v[p].flags & ~uint32_t(kValueGiven);
      bad |= uint64_t(v[p].offset) + uint64_t(v[p].count) * pd.width > hot.num_words;
      bad |= (pd.arity != 0) & (v[p].count != 0) & (v[p].count != pd.arity);
      if (v[p].texture != kNoIndex &&
          (pd.texture == kNoTextureCategory || v[p].texture >= hot.num_textures ||
           hot.entities[hot.textures[v[p].texture].entity].category != pd.texture))
        return false;
    }
    if (bad) return false;
    if (t.has_strings)
      for (uint32_t q = 0; q < known; ++q)
        if (t.params[q].is_string)
          for (uint32_t k = 0; k < v[q].count; ++k)
            if (hot.words[v[q].offset + k] >= hot.num_strings) return false;
    return true;
  };
  // Runs of plain entities by the vector check, the rest one by one.
  auto entities_sound = [hot, &entity_sound](uint32_t from, uint32_t to) {
#if defined(PBRTA_CHECKS_AVX2)
    if (hot.avx2) {
      auto fast = [&hot](uint32_t i, uint32_t end) { return plain_entities_avx2(hot, i, end); };
      return fast_path_scan(fast, entity_sound, from, to);
    }
#endif
    return each_record(entity_sound)(from, to);
  };
  c.in(sec(SectionKind::kEntities));
  first_failure(entities.size, par, c, "entity", entities_sound, [&](uint32_t i, Checker& c) {
    if (!check_entity(i, c)) return false;
    c.in(sec(SectionKind::kValues));  // a binding is a value's fault
    const bool ok = check_bindings(i, c);
    c.in(sec(SectionKind::kEntities));
    return ok;
  });
  auto index_bad = [](uint32_t i, uint32_t count) { return i >= count; };
  auto entity_is = [&](uint32_t e, Category cat) {
    return e < entities.size && entities[e].category == uint8_t(cat);
  };
  // Render options point at entities of the right category.
  c.in(sec(SectionKind::kScene));
  auto entity_of = [&](Checker& c, uint32_t e, Category cat, const char* record, uint32_t at,
                       const char* field) {
    if (!c.index(e, entities.size, record, at, field, "entities", false)) return false;
    if (entities[e].category != uint8_t(cat))
      return c.fail(std::string(record) + " " + std::to_string(at) + ": " + field + " entity " +
                    std::to_string(e) + " is a " +
                    std::string(category_name(Category(entities[e].category))) + ", not a " +
                    std::string(category_name(cat)));
    return true;
  };
  if (!c.failed()) {
    entity_of(c, sr.camera, Category::kCamera, "scene", 0, "camera") &&
        entity_of(c, sr.film, Category::kFilm, "scene", 0, "film") &&
        entity_of(c, sr.filter, Category::kFilter, "scene", 0, "filter") &&
        entity_of(c, sr.sampler, Category::kSampler, "scene", 0, "sampler") &&
        entity_of(c, sr.integrator, Category::kIntegrator, "scene", 0, "integrator") &&
        entity_of(c, sr.accelerator, Category::kAccelerator, "scene", 0, "accelerator") &&
        c.index(sr.camera_transform, transforms.size, "scene", 0, "camera transform", "transforms",
                false) &&
        c.index(sr.camera_medium, media.size, "scene", 0, "camera medium", "media", true);
  }
  c.in(sec(SectionKind::kMaterials));
  auto check_material = [&](uint32_t i, Checker& c) {
    const MaterialRecord& m = materials[i];
    return entity_of(c, m.entity, Category::kMaterial, "material", i, "entity") &&
           (m.reserved == 0 ||
            c.fail("material " + std::to_string(i) + ": reserved field is not zero")) &&
           c.index(m.mix[0], materials.size, "material", i, "mix material 1", "materials", true) &&
           c.index(m.mix[1], materials.size, "material", i, "mix material 2", "materials", true);
  };
  first_failure(materials.size, par, c, "material", each_record([&](uint32_t i) {
                  const MaterialRecord& m = materials[i];
                  return !((m.reserved != 0) | optional_bad(m.mix[0], materials.size) |
                           optional_bad(m.mix[1], materials.size)) &&
                         entity_is(m.entity, Category::kMaterial);
                }),
                check_material);
  c.in(sec(SectionKind::kMedia));
  first_failure(media.size, par, c, [&](uint32_t i, Checker& c) {
    const MediumRecord& m = media[i];
    return entity_of(c, m.entity, Category::kMedium, "medium", i, "entity") &&
           c.index(m.transform, transforms.size, "medium", i, "transform", "transforms", false) &&
           ((m.reserved[0] | m.reserved[1]) == 0 ||
            c.fail("medium " + std::to_string(i) + ": reserved field is not zero"));
  });
  c.in(sec(SectionKind::kLights));
  first_failure(lights.size, par, c, [&](uint32_t i, Checker& c) {
    const LightRecord& l = lights[i];
    return entity_of(c, l.entity, Category::kLight, "light", i, "entity") &&
           c.index(l.transform, transforms.size, "light", i, "transform", "transforms", false) &&
           c.index(l.medium, media.size, "light", i, "medium", "media", true) &&
           c.index(l.image, images.size, "light", i, "image", "images", true);
  });
  c.in(sec(SectionKind::kAreaLights));
  first_failure(area_lights.size, par, c, [&](uint32_t i, Checker& c) {
    return entity_of(c, area_lights[i], Category::kAreaLight, "area light", i, "entity");
  });
  c.in(sec(SectionKind::kShapes));
  auto check_shape = [&](uint32_t i, Checker& c) {
    const ShapeRecord& s = shapes[i];
    return entity_of(c, s.entity, Category::kShape, "shape", i, "entity") &&
           c.index(s.mesh, meshes.size, "shape", i, "mesh", "meshes", true) &&
           c.index(s.material, materials.size, "shape", i, "material", "materials", false) &&
           c.index(s.area_light, area_lights.size, "shape", i, "area light", "area lights", true) &&
           c.index(s.inside_medium, media.size, "shape", i, "inside medium", "media", true) &&
           c.index(s.outside_medium, media.size, "shape", i, "outside medium", "media", true) &&
           c.index(s.transform, transforms.size, "shape", i, "transform", "transforms", false) &&
           c.index(s.object, objects.size, "shape", i, "object", "objects", true) &&
           ((s.flags & ~kKnownShapeFlags) == 0 ||
            c.fail("shape " + std::to_string(i) + ": unknown flags")) &&
           (s.reserved == 0 ||
            c.fail("shape " + std::to_string(i) + ": reserved field is not zero"));
  };
  auto shape_sound = [&](uint32_t i) {
    const ShapeRecord& s = shapes[i];
    return !(optional_bad(s.mesh, meshes.size) | index_bad(s.material, materials.size) |
             optional_bad(s.area_light, area_lights.size) |
             optional_bad(s.inside_medium, media.size) |
             optional_bad(s.outside_medium, media.size) | index_bad(s.transform, transforms.size) |
             optional_bad(s.object, objects.size) | ((s.flags & ~kKnownShapeFlags) != 0) |
             (s.reserved != 0)) &&
           entity_is(s.entity, Category::kShape);
  };
#if defined(PBRTA_CHECKS_AVX2)
  const ShapeInputs shape_inputs{shapes.data,
                                 entities.data,
                                 {entities.size, meshes.size, materials.size, area_lights.size,
                                  media.size, media.size, transforms.size, objects.size}};
#endif
  auto shapes_sound = [&](uint32_t from, uint32_t to) {
#if defined(PBRTA_CHECKS_AVX2)
    if (avx2) {
      auto fast = [&](uint32_t i, uint32_t end) { return plain_shapes_avx2(shape_inputs, i, end); };
      return fast_path_scan(fast, shape_sound, from, to);
    }
#endif
    return each_record(shape_sound)(from, to);
  };
  first_failure(shapes.size, par, c, "shape", shapes_sound, check_shape);
  c.in(sec(SectionKind::kObjects));
  first_failure(objects.size, par, c, [&](uint32_t i, Checker& c) {
    const ObjectRecord& o = objects[i];
    return (o.reserved == 0 ||
            c.fail("object " + std::to_string(i) + ": reserved field is not zero")) &&
           c.index(o.provenance, provenance.size, "object", i, "provenance", "records", false) &&
           (uint64_t(o.first_shape) + o.num_shapes <= object_shapes.size ||
            c.fail("object " + std::to_string(i) + ": shapes out of range"));
  });
  c.in(sec(SectionKind::kObjectShapes));
  first_failure(object_shapes.size, par, c, [&](uint32_t i, Checker& c) {
    return c.index(object_shapes[i], shapes.size, "entry", i, "shape", "shapes", false);
  });
  c.in(sec(SectionKind::kInstances));
  first_failure(instances.size, par, c, [&](uint32_t i, Checker& c) {
    const InstanceRecord& in = instances[i];
    return c.index(in.object, objects.size, "instance", i, "object", "objects", false) &&
           c.index(in.transform, transforms.size, "instance", i, "transform", "transforms",
                   false) &&
           c.index(in.provenance, provenance.size, "instance", i, "provenance", "records", false) &&
           (in.reserved == 0 ||
            c.fail("instance " + std::to_string(i) + ": reserved field is not zero"));
  });
  if (c.failed()) {
    *error = c.message();
    return false;
  }
  return true;
}

bool SceneArchive::validate_geometry(CheckThreads* threads, const IndexChecks& checks,
                                     std::string* error) {
  tbb::task_arena* const par = threads->arena();
  Checker c(path_, reader_);
  const ArchiveReader& r = reader_;
  auto sec = [&](SectionKind k) { return r.find_section(k); };  // each once: validate_records()
  if (transforms.size > 0)
    transforms.data = reinterpret_cast<const TransformRecord*>(
        r.section_data(uint32_t(sec(SectionKind::kTransforms))));
  const Checker unreported = c.blank();
  c.in(sec(SectionKind::kMeshes));
  // A mesh's layout, with the reason it is refused; its indices are checked below, in the same
  // pass (the largest part of validation: every index of every mesh is read).
  auto check_mesh = [&](uint32_t i, Checker& c) {
    const MeshRecord& m = meshes[i];
    auto at = [&]() { return "mesh " + std::to_string(i) + ": "; };
    if (m.section >= r.section_count() ||
        r.entry(m.section).kind != uint32_t(SectionKind::kGeometry))
      return c.fail(at() + "section " + std::to_string(m.section) + " is not a geometry section");
    if (m.flags & ~kKnownMeshFlags) return c.fail(at() + "unknown flags");
    if (r.entry(m.section).codec == uint32_t(Codec::kDraco)) {
      // A Draco section decodes to exactly one mesh's layout: the record must describe it.
      MeshRecord expect = m;
      if ((m.flags & kMeshTangents) || single_mesh_layout(&expect) != r.section_size(m.section) ||
          std::memcmp(&expect, &m, sizeof m) != 0)
        return c.fail(at() + "does not match the layout of its draco section");
      // Other counts may lay out alike (8 vertices and 4 triangles, 4 and 8): only the stream's
      // own say what the bytes are.
      const uint32_t dv = r.decoded_vertices(m.section), dt = r.decoded_triangles(m.section);
      if (m.num_vertices != dv || m.num_triangles != dt)
        return c.fail(at() + std::to_string(m.num_vertices) + " vertices and " +
                      std::to_string(m.num_triangles) + " triangles, but its draco section (#" +
                      std::to_string(m.section) + ") decodes to " + std::to_string(dv) + " and " +
                      std::to_string(dt));
    }
    uint64_t size = r.section_size(m.section);
    auto array_ok = [&](bool present, uint64_t offset, uint64_t elems, uint64_t elem_bytes,
                        const char* name) {
      if (!present) return offset == 0 || c.fail(at() + name + " offset set but flag clear");
      if (offset % 16 != 0) return c.fail(at() + name + " offset is not 16-byte aligned");
      if (offset > size || elems * elem_bytes > size - offset)
        return c.fail(at() + name + " (" + std::to_string(elems * elem_bytes) + " bytes at " +
                      std::to_string(offset) + ") lies outside its section (" +
                      std::to_string(size) + " bytes)");
      return true;
    };
    uint64_t nv = m.num_vertices, nt = m.num_triangles;
    return array_ok(true, m.positions, nv, 12, "positions") &&
           array_ok(m.flags & kMeshNormals, m.normals, nv, 12, "normals") &&
           array_ok(m.flags & kMeshTangents, m.tangents, nv, 12, "tangents") &&
           array_ok(m.flags & kMeshUV, m.uv, nv, 8, "uv") &&
           array_ok(true, m.indices, nt, 12, "indices") &&
           array_ok(m.flags & kMeshFaceIndices, m.face_indices, nt, 4, "face indices") &&
           c.index(m.source_shape, shapes.size, "mesh", i, "source shape", "shapes", true);
  };
  auto mesh_sound = [&](uint32_t i) {
    const MeshRecord& m = meshes[i];
    if (m.section >= r.section_count() ||
        r.entry(m.section).kind != uint32_t(SectionKind::kGeometry) ||
        (m.flags & ~kKnownMeshFlags) != 0)
      return false;
    if (r.entry(m.section).codec == uint32_t(Codec::kDraco)) {
      Checker scratch = unreported;
      return check_mesh(i, scratch);
    }
    return !layout_bad(m, r.section_size(m.section), shapes.size);
  };
  // Each laid-out mesh's triangle indices against its vertex count: a large mesh's were checked
  // as they decoded (bound b), a small one's are read here, in the same parallel pass as the
  // layouts. The first mesh in order with a bad layout or a bad index is the one reported.
  auto bound_of = [&](uint32_t i) -> size_t {
    auto it = std::lower_bound(checks.mesh.begin(), checks.mesh.end(), i);
    return it != checks.mesh.end() && *it == i ? size_t(it - checks.mesh.begin())
                                               : checks.mesh.size();
  };
  // The first bad index of a laid-out mesh i, as an element of its indices, or 3 * triangles.
  auto first_bad_index = [&](uint32_t i) -> uint64_t {
    const size_t b = bound_of(i);
    if (b < checks.mesh.size()) {
      const ArchiveReader::U32Bound& bound = checks.bounds[b];
      return checks.first[b] == bound.end ? uint64_t(meshes[i].num_triangles) * 3
                                          : (checks.first[b] - bound.begin) / 4;
    }
    const uint32_t* v = indices(i);
    const uint64_t n = uint64_t(meshes[i].num_triangles) * 3;
    const uint32_t limit = meshes[i].num_vertices;
    if (n > 12) return first_at_or_above(v, n, limit);
    for (uint64_t k = 0; k < n; ++k)  // a few triangles (50k one-triangle meshes): no call
      if (v[k] >= limit) return k;
    return n;
  };
  auto one_mesh_sound = [&](uint32_t i) {
    return mesh_sound(i) && first_bad_index(i) == uint64_t(meshes[i].num_triangles) * 3;
  };
  // The common case of a few triangles in an uncompressed or zstd geometry section (50k
  // one-triangle meshes), checked with what it reads held in registers; the rest one by one as
  // above. 12 indices: first_bad_index() reads that many in place too.
  std::vector<TinyMeshInputs::Area> areas(r.section_count());
  for (uint32_t s = 0; s < r.section_count(); ++s)
    if (r.entry(s).kind == uint32_t(SectionKind::kGeometry) &&
        r.entry(s).codec != uint32_t(Codec::kDraco) && r.section_data(s) != nullptr)
      areas[s] = {r.section_data(s), r.section_size(s)};
  const TinyMeshInputs tiny{meshes.data, areas.data(), r.section_count(), shapes.size};
  auto tiny_meshes = [tiny](uint32_t i, uint32_t end) {
    while (i < end && tiny_mesh_sound(tiny, i)) ++i;
    return i;
  };
  auto meshes_sound = [&](uint32_t from, uint32_t to) {
    return fast_path_scan(tiny_meshes, one_mesh_sound, from, to);
  };
  first_failure(meshes.size, par, c, "mesh", meshes_sound, [&](uint32_t i, Checker& c) {
    if (!check_mesh(i, c)) return false;
    const uint64_t k = first_bad_index(i);
    return k == uint64_t(meshes[i].num_triangles) * 3 ||
           c.fail("mesh " + std::to_string(i) + ": triangle " + std::to_string(k / 3) +
                  " has vertex index " + std::to_string(indices(i)[k]) + " (" +
                  std::to_string(meshes[i].num_vertices) + " vertices)");
  });
  // A Draco section holds one mesh (ARCHIVE.md section 8): no two records may name it. Only
  // archives with Draco sections pay for the pass.
  bool any_draco = false;
  for (uint32_t s = 0; s < r.section_count(); ++s)
    any_draco |= r.entry(s).codec == uint32_t(Codec::kDraco);
  if (any_draco && !c.failed()) {
    std::vector<uint32_t> owner(r.section_count(), kNoIndex);
    for (uint32_t i = 0; i < meshes.size; ++i) {
      const uint32_t s = meshes[i].section;  // checked above: a geometry section
      if (r.entry(s).codec != uint32_t(Codec::kDraco)) continue;
      if (owner[s] != kNoIndex) {
        c.fail("mesh " + std::to_string(i) + ": its draco section (#" + std::to_string(s) +
               ") holds mesh " + std::to_string(owner[s]) + " already");
        break;
      }
      owner[s] = i;
    }
  }
  c.in(sec(SectionKind::kImages));
  for (uint32_t i = 0; i < images.size && !c.failed(); ++i) {
    const ImageRecord& im = images[i];
    std::string at = "image " + std::to_string(i) + ": ";
    if (im.section >= r.section_count() ||
        r.entry(im.section).kind != uint32_t(SectionKind::kTexels)) {
      c.fail(at + "section is not a texels section");
      break;
    }
    if ((im.channels != 1 && im.channels != 3) || im.levels == 0 || im.levels > 32 ||
        im.format > uint32_t(PixelFormat::kUnorm8) || im.wrap > 2 || im.width == 0 ||
        im.height == 0 || im.source_width == 0 || im.source_height == 0) {
      c.fail(at + "malformed header");
      break;
    }
    const uint64_t bytes_per = texel_bytes(im.format);  // 4, 2 or 1: the format was checked
    uint64_t off = im.offset, size = r.section_size(im.section);
    for (uint32_t l = 0; l < im.levels && !c.failed(); ++l) {
      uint64_t w = std::max<uint64_t>(1, uint64_t(im.width) >> l);
      uint64_t h = std::max<uint64_t>(1, uint64_t(im.height) >> l);
      uint64_t bytes = w * h * im.channels * bytes_per;
      if (off % 16 != 0 || off > size || bytes > size - off) {
        c.fail(at + "level " + std::to_string(l) + " lies outside its section");
        break;
      }
      off = (off + bytes + 15) & ~uint64_t(15);
    }
    if (c.failed()) break;
    if ((im.reserved[0] | im.reserved[1] | im.reserved[2]) != 0) {
      c.fail(at + "reserved field is not zero");
      break;
    }
    if (!c.index(im.distribution, images.size, "image", i, "distribution", "images", true) ||
        !c.index(im.source_image, images.size, "image", i, "source image", "images", true))
      break;
    // A sampling distribution is a pdf: pbrtc keeps it f32 whatever --texture-precision says.
    if (im.distribution != kNoIndex &&
        images[im.distribution].format != uint32_t(PixelFormat::kFloat32)) {
      c.fail(at + "distribution image " + std::to_string(im.distribution) + " is " +
             texel_format_name(images[im.distribution].format) + ", not f32");
      break;
    }
    if (im.source_image != kNoIndex) {
      // Only a resampled image names its texels as decoded; a source is at its own size, so
      // this also keeps sources from naming sources (no chains).
      if (im.width == im.source_width && im.height == im.source_height) {
        c.fail(at + "level 0 is already the source size, " + std::to_string(im.width) + " x " +
               std::to_string(im.height) + ", yet it names source image " +
               std::to_string(im.source_image));
        break;
      }
      // The texels as decoded: one level at the source size, with no source of its own.
      const ImageRecord& src = images[im.source_image];
      if (im.source_image == i || src.source_image != kNoIndex || src.levels != 1 ||
          src.width != im.source_width || src.height != im.source_height ||
          src.channels != im.channels || src.format != im.format || src.wrap != im.wrap) {
        c.fail(at + "source image " + std::to_string(im.source_image) + " is not " +
               std::to_string(im.source_width) + " x " + std::to_string(im.source_height) + " x " +
               std::to_string(im.channels) +
               " in the same format and wrap, with one level and no source of its own");
        break;
      }
    }
  }
  // What a texture or a light looks up is a whole pyramid, as pbrt-v3's MIPMap builds it: the
  // renderer picks levels by pbrt-v3's arithmetic, which a shorter one would silently change.
  // A sampling distribution is one level.
  auto expect_levels = [&](uint32_t image, bool whole_pyramid, const char* as, uint32_t owner,
                           const char* role) {
    if (image == kNoIndex) return true;
    const ImageRecord& im = images[image];
    const uint32_t want = whole_pyramid ? full_pyramid_levels(im.width, im.height) : 1;
    if (im.levels == want) return true;
    return c.fail("image " + std::to_string(image) + ": " + std::to_string(im.levels) +
                  " levels, but as " + as + " " + std::to_string(owner) + "'s " + role +
                  " it has " + std::to_string(want));
  };
  for (uint32_t i = 0; i < textures.size && !c.failed(); ++i)
    expect_levels(textures[i].image, true, "texture", i, "pyramid");
  for (uint32_t i = 0; i < lights.size && !c.failed(); ++i)
    expect_levels(lights[i].image, true, "light", i, "pyramid");
  for (uint32_t i = 0; i < images.size && !c.failed(); ++i)
    expect_levels(images[i].distribution, false, "image", i, "distribution");
  if (c.failed()) {
    *error = c.message();
    return false;
  }
  return true;
}

}  // namespace pbrta
