// compiler/ply_reader.cpp — PLY parsing in three steps: read the header, check every count it
// declares against the bytes that follow (before allocating anything from it), then read the
// body in one pass, element by element, straight into the output arrays.
#include "compiler/ply_reader.h"

#include <fast_float/fast_float.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>

namespace pbrtc {

size_t PlyMesh::num_vertices() const {
  return positions.size() / 3;
}
size_t PlyMesh::num_triangles() const {
  return indices.size() / 3;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Limits and basic types

// Real headers are a few hundred bytes; a line longer than this is garbage, and bounding it
// keeps the search for the end of a line from scanning a whole binary file.
constexpr size_t kMaxHeaderLineBytes = 64 * 1024;
// Indices are uint32_t, so vertex ids must fit; consumers number triangles with uint32_t too.
constexpr uint64_t kMaxVertices = std::numeric_limits<uint32_t>::max();
constexpr uint64_t kMaxTriangles = std::numeric_limits<uint32_t>::max();
// Tokens quoted in messages are cut to this length so garbage cannot flood a log.
constexpr size_t kMaxQuotedBytes = 40;
constexpr double kFloatMax = std::numeric_limits<float>::max();

#if defined(__BYTE_ORDER__) && defined(__ORDER_BIG_ENDIAN__) && \
    __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
constexpr bool kHostIsBigEndian = true;
#else
constexpr bool kHostIsBigEndian = false;
#endif

enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

// In the order of kTypeInfo below.
enum class ScalarType : uint8_t {
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kFloat32,
  kFloat64
};

struct TypeSpelling {
  std::string_view name;
  ScalarType type;
};

// Both the original PLY names and the sized names later writers use.
constexpr TypeSpelling kTypeSpellings[] = {
    {"char", ScalarType::kInt8},      {"int8", ScalarType::kInt8},
    {"uchar", ScalarType::kUint8},    {"uint8", ScalarType::kUint8},
    {"short", ScalarType::kInt16},    {"int16", ScalarType::kInt16},
    {"ushort", ScalarType::kUint16},  {"uint16", ScalarType::kUint16},
    {"int", ScalarType::kInt32},      {"int32", ScalarType::kInt32},
    {"uint", ScalarType::kUint32},    {"uint32", ScalarType::kUint32},
    {"float", ScalarType::kFloat32},  {"float32", ScalarType::kFloat32},
    {"double", ScalarType::kFloat64}, {"float64", ScalarType::kFloat64},
};

bool parse_scalar_type(std::string_view name, ScalarType* type) {
  for (const TypeSpelling& spelling : kTypeSpellings) {
    if (spelling.name == name) {
      *type = spelling.type;
      return true;
    }
  }
  return false;
}

// Facts about each type, indexed by ScalarType. The integer range checks ascii values against
// their declared type.
struct TypeInfo {
  size_t size;
  bool is_integer;
  const char* name;
  int64_t min;
  int64_t max;
};

constexpr TypeInfo kTypeInfo[] = {
    {1, true, "char", INT8_MIN, INT8_MAX},
    {1, true, "uchar", 0, UINT8_MAX},
    {2, true, "short", INT16_MIN, INT16_MAX},
    {2, true, "ushort", 0, UINT16_MAX},
    {4, true, "int", INT32_MIN, INT32_MAX},
    {4, true, "uint", 0, UINT32_MAX},
    {4, false, "float", 0, 0},
    {8, false, "double", 0, 0},
};

static_assert(sizeof(kTypeInfo) / sizeof(kTypeInfo[0]) ==
              static_cast<size_t>(ScalarType::kFloat64) + 1);

const TypeInfo& info(ScalarType type) {
  return kTypeInfo[static_cast<size_t>(type)];
}
size_t scalar_size(ScalarType type) {
  return info(type).size;
}
bool is_integer(ScalarType type) {
  return info(type).is_integer;
}

// What a property is for. Each role is given to at most one property of its element.
enum class Role : uint8_t { kSkip, kX, kY, kZ, kNx, kNy, kNz, kU, kV, kVertexIndices, kFaceIndex };

struct Property {
  std::string_view name;  // points into the input bytes
  bool is_list = false;
  ScalarType count_type = ScalarType::kUint8;  // lists only
  ScalarType value_type = ScalarType::kFloat32;
  Role role = Role::kSkip;
};

enum class ElementKind : uint8_t { kOther, kVertex, kFace };

// A property read by the fixed-record fast path: where it sits in the record.
struct Field {
  size_t offset;
  ScalarType type;
  Role role;
};

struct Element {
  std::string_view name;  // points into the input bytes
  uint64_t count = 0;
  ElementKind kind = ElementKind::kOther;
  std::vector<Property> properties;
  size_t fixed_size = 0;      // binary record size if no property is a list, else 0
  std::vector<Field> fields;  // properties with a role, when fixed_size > 0
};

// ---------------------------------------------------------------------------------------------
// Binary loads: memcpy (alignment-safe), then swap bytes when the file's order is not the host's.

inline uint16_t byte_swap(uint16_t v) {
  return static_cast<uint16_t>((v >> 8) | (v << 8));
}
inline uint32_t byte_swap(uint32_t v) {
  return ((v & 0x000000FFu) << 24) | ((v & 0x0000FF00u) << 8) | ((v & 0x00FF0000u) >> 8) |
         ((v & 0xFF000000u) >> 24);
}
inline uint64_t byte_swap(uint64_t v) {
  return (static_cast<uint64_t>(byte_swap(static_cast<uint32_t>(v))) << 32) |
         byte_swap(static_cast<uint32_t>(v >> 32));
}

template <typename T, bool kSwap>
inline T load(const char* p) {
  T value;
  if constexpr (sizeof(T) == 1 || !kSwap) {
    std::memcpy(&value, p, sizeof(T));
  } else {
    using Bits = std::conditional_t<sizeof(T) == 2, uint16_t,
                                    std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>;
    Bits bits;
    std::memcpy(&bits, p, sizeof(bits));
    bits = byte_swap(bits);
    std::memcpy(&value, &bits, sizeof(value));
  }
  return value;
}

// Every type goes through double, as pbrt-v3 (via rply) does, so values convert identically.
template <bool kSwap>
inline double load_real(ScalarType type, const char* p) {
  switch (type) {
    case ScalarType::kInt8:
      return load<int8_t, kSwap>(p);
    case ScalarType::kUint8:
      return load<uint8_t, kSwap>(p);
    case ScalarType::kInt16:
      return load<int16_t, kSwap>(p);
    case ScalarType::kUint16:
      return load<uint16_t, kSwap>(p);
    case ScalarType::kInt32:
      return load<int32_t, kSwap>(p);
    case ScalarType::kUint32:
      return load<uint32_t, kSwap>(p);
    case ScalarType::kFloat32:
      return load<float, kSwap>(p);
    case ScalarType::kFloat64:
      return load<double, kSwap>(p);
  }
  return 0.0;
}

// Only called for integer types (the header check rejects float counts and indices).
template <bool kSwap>
inline int64_t load_integer(ScalarType type, const char* p) {
  switch (type) {
    case ScalarType::kInt8:
      return load<int8_t, kSwap>(p);
    case ScalarType::kUint8:
      return load<uint8_t, kSwap>(p);
    case ScalarType::kInt16:
      return load<int16_t, kSwap>(p);
    case ScalarType::kUint16:
      return load<uint16_t, kSwap>(p);
    case ScalarType::kInt32:
      return load<int32_t, kSwap>(p);
    case ScalarType::kUint32:
      return load<uint32_t, kSwap>(p);
    case ScalarType::kFloat32:
    case ScalarType::kFloat64:
      break;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Text helpers

inline bool is_space(char c) {
  return c == ' ' || (c >= '\t' && c <= '\r');
}

// Bytes from the file, made safe to print: cut short, non-printing bytes replaced.
std::string printable(std::string_view text) {
  std::string out;
  const size_t n = std::min(text.size(), kMaxQuotedBytes);
  out.reserve(n + 3);
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    out += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '?';
  }
  if (text.size() > n) out += "...";
  return out;
}

std::string quote(std::string_view text) {
  return "'" + printable(text) + "'";
}

// Splits a header line at spaces and tabs. Returns the number of tokens, which may exceed the
// array (only the first tokens.size() are stored), so callers can reject extra words.
template <size_t kN>
size_t split_words(std::string_view line, std::array<std::string_view, kN>* tokens) {
  size_t count = 0;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i == line.size()) break;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (count < kN) (*tokens)[count] = line.substr(start, i - start);
    ++count;
  }
  return count;
}

// A leading '+' is valid in printf output but not for from_chars; accept it once.
inline const char* skip_plus(const char* first, const char* last) {
  if (last - first >= 2 && first[0] == '+' && first[1] != '-' && first[1] != '+') return first + 1;
  return first;
}

// ---------------------------------------------------------------------------------------------
// The parser: one object per call, so the public functions stay reentrant.

class PlyParser {
 public:
  PlyParser(std::string_view bytes, PlyMesh* mesh, std::vector<std::string>* warnings)
      : bytes_(bytes), mesh_(mesh), warnings_(warnings) {}

  bool parse() {
    if (!parse_header() || !resolve_roles() || !check_counts()) return false;
    allocate();
    cur_ = bytes_.data() + data_begin_;
    end_ = bytes_.data() + bytes_.size();
    const bool swap = (format_ == Format::kBinaryBigEndian) != kHostIsBigEndian;
    for (const Element& element : elements_) {
      bool ok;
      if (format_ == Format::kAscii) {
        ok = read_ascii_element(element);
      } else if (swap) {
        ok = read_binary_element<true>(element);
      } else {
        ok = read_binary_element<false>(element);
      }
      if (!ok) return false;
    }
    // Trailing bytes after the last element are ignored, as rply does.
    return true;
  }

  const std::string& message() const { return message_; }

 private:
  static constexpr size_t kNone = static_cast<size_t>(-1);

  bool fail(std::string message) {
    message_ = std::move(message);
    return false;
  }

  std::string line_label() const { return "header line " + std::to_string(line_number_); }

  // ---- Header

  bool next_header_line(std::string_view* line) {
    if (pos_ >= bytes_.size()) {
      return fail("header: missing end_header (input ends after line " +
                  std::to_string(line_number_) + ")");
    }
    ++line_number_;
    const char* start = bytes_.data() + pos_;
    const size_t remaining = bytes_.size() - pos_;
    const size_t window = std::min(remaining, kMaxHeaderLineBytes + 1);
    const void* newline = std::memchr(start, '\n', window);
    size_t length;
    if (newline != nullptr) {
      length = static_cast<size_t>(static_cast<const char*>(newline) - start);
      pos_ += length + 1;
    } else if (remaining > kMaxHeaderLineBytes) {
      return fail(line_label() + ": longer than " + std::to_string(kMaxHeaderLineBytes) + " bytes");
    } else {
      length = remaining;  // the last line of the input, without a line end
      pos_ = bytes_.size();
    }
    *line = std::string_view(start, length);
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);  // CRLF headers
    return true;
  }

  bool parse_header() {
    if (bytes_.empty()) return fail("empty input");
    if (bytes_.size() < 3 || bytes_.substr(0, 3) != "ply") {
      return fail("missing \"ply\" magic at start of file");
    }
    std::string_view line;
    if (!next_header_line(&line)) return false;
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    if (line != "ply") return fail("header line 1: expected \"ply\", got " + quote(line));

    bool have_format = false;
    for (;;) {
      if (!next_header_line(&line)) return false;
      std::array<std::string_view, 5> words;
      const size_t n = split_words(line, &words);
      if (n == 0) continue;  // blank lines are harmless; tolerate them
      const std::string_view keyword = words[0];
      if (keyword == "comment" || keyword == "obj_info") continue;
      if (keyword == "end_header") {
        if (n != 1) return fail(line_label() + ": unexpected words after end_header");
        break;
      }
      if (keyword == "format") {
        if (have_format) return fail(line_label() + ": second format line");
        if (!parse_format(words, n)) return false;
        have_format = true;
      } else if (keyword == "element") {
        if (!parse_element(words, n)) return false;
      } else if (keyword == "property") {
        if (!parse_property(words, n)) return false;
      } else {
        // Old exporters wrote free text without "comment" (Blender 2.4's "Created by ...").
        // A line that is not format, element, property or end_header cannot change the layout,
        // so it is skipped, and said.
        warnings_->push_back(line_label() + ": skipped " + quote(line) +
                             " (not a PLY header keyword)");
      }
    }
    if (!have_format) return fail("header: no format line");
    data_begin_ = pos_;
    return true;
  }

  bool parse_format(const std::array<std::string_view, 5>& words, size_t n) {
    if (n != 3) return fail(line_label() + ": expected 'format <type> 1.0'");
    if (words[1] == "ascii") {
      format_ = Format::kAscii;
    } else if (words[1] == "binary_little_endian") {
      format_ = Format::kBinaryLittleEndian;
    } else if (words[1] == "binary_big_endian") {
      format_ = Format::kBinaryBigEndian;
    } else {
      return fail(line_label() + ": unknown format " + quote(words[1]));
    }
    if (words[2] != "1.0" && words[2] != "1") {
      return fail(line_label() + ": unsupported PLY version " + quote(words[2]));
    }
    return true;
  }

  bool parse_element(const std::array<std::string_view, 5>& words, size_t n) {
    if (n != 3) return fail(line_label() + ": expected 'element <name> <count>'");
    Element element;
    element.name = words[1];
    const std::string_view count = words[2];
    const auto result = std::from_chars(count.data(), count.data() + count.size(), element.count);
    if (result.ec == std::errc::result_out_of_range) {
      return fail(line_label() + ": element count " + quote(count) + " is too large");
    }
    if (result.ec != std::errc() || result.ptr != count.data() + count.size()) {
      return fail(line_label() + ": element count " + quote(count) +
                  " is not a non-negative integer");
    }
    if (element.name == "vertex" || element.name == "face") {
      size_t* slot = element.name == "vertex" ? &vertex_element_ : &face_element_;
      if (*slot != kNone)
        return fail(line_label() + ": second " + std::string(element.name) + " element");
      *slot = elements_.size();
      element.kind = element.name == "vertex" ? ElementKind::kVertex : ElementKind::kFace;
    }
    elements_.push_back(std::move(element));
    return true;
  }

  bool parse_property(const std::array<std::string_view, 5>& words, size_t n) {
    if (elements_.empty()) return fail(line_label() + ": property before any element");
    Property property;
    if (n >= 2 && words[1] == "list") {
      if (n != 5)
        return fail(line_label() + ": expected 'property list <count type> <type> <name>'");
      if (!parse_scalar_type(words[2], &property.count_type)) {
        return fail(line_label() + ": unknown type " + quote(words[2]));
      }
      if (!is_integer(property.count_type)) {
        return fail(line_label() + ": list count type " + quote(words[2]) +
                    " is not an integer type");
      }
      if (!parse_scalar_type(words[3], &property.value_type)) {
        return fail(line_label() + ": unknown type " + quote(words[3]));
      }
      property.is_list = true;
      property.name = words[4];
    } else {
      if (n != 3) return fail(line_label() + ": expected 'property <type> <name>'");
      if (!parse_scalar_type(words[1], &property.value_type)) {
        return fail(line_label() + ": unknown type " + quote(words[1]));
      }
      property.name = words[2];
    }
    elements_.back().properties.push_back(property);
    return true;
  }

  // ---- Meaning: which property feeds which output

  static Property* find_property(Element* element, std::string_view name) {
    // The first of duplicate names wins, as with rply's lookup.
    for (Property& property : element->properties) {
      if (property.name == name) return &property;
    }
    return nullptr;
  }

  bool assign_scalar(Property* property, Role role) {
    if (property->is_list) {
      return fail("header: vertex property '" + std::string(property->name) + "' is a list");
    }
    property->role = role;
    return true;
  }

  bool resolve_roles() {
    if (vertex_element_ == kNone) return fail("header: no vertex element");
    if (face_element_ == kNone) return fail("header: no face element");
    Element* vertex = &elements_[vertex_element_];
    Element* face = &elements_[face_element_];

    static constexpr std::string_view kPositionNames[3] = {"x", "y", "z"};
    static constexpr Role kPositionRoles[3] = {Role::kX, Role::kY, Role::kZ};
    for (int i = 0; i < 3; ++i) {
      Property* property = find_property(vertex, kPositionNames[i]);
      if (property == nullptr) {
        return fail("header: vertex element has no '" + std::string(kPositionNames[i]) +
                    "' property");
      }
      if (!assign_scalar(property, kPositionRoles[i])) return false;
    }

    // Normals and uvs are used only when complete; a partial set is a broken exporter.
    static constexpr std::string_view kNormalNames[3] = {"nx", "ny", "nz"};
    static constexpr Role kNormalRoles[3] = {Role::kNx, Role::kNy, Role::kNz};
    Property* normal[3];
    int normal_count = 0;
    for (int i = 0; i < 3; ++i) {
      normal[i] = find_property(vertex, kNormalNames[i]);
      normal_count += normal[i] != nullptr;
    }
    if (normal_count == 3) {
      for (int i = 0; i < 3; ++i) {
        if (!assign_scalar(normal[i], kNormalRoles[i])) return false;
      }
      has_normals_ = true;
    } else if (normal_count > 0) {
      int present = 0, missing = 0;
      for (int i = 0; i < 3; ++i) (normal[i] != nullptr ? present : missing) = i;
      return fail("header: vertex has '" + std::string(kNormalNames[present]) + "' but no '" +
                  std::string(kNormalNames[missing]) + "'");
    }

    // pbrt-v3 tries these pairs in this order and takes the first whose both names exist.
    static constexpr std::string_view kUvNames[4][2] = {
        {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
    std::string half_pair;
    for (const auto& pair : kUvNames) {
      Property* u = find_property(vertex, pair[0]);
      Property* v = find_property(vertex, pair[1]);
      if (u != nullptr && v != nullptr) {
        if (!assign_scalar(u, Role::kU) || !assign_scalar(v, Role::kV)) return false;
        has_uvs_ = true;
        break;
      }
      if (half_pair.empty() && (u != nullptr || v != nullptr)) {
        half_pair = u != nullptr
                        ? "'" + std::string(pair[0]) + "' but no '" + std::string(pair[1]) + "'"
                        : "'" + std::string(pair[1]) + "' but no '" + std::string(pair[0]) + "'";
      }
    }
    if (!has_uvs_ && !half_pair.empty()) return fail("header: vertex has " + half_pair);

    // pbrt-v3 reads "vertex_indices"; "vertex_index" is the other common spelling.
    Property* indices = find_property(face, "vertex_indices");
    if (indices == nullptr) indices = find_property(face, "vertex_index");
    if (indices == nullptr) return fail("header: face element has no vertex_indices property");
    if (!indices->is_list || !is_integer(indices->value_type)) {
      return fail("header: face property '" + std::string(indices->name) +
                  "' is not a list of integers");
    }
    indices->role = Role::kVertexIndices;

    Property* face_indices = find_property(face, "face_indices");
    if (face_indices != nullptr) {
      if (face_indices->is_list || !is_integer(face_indices->value_type)) {
        return fail("header: face property 'face_indices' is not a scalar integer");
      }
      face_indices->role = Role::kFaceIndex;
      has_face_indices_ = true;
    }
    return true;
  }

  // ---- Counts against bytes: the guard that lets us allocate from the header's counts.

  bool check_counts() {
    const Element& vertex = elements_[vertex_element_];
    const Element& face = elements_[face_element_];
    if (vertex.count == 0) return fail("header: vertex count is 0");
    if (face.count == 0) return fail("header: face count is 0");
    if (vertex.count > kMaxVertices) {
      return fail("header: vertex count " + std::to_string(vertex.count) + " exceeds " +
                  std::to_string(kMaxVertices));
    }

    const bool ascii = format_ == Format::kAscii;
    const uint64_t data_bytes = bytes_.size() - data_begin_;
    // An ascii value is at least one character plus a separator, except the very last value of
    // the file, hence 2 bytes per value and one byte of slack.
    const uint64_t slack = ascii ? 1 : 0;
    uint64_t capacity = data_bytes + slack;
    for (Element& element : elements_) {
      uint64_t min_record = 0;
      bool has_list = false;
      // The bound counts lists as empty, so that a file whose real fault is a short face or a
      // cut gets that message rather than this one. min_face_bytes (below) is the tight bound.
      uint64_t min_face = 0;
      for (const Property& property : element.properties) {
        const uint64_t value_bytes = ascii ? 2 : scalar_size(property.value_type);
        const uint64_t bytes = ascii              ? 2
                               : property.is_list ? scalar_size(property.count_type)
                                                  : value_bytes;
        min_record += bytes;
        // A valid face lists at least 3 vertices.
        min_face += bytes + (property.role == Role::kVertexIndices ? 3 * value_bytes : 0);
        has_list |= property.is_list;
      }
      if (element.kind == ElementKind::kFace) min_face_bytes_ = min_face;
      if (!ascii && !has_list) {
        element.fixed_size = static_cast<size_t>(min_record);
        size_t offset = 0;
        for (const Property& property : element.properties) {
          if (property.role != Role::kSkip) {
            element.fields.push_back({offset, property.value_type, property.role});
          }
          offset += scalar_size(property.value_type);
        }
      }
      if (min_record == 0 || element.count == 0) continue;
      if (element.count > capacity / min_record) {
        const uint64_t bytes_left = capacity >= slack ? capacity - slack : 0;
        return fail("header: " + printable(element.name) + " count " +
                    std::to_string(element.count) + " exceeds what the file can hold (" +
                    std::to_string(bytes_left) + " bytes left)");
      }
      capacity -= element.count * min_record;
    }
    return true;
  }

  void allocate() {
    vertex_count_ = elements_[vertex_element_].count;
    const size_t n = static_cast<size_t>(vertex_count_);
    mesh_->positions.resize(3 * n);
    positions_ = mesh_->positions.data();
    if (has_normals_) {
      mesh_->normals.resize(3 * n);
      normals_ = mesh_->normals.data();
    }
    if (has_uvs_) {
      mesh_->uvs.resize(2 * n);
      uvs_ = mesh_->uvs.data();
    }
    // One triangle per face is the common case; quads and polygons grow the vector later. The
    // reservation is capped by the faces the bytes can hold when each lists 3 vertices, so a
    // lying count costs at most a few times the file's size, and then only until it is caught.
    const uint64_t data_bytes = bytes_.size() - data_begin_ + 1;
    const uint64_t faces = std::min({elements_[face_element_].count, kMaxTriangles,
                                     data_bytes / std::max<uint64_t>(min_face_bytes_, 1)});
    mesh_->indices.reserve(static_cast<size_t>(3 * faces));
    if (has_face_indices_) mesh_->face_indices.reserve(static_cast<size_t>(faces));
  }

  // ---- Sinks: where a value of a given role goes, with its checks

  bool store_vertex_value(Role role, double value, uint64_t vertex) {
    // The explicit range test also keeps the double-to-float conversion defined.
    if (!(std::fabs(value) <= kFloatMax)) {
      const char* what = role <= Role::kZ    ? "coordinate"
                         : role <= Role::kNz ? "normal"
                                             : "texture coordinate";
      const char* problem = std::isnan(value)   ? "is NaN"
                            : std::isinf(value) ? "is infinite"
                                                : "is out of float range";
      return fail("vertex " + std::to_string(vertex) + ": " + what + " " + problem);
    }
    const float f = static_cast<float>(value);
    const size_t i = static_cast<size_t>(vertex);
    switch (role) {
      case Role::kX:
        positions_[3 * i + 0] = f;
        break;
      case Role::kY:
        positions_[3 * i + 1] = f;
        break;
      case Role::kZ:
        positions_[3 * i + 2] = f;
        break;
      case Role::kNx:
        normals_[3 * i + 0] = f;
        break;
      case Role::kNy:
        normals_[3 * i + 1] = f;
        break;
      case Role::kNz:
        normals_[3 * i + 2] = f;
        break;
      case Role::kU:
        uvs_[2 * i + 0] = f;
        break;
      case Role::kV:
        uvs_[2 * i + 1] = f;
        break;
      default:
        break;
    }
    return true;
  }

  bool set_face_index(int64_t value, uint64_t face) {
    if (value < INT32_MIN || value > INT32_MAX) {
      return fail("face " + std::to_string(face) + ": face_indices value " + std::to_string(value) +
                  " does not fit in int32");
    }
    face_index_ = static_cast<int32_t>(value);
    return true;
  }

  bool begin_face(int64_t size, uint64_t face) {
    if (size < 3) {
      return fail("face " + std::to_string(face) + " has " + std::to_string(size) + " vertices");
    }
    const uint64_t triangles = static_cast<uint64_t>(size) - 2;
    if (triangles > kMaxTriangles - triangle_count_) {
      return fail("face " + std::to_string(face) + ": mesh has more than " +
                  std::to_string(kMaxTriangles) + " triangles");
    }
    triangle_count_ += triangles;
    face_size_ = static_cast<uint64_t>(size);
    return true;
  }

  // Triangles are emitted as the face's indices stream in, so no face is ever buffered.
  // pbrt-v3 emits a triangle as (f0, f1, f2) and splits a quad into (f0, f1, f2) and
  // (f3, f0, f2). Larger polygons, which pbrt-v3 drops, are fan-triangulated here:
  // (f0, f[k-1], f[k]) for k = 2 .. n-1.
  bool add_face_vertex(int64_t value, uint64_t k, uint64_t face) {
    if (value < 0 || static_cast<uint64_t>(value) >= vertex_count_) {
      return fail("face " + std::to_string(face) + ": index " + std::to_string(value) +
                  " out of range (" + std::to_string(vertex_count_) + " vertices)");
    }
    const uint32_t index = static_cast<uint32_t>(value);
    std::vector<uint32_t>& out = mesh_->indices;
    if (k == 0) {
      face_first_ = index;
    } else if (k == 3 && face_size_ == 4) {
      out.push_back(index);
      out.push_back(face_first_);
      out.push_back(face_prev_);
    } else if (k >= 2) {
      out.push_back(face_first_);
      out.push_back(face_prev_);
      out.push_back(index);
    }
    face_prev_ = index;
    return true;
  }

  void begin_record(const Element& element) {
    if (element.kind == ElementKind::kFace) {
      face_size_ = 0;
      face_index_ = 0;
    }
  }

  void end_record(const Element& element) {
    // face_indices may come before or after the list in the record, so it is written last, once
    // per triangle the face produced.
    if (element.kind == ElementKind::kFace && has_face_indices_) {
      mesh_->face_indices.insert(mesh_->face_indices.end(), face_size_ - 2, face_index_);
    }
  }

  bool check_list_count(const Element& element, const Property& property, int64_t count,
                        uint64_t record) {
    if (count < 0) {
      return fail(printable(element.name) + " " + std::to_string(record) + ": list '" +
                  printable(property.name) + "' has negative count " + std::to_string(count));
    }
    if (property.role == Role::kVertexIndices) return begin_face(count, record);
    return true;
  }

  bool list_too_long(const Element& element, const Property& property, int64_t count,
                     uint64_t record) {
    return fail(printable(element.name) + " " + std::to_string(record) + ": list '" +
                printable(property.name) + "' count " + std::to_string(count) +
                " exceeds what the file can hold (" +
                std::to_string(static_cast<size_t>(end_ - cur_)) + " bytes left)");
  }

  bool truncated(const Element& element, uint64_t record) {
    return fail(printable(element.name) + " " + std::to_string(record) +
                ": unexpected end of data at byte " +
                std::to_string(static_cast<size_t>(cur_ - bytes_.data())));
  }

  // ---- Binary body

  template <bool kSwap>
  bool read_binary_element(const Element& element) {
    if (element.properties.empty() || element.count == 0) return true;
    const size_t left = static_cast<size_t>(end_ - cur_);
    if (element.fixed_size > 0) {
      // Records of one size: one bounds check for the whole element, then no checks per value.
      const uint64_t fits = left / element.fixed_size;
      if (element.count > fits) {
        cur_ += fits * element.fixed_size;
        return truncated(element, fits);
      }
      if (element.kind == ElementKind::kOther) {
        cur_ += element.count * element.fixed_size;  // nothing we want: jump over it
        return true;
      }
      return read_fixed_records<kSwap>(element);
    }
    return read_variable_records<kSwap>(element);
  }

  template <bool kSwap>
  bool read_fixed_records(const Element& element) {
    const char* record = cur_;
    for (uint64_t i = 0; i < element.count; ++i, record += element.fixed_size) {
      for (const Field& field : element.fields) {
        const char* p = record + field.offset;
        // Only vertex elements get here (a face element always has its list).
        if (!store_vertex_value(field.role, load_real<kSwap>(field.type, p), i)) return false;
      }
    }
    cur_ = record;
    return true;
  }

  template <bool kSwap>
  bool read_variable_records(const Element& element) {
    for (uint64_t i = 0; i < element.count; ++i) {
      begin_record(element);
      for (const Property& property : element.properties) {
        if (!property.is_list) {
          const size_t size = scalar_size(property.value_type);
          if (static_cast<size_t>(end_ - cur_) < size) return truncated(element, i);
          if (property.role == Role::kFaceIndex) {
            if (!set_face_index(load_integer<kSwap>(property.value_type, cur_), i)) return false;
          } else if (property.role != Role::kSkip) {
            if (!store_vertex_value(property.role, load_real<kSwap>(property.value_type, cur_),
                                    i)) {
              return false;
            }
          }
          cur_ += size;
          continue;
        }
        const size_t count_size = scalar_size(property.count_type);
        if (static_cast<size_t>(end_ - cur_) < count_size) return truncated(element, i);
        const int64_t count = load_integer<kSwap>(property.count_type, cur_);
        cur_ += count_size;
        if (!check_list_count(element, property, count, i)) return false;
        const size_t value_size = scalar_size(property.value_type);
        if (static_cast<uint64_t>(count) > static_cast<size_t>(end_ - cur_) / value_size) {
          return list_too_long(element, property, count, i);
        }
        if (property.role == Role::kVertexIndices) {
          for (int64_t k = 0; k < count; ++k, cur_ += value_size) {
            if (!add_face_vertex(load_integer<kSwap>(property.value_type, cur_),
                                 static_cast<uint64_t>(k), i)) {
              return false;
            }
          }
        } else {
          cur_ += static_cast<size_t>(count) * value_size;
        }
      }
      end_record(element);
    }
    return true;
  }

  // ---- Ascii body: a stream of whitespace-separated numbers, as rply reads it (line breaks
  // carry no meaning). Values of skipped properties are stepped over without being parsed.

  bool next_token(std::string_view* token) {
    while (cur_ < end_ && is_space(*cur_)) ++cur_;
    if (cur_ == end_) return false;
    const char* start = cur_;
    while (cur_ < end_ && !is_space(*cur_)) ++cur_;
    *token = std::string_view(start, static_cast<size_t>(cur_ - start));
    return true;
  }

  bool parse_ascii_integer(std::string_view token, ScalarType type, const Element& element,
                           uint64_t record, int64_t* value) {
    const char* last = token.data() + token.size();
    const char* first = skip_plus(token.data(), last);
    const auto result = std::from_chars(first, last, *value);
    if (result.ec != std::errc() || result.ptr != last) {
      return fail(printable(element.name) + " " + std::to_string(record) + ": " + quote(token) +
                  " is not a valid " + info(type).name);
    }
    if (*value < info(type).min || *value > info(type).max) {
      return fail(printable(element.name) + " " + std::to_string(record) + ": value " +
                  std::to_string(*value) + " out of range for " + info(type).name);
    }
    return true;
  }

  // Parsed as double, then narrowed, as pbrt-v3 does (rply reads ascii with strtod): parsing
  // straight to float could round a few values differently.
  bool parse_ascii_real(std::string_view token, ScalarType type, const Element& element,
                        uint64_t record, double* value) {
    if (is_integer(type)) {
      int64_t integer;
      if (!parse_ascii_integer(token, type, element, record, &integer)) return false;
      *value = static_cast<double>(integer);
      return true;
    }
    const char* last = token.data() + token.size();
    const char* first = skip_plus(token.data(), last);
    const auto result = fast_float::from_chars(first, last, *value);
    if (result.ec != std::errc() || result.ptr != last) {
      return fail(printable(element.name) + " " + std::to_string(record) + ": " + quote(token) +
                  " is not a number");
    }
    return true;
  }

  bool read_ascii_element(const Element& element) {
    if (element.properties.empty()) return true;
    std::string_view token;
    for (uint64_t i = 0; i < element.count; ++i) {
      begin_record(element);
      for (const Property& property : element.properties) {
        if (!next_token(&token)) return truncated(element, i);
        if (!property.is_list) {
          if (property.role == Role::kFaceIndex) {
            int64_t value;
            if (!parse_ascii_integer(token, property.value_type, element, i, &value) ||
                !set_face_index(value, i)) {
              return false;
            }
          } else if (property.role != Role::kSkip) {
            double value;
            if (!parse_ascii_real(token, property.value_type, element, i, &value) ||
                !store_vertex_value(property.role, value, i)) {
              return false;
            }
          }
          continue;
        }
        int64_t count;
        if (!parse_ascii_integer(token, property.count_type, element, i, &count) ||
            !check_list_count(element, property, count, i)) {
          return false;
        }
        // Each value needs a digit and a separator (the file's last value needs no separator).
        if (static_cast<uint64_t>(count) > (static_cast<size_t>(end_ - cur_) + 1) / 2) {
          return list_too_long(element, property, count, i);
        }
        for (int64_t k = 0; k < count; ++k) {
          if (!next_token(&token)) return truncated(element, i);
          if (property.role != Role::kVertexIndices) continue;
          int64_t value;
          if (!parse_ascii_integer(token, property.value_type, element, i, &value) ||
              !add_face_vertex(value, static_cast<uint64_t>(k), i)) {
            return false;
          }
        }
      }
      end_record(element);
    }
    return true;
  }

  // ---- State

  std::string_view bytes_;
  PlyMesh* mesh_;
  std::vector<std::string>* warnings_;  // header lines skipped; never null
  std::string message_;

  // Header
  size_t pos_ = 0;
  size_t line_number_ = 0;
  size_t data_begin_ = 0;
  Format format_ = Format::kAscii;
  std::vector<Element> elements_;
  size_t vertex_element_ = kNone;
  size_t face_element_ = kNone;
  bool has_normals_ = false;
  bool has_uvs_ = false;
  bool has_face_indices_ = false;
  uint64_t min_face_bytes_ = 1;  // the smallest valid face record

  // Body
  const char* cur_ = nullptr;
  const char* end_ = nullptr;
  uint64_t vertex_count_ = 0;
  float* positions_ = nullptr;
  float* normals_ = nullptr;
  float* uvs_ = nullptr;
  uint64_t triangle_count_ = 0;

  // The face being read
  uint64_t face_size_ = 0;
  uint32_t face_first_ = 0;
  uint32_t face_prev_ = 0;
  int32_t face_index_ = 0;
};

bool report(PlyError* error, std::string message) {
  if (error != nullptr) error->message = std::move(message);
  return false;
}

// Closes a file descriptor on every path out of read_ply.
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

bool parse_ply(std::string_view bytes, PlyMesh* mesh, PlyError* error,
               std::vector<std::string>* warnings) {
  if (mesh == nullptr) return report(error, "no output mesh given");
  *mesh = PlyMesh();
  PlyMesh result;
  std::vector<std::string> said;
  PlyParser parser(bytes, &result, &said);
  bool ok;
  try {
    ok = parser.parse();
  } catch (const std::bad_alloc&) {
    // Counts are checked against the input size first, so this is a big, valid file.
    return report(error, "out of memory reading " + std::to_string(bytes.size()) + " bytes");
  } catch (const std::length_error&) {
    return report(error, "out of memory reading " + std::to_string(bytes.size()) + " bytes");
  }
  if (!ok) return report(error, parser.message());
  *mesh = std::move(result);
  if (warnings != nullptr) warnings->insert(warnings->end(), said.begin(), said.end());
  return true;
}

bool read_ply(const std::string& path, PlyMesh* mesh, PlyError* error,
              std::vector<std::string>* warnings) {
  if (mesh != nullptr) *mesh = PlyMesh();
  // Read in one block rather than memory-map: a mapped file that shrinks under us would fault
  // (SIGBUS), and the copy costs little next to parsing.
  FileDescriptor file;
  file.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (file.fd < 0) {
    return report(error, "cannot open file: " + std::generic_category().message(errno));
  }
  struct stat status;
  if (::fstat(file.fd, &status) != 0) {
    return report(error, "cannot stat file: " + std::generic_category().message(errno));
  }
  if (!S_ISREG(status.st_mode)) return report(error, "not a regular file");
  const size_t size = static_cast<size_t>(status.st_size);
  std::unique_ptr<char[]> buffer(new (std::nothrow) char[size > 0 ? size : 1]);
  if (buffer == nullptr) {
    return report(error, "out of memory reading " + std::to_string(size) + " bytes");
  }
  size_t got = 0;
  while (got < size) {
    const ssize_t n = ::read(file.fd, buffer.get() + got, size - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      return report(error, "read failed: " + std::generic_category().message(errno));
    }
    if (n == 0) break;  // the file shrank since fstat; parse what is there
    got += static_cast<size_t>(n);
  }
  return parse_ply(std::string_view(buffer.get(), got), mesh, error, warnings);
}

}  // namespace pbrtc
