#include "compiler/archive_dump.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "compiler/bsdf_file.h"
#include "format/fourier_table.h"
#include "compiler/ply_writer.h"
#include "format/texel_format.h"

namespace pbrtc {

namespace {

using pbrta::Category;
using pbrta::Kind;
using pbrta::kNoIndex;

bool make_dir(const std::string& d, std::string* error) {
  if (::mkdir(d.c_str(), 0777) == 0 || errno == EEXIST) return true;
  *error = "cannot create directory '" + d + "': " + std::strerror(errno);
  return false;
}

std::string fmt_float(float v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", double(v));
  return b;
}
std::string fmt_double(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string_view decl_type(Kind k) {
  switch (k) {
    case Kind::kInt:
      return "integer";
    case Kind::kFloat:
    case Kind::kFloatTex:
      return "float";
    case Kind::kBool:
      return "bool";
    case Kind::kString:
      return "string";
    case Kind::kPoint2:
      return "point2";
    case Kind::kVector2:
      return "vector2";
    case Kind::kPoint3:
      return "point3";
    case Kind::kVector3:
      return "vector3";
    case Kind::kNormal3:
      return "normal";
    default:
      return "rgb";
  }
}

class Dumper {
 public:
  Dumper(const pbrta::SceneArchive& a, std::string outdir, DumpOptions options)
      : a_(a), outdir_(std::move(outdir)), opts_(std::move(options)) {}

  // The given parameters of an entity, as a pbrt parameter list.
  bool params(uint32_t entity, std::string* out) {
    const pbrta::EntityRecord& e = a_.entities[entity];
    const pbrta::TypeSpec& ts = a_.type_of(entity);
    // A newer minor version may append parameters this reader does not know: they are skipped.
    uint32_t known = std::min<uint32_t>(e.num_values, ts.num_params);
    for (uint32_t p = 0; p < known; ++p) {
      const pbrta::ValueRecord& v = a_.values[e.first_value + p];
      const pbrta::ParamSpec& ps = ts.params[p];
      if (!(v.flags & pbrta::kValueGiven)) continue;
      if (v.count == 0) continue;                     // bulk mesh arrays: written from the mesh
      if (ps.flags & pbrta::kParamDerived) continue;  // re-derived from the file written below
      if (skip_filename_ && ps.name == "filename") continue;  // a plymesh written inline
      std::string name(ps.name);
      if (v.texture != kNoIndex) {
        *out += " \"texture " + name + "\" \"tex" + std::to_string(v.texture) + "\"";
        continue;
      }
      std::string vals;
      uint32_t words = v.count * uint32_t(pbrta::kind_width(ps.kind));
      for (uint32_t w = 0; w < words; ++w) {
        uint32_t word = a_.words[v.offset + w];
        if (!vals.empty()) vals += ' ';
        switch (pbrta::kind_store(ps.kind)) {
          case pbrta::KindStore::kInt:
            vals += ps.kind == Kind::kBool ? (word ? "\"true\"" : "\"false\"")
                                           : std::to_string(int32_t(word));
            break;
          case pbrta::KindStore::kString:
            if (word == 0 && (ps.flags & pbrta::kParamFilename)) {
              if (opts_.original_files && !(ts.name == "plymesh" && name == "filename")) {
                std::string_view original = a_.path_of(entity);
                if (!original.empty()) {
                  vals += quoted(original);
                  break;
                }
              }
              // File data must come from the archive: meshes, lens files and images.
              if (ts.name == "realistic" && name == "lensfile") {
                if (!write_lens(entity, &vals)) return false;
                break;
              }
              if (ts.name == "fourier" && name == "bsdffile") {
                if (!write_bsdf(entity, &vals)) return false;
                break;
              }
              if ((ts.name == "imagemap" && name == "filename") || name == "mapname") {
                if (image_ == kNoIndex) {
                  error_ = "cannot dump " + std::string(ts.name) + " \"" + name +
                           "\": the archive holds no image for it";
                  return false;
                }
                if (!write_image(&vals)) return false;
                break;
              }
              if (!(e.category == uint8_t(Category::kShape) && ts.name == "plymesh")) {
                error_ = "cannot dump " + std::string(ts.name) + " \"" + name +
                         "\": the archive does not store that file's data yet";
                return false;
              }
              vals += quoted(ply_name_);
            } else if (word == 0 && ts.name == "mix" && name.substr(0, 13) == "namedmaterial") {
              vals += quoted("mat" + std::to_string(mix_[name == "namedmaterial1" ? 0 : 1]));
            } else {
              vals += quoted(a_.string(word));
            }
            break;
          case pbrta::KindStore::kFloat: {
            float f;
            std::memcpy(&f, &word, 4);
            vals += fmt_float(f);
            break;
          }
        }
      }
      *out += " \"" + std::string(decl_type(ps.kind)) + " " + name + "\" [" + vals + "]";
    }
    return true;
  }

  // The realistic camera's lens elements back out as a lens file.
  bool write_lens(uint32_t entity, std::string* vals) {
    const pbrta::ValueRecord* v = a_.value(entity, "lensdata");
    if (!v || v->count == 0 || v->count % 4) {
      error_ = "realistic camera without lens data";
      return false;
    }
    std::string name = "lenses/lens.dat";
    std::string text = "# lens elements: radius thickness eta aperture (mm)\n";
    const float* f = a_.floats(*v);
    for (uint32_t k = 0; k < v->count; ++k) text += fmt_float(f[k]) + (k % 4 == 3 ? "\n" : " ");
    std::string dir = outdir_ + "/lenses";
    ::mkdir(dir.c_str(), 0777);
    std::ofstream out(outdir_ + "/" + name, std::ios::binary);
    out << text;
    if (!out.flush()) {
      error_ = "cannot write '" + outdir_ + "/" + name + "'";
      return false;
    }
    *vals += quoted(name);
    return true;
  }

  // The fourier material's table backs out as a .bsdf file that reads back to the same arrays.
  bool write_bsdf(uint32_t entity, std::string* vals) {
    pbrta::FourierTableView t;
    if (!pbrta::fourier_table_of(a_, entity, &t, &error_)) return false;
    std::string name = "bsdfs/material" + std::to_string(entity) + ".bsdf";
    if (!make_dir(outdir_ + "/bsdfs", &error_)) return false;
    std::ofstream out(outdir_ + "/" + name, std::ios::binary);
    out << write_bsdf_file(t);
    if (!out.flush()) {
      error_ = "cannot write '" + outdir_ + "/" + name + "'";
      return false;
    }
    *vals += quoted(name);
    return true;
  }

  // The image of the texture or light being written (image_), as images/imageN.pfm: its texels
  // as decoded (the source image, or level 0 when it was not resampled), which compile back to
  // the same pyramid. The entity's gamma and scale already describe these texels (ARCHIVE.md).
  bool write_image(std::string* vals) {
    std::string name = "images/image" + std::to_string(image_) + ".pfm";
    if (written_images_.insert(image_).second) {
      const pbrta::ImageRecord& top = a_.images[image_];
      uint32_t src = top.source_image == kNoIndex ? image_ : top.source_image;
      const pbrta::ImageRecord& r = a_.images[src];
      if (r.width != top.source_width || r.height != top.source_height) {
        error_ = "cannot dump image " + std::to_string(image_) +
                 ": it was resampled and the archive does not hold its decoded texels";
        return false;
      }
      // f16 and unorm8 texels (pbrtc --texture-precision) go out as the floats they decode to:
      // the dump then compiles to an f32 archive of the quantised image, not to this one.
      const uint8_t* bytes = a_.reader().section_data(r.section) + r.offset;
      std::vector<float> widened;
      const float* texels = reinterpret_cast<const float*>(bytes);
      if (r.format != uint32_t(pbrta::PixelFormat::kFloat32)) {
        widened.resize(size_t(r.width) * r.height * r.channels);
        pbrta::decode_texels(r.format, bytes, widened.size(), widened.data());
        texels = widened.data();
      }
      if (!make_dir(outdir_ + "/images", &error_) ||
          !write_pfm(outdir_ + "/" + name, texels, r.width, r.height, r.channels, &error_))
        return false;
    }
    *vals += quoted(name);
    return true;
  }

  void transform(const pbrta::TransformRecord& t, std::string* out) {
    auto one = [&](const double* m) {
      // pbrt-v3 reads matrices column by column.
      std::string s = "Transform [";
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) s += (c || r ? " " : "") + fmt_double(m[r * 4 + c]);
      return s + "]\n";
    };
    if (std::memcmp(t.start, t.end, sizeof t.start) == 0) {
      *out += one(t.start);
    } else {
      *out += "ActiveTransform StartTime\n" + one(t.start) + "ActiveTransform EndTime\n" +
              one(t.end) + "ActiveTransform All\n";
    }
  }

  std::string medium(uint32_t m) const {
    return m == kNoIndex ? "\"\"" : "\"medium" + std::to_string(m) + "\"";
  }

  bool run(std::string* text) {
    std::string& o = *text;
    const pbrta::SceneRecord& s = a_.scene();
    o += "# Written by pbrtc --dump. Names are generated; the original names are in the\n"
         "# archive's provenance.\n";
    // TransformTimes: the camera's, then the rest of the scene's.
    const pbrta::TransformRecord& ct = a_.transforms[s.camera_transform];
    auto times = [&](const pbrta::TransformRecord& t) {
      if (t.start_time != 0 || t.end_time != 1)
        o += "TransformTimes " + fmt_double(t.start_time) + " " + fmt_double(t.end_time) + "\n";
    };
    // Media come first: they are global, and the camera may sit in one.
    for (uint32_t i = 0; i < a_.media.size; ++i) {
      transform(a_.transforms[a_.media[i].transform], &o);
      std::string p;
      if (!params(a_.media[i].entity, &p)) return false;
      o += "MakeNamedMedium \"medium" + std::to_string(i) + "\" \"string type\" \"" +
           std::string(a_.type_name(a_.media[i].entity)) + "\"" + p + "\n";
    }
    times(ct);
    if (s.camera_medium != kNoIndex) o += "MediumInterface \"\" " + medium(s.camera_medium) + "\n";
    transform(ct, &o);
    for (auto [entity, directive] : {std::pair{s.camera, "Camera"},
                                     {s.film, "Film"},
                                     {s.filter, "PixelFilter"},
                                     {s.sampler, "Sampler"},
                                     {s.integrator, "Integrator"},
                                     {s.accelerator, "Accelerator"}}) {
      std::string p;
      if (!params(entity, &p)) return false;
      o += std::string(directive) + " \"" + std::string(a_.type_name(entity)) + "\"" + p + "\n";
    }
    if (s.camera_medium != kNoIndex) o += "MediumInterface \"\" \"\"\n";
    // The rest of the scene's transform times (any non-camera transform).
    for (uint32_t i = 0; i < a_.transforms.size; ++i)
      if (i != s.camera_transform) {
        const pbrta::TransformRecord& t = a_.transforms[i];
        if (t.start_time != ct.start_time || t.end_time != ct.end_time)
          o += "TransformTimes " + fmt_double(t.start_time) + " " + fmt_double(t.end_time) + "\n";
        break;
      }
    o += "Identity\nWorldBegin\n";

    for (uint32_t i = 0; i < a_.textures.size; ++i) {
      const pbrta::TextureRecord& t = a_.textures[i];
      std::string p;
      image_ = t.image;
      if (!params(t.entity, &p)) return false;
      o += "TransformBegin\n";
      transform(a_.transforms[t.transform], &o);
      bool is_float = a_.entities[t.entity].category == uint8_t(Category::kFloatTexture);
      o += "Texture \"tex" + std::to_string(i) + "\" \"" + (is_float ? "float" : "spectrum") +
           "\" \"" + std::string(a_.type_name(t.entity)) + "\"" + p + "\nTransformEnd\n";
    }
    for (uint32_t i = 0; i < a_.materials.size; ++i) {
      const pbrta::MaterialRecord& m = a_.materials[i];
      mix_[0] = m.mix[0];
      mix_[1] = m.mix[1];
      std::string p;
      if (!params(m.entity, &p)) return false;
      o += "MakeNamedMaterial \"mat" + std::to_string(i) + "\" \"string type\" \"" +
           std::string(a_.type_name(m.entity)) + "\"" + p + "\n";
    }
    for (uint32_t i = 0; i < a_.lights.size; ++i) {
      const pbrta::LightRecord& l = a_.lights[i];
      std::string p;
      image_ = l.image;
      if (!params(l.entity, &p)) return false;
      o += "AttributeBegin\n";
      transform(a_.transforms[l.transform], &o);
      if (l.medium != kNoIndex) o += "MediumInterface \"\" " + medium(l.medium) + "\n";
      o += "LightSource \"" + std::string(a_.type_name(l.entity)) + "\"" + p + "\nAttributeEnd\n";
    }
    if (!shapes(&o)) return false;
    for (uint32_t i = 0; i < a_.instances.size; ++i) {
      o += "AttributeBegin\n";
      transform(a_.transforms[a_.instances[i].transform], &o);
      o +=
          "ObjectInstance \"object" + std::to_string(a_.instances[i].object) + "\"\nAttributeEnd\n";
    }
    o += "WorldEnd\n";
    return true;
  }

  // Shapes in order, with objects around their shapes and area lights made
  // current through a stack of attribute blocks (pbrt-v3 has no other way to
  // return to an earlier area light).
  bool shapes(std::string* out) {
    std::string& o = *out;
    std::vector<uint32_t> area_stack;
    size_t object_base = 0;  // area_stack depth when the current object began
    uint32_t next_area = 0, next_object = 0, cur_object = kNoIndex;
    auto push_area = [&](uint32_t upto) -> bool {
      for (; next_area <= upto; ++next_area) {
        std::string p;
        if (!params(a_.area_lights[next_area], &p)) return false;
        o += "AttributeBegin\nAreaLightSource \"" +
             std::string(a_.type_name(a_.area_lights[next_area])) + "\"" + p + "\n";
        area_stack.push_back(next_area);
      }
      return true;
    };
    auto pop_to = [&](size_t depth) {
      while (area_stack.size() > depth) {
        o += "AttributeEnd\n";
        area_stack.pop_back();
      }
    };
    auto open_object = [&](uint32_t obj) {
      for (; next_object <= obj; ++next_object) {
        o += "ObjectBegin \"object" + std::to_string(next_object) + "\"\n";
        if (next_object < obj) o += "ObjectEnd\n";  // an object with no shapes
      }
      object_base = area_stack.size();
      cur_object = obj;
    };
    auto close_object = [&]() {
      pop_to(object_base);
      o += "ObjectEnd\n";
      cur_object = kNoIndex;
    };
    for (uint32_t i = 0; i < a_.shapes.size; ++i) {
      const pbrta::ShapeRecord& sh = a_.shapes[i];
      if (sh.object != cur_object) {
        if (cur_object != kNoIndex) close_object();
        if (sh.object != kNoIndex) open_object(sh.object);
      }
      if (sh.area_light != kNoIndex) {
        if (sh.area_light >= next_area) {
          if (!push_area(sh.area_light)) return false;
        } else {
          size_t at = area_stack.size();
          while (at > 0 && area_stack[at - 1] != sh.area_light) --at;
          if (at == 0 || at <= object_base) {
            error_ = "cannot dump shape " + std::to_string(i) +
                     ": its area light is no longer reachable in pbrt-v3's attribute stack";
            return false;
          }
          pop_to(at);
        }
      } else if (cur_object == kNoIndex) {
        pop_to(0);
      }
      if (!shape(i, &o)) return false;
    }
    if (cur_object != kNoIndex) close_object();
    if (next_area < a_.area_lights.size && !push_area(a_.area_lights.size - 1)) return false;
    pop_to(0);
    if (next_object < a_.objects.size) {
      open_object(a_.objects.size - 1);
      close_object();
    }
    return true;
  }

  bool shape(uint32_t i, std::string* out) {
    const pbrta::ShapeRecord& sh = a_.shapes[i];
    std::string& o = *out;
    std::string_view type = a_.type_name(sh.entity);
    o += "AttributeBegin\nNamedMaterial \"mat" + std::to_string(sh.material) + "\"\n";
    if (sh.inside_medium != kNoIndex || sh.outside_medium != kNoIndex)
      o += "MediumInterface " + medium(sh.inside_medium) + " " + medium(sh.outside_medium) + "\n";
    if (sh.flags & pbrta::kShapeReverseOrientation) o += "ReverseOrientation\n";
    transform(a_.transforms[sh.transform], &o);
    std::string p;
    uint32_t m = sh.mesh;
    const bool is_mesh = type == "plymesh" || type == "trianglemesh";
    const bool as_ply = is_mesh && (opts_.meshes == DumpMeshes::kAllPly ||
                                    (type == "plymesh" && opts_.meshes == DumpMeshes::kAsCompiled));
    if (is_mesh && m == kNoIndex) {
      error_ = std::string(type) + " shape " + std::to_string(i) + " has no mesh";
      return false;
    }
    if (as_ply) {
      ply_name_ = opts_.mesh_prefix + std::to_string(m) + ".ply";
      size_t slash = ply_name_.find_last_of('/');
      if (slash != std::string::npos &&
          !make_dir(outdir_ + "/" + ply_name_.substr(0, slash), &error_))
        return false;
      if (written_meshes_.insert(m).second &&
          !pbrtc::write_ply(outdir_ + "/" + ply_name_, a_.mesh_arrays(m), &error_))
        return false;
    }
    skip_filename_ = is_mesh && !as_ply;
    bool ok = params(sh.entity, &p);
    skip_filename_ = false;
    if (!ok) return false;
    if (as_ply && type == "trianglemesh")
      p = " \"string filename\" [" + quoted(ply_name_) + "]" + p;
    if (is_mesh) type = as_ply ? "plymesh" : "trianglemesh";
    o += "Shape \"" + std::string(type) + "\"" + p;
    if (type == "trianglemesh") {
      const pbrta::MeshRecord& mr = a_.meshes[m];
      auto floats = [&](const char* decl, const float* d, uint64_t n) {
        if (!d) return;
        o += "\n  \"" + std::string(decl) + "\" [";
        for (uint64_t k = 0; k < n; ++k) o += (k ? " " : "") + fmt_float(d[k]);
        o += "]";
      };
      floats("point3 P", a_.positions(m), uint64_t(mr.num_vertices) * 3);
      floats("normal N", a_.normals(m), uint64_t(mr.num_vertices) * 3);
      floats("vector3 S", a_.tangents(m), uint64_t(mr.num_vertices) * 3);
      floats("point2 uv", a_.uvs(m), uint64_t(mr.num_vertices) * 2);
      o += "\n  \"integer indices\" [";
      const uint32_t* idx = a_.indices(m);
      for (uint64_t k = 0; k < uint64_t(mr.num_triangles) * 3; ++k)
        o += (k ? " " : "") + std::to_string(idx[k]);
      o += "]";
      if (const int32_t* fi = a_.face_indices(m)) {
        o += "\n  \"integer faceIndices\" [";
        for (uint64_t k = 0; k < mr.num_triangles; ++k) o += (k ? " " : "") + std::to_string(fi[k]);
        o += "]";
      }
    }
    o += "\nAttributeEnd\n";
    return true;
  }

  const std::string& error() const { return error_; }

 private:
  const pbrta::SceneArchive& a_;
  std::string outdir_;
  std::string error_;
  std::string ply_name_;
  uint32_t mix_[2] = {kNoIndex, kNoIndex};
  uint32_t image_ = kNoIndex;          // the image of the texture or light being written
  std::set<uint32_t> written_images_;  // images shared by several users are written once
  std::set<uint32_t> written_meshes_;  // instanced meshes likewise
  DumpOptions opts_;
  bool skip_filename_ = false;  // writing a plymesh's shape as an inline trianglemesh
};

}  // namespace

bool write_pfm(const std::string& path, const float* texels, uint32_t width, uint32_t height,
               uint32_t channels, std::string* error) {
  if (channels != 1 && channels != 3) {
    *error =
        "cannot write '" + path + "': PFM holds 1 or 3 channels, not " + std::to_string(channels);
    return false;
  }
  // A negative scale says little-endian; PFM stores the bottom row first.
  std::string bytes = std::string(channels == 3 ? "PF" : "Pf") + "\n" + std::to_string(width) +
                      " " + std::to_string(height) + "\n-1\n";
  const size_t row = size_t(width) * channels;
  const size_t header = bytes.size();
  bytes.resize(header + row * height * 4);
  char* out = bytes.data() + header;
  for (uint32_t y = height; y-- > 0;) {
    for (size_t k = 0; k < row; ++k) {
      uint32_t bits;
      std::memcpy(&bits, &texels[size_t(y) * row + k], 4);
      for (int b = 0; b < 4; ++b) *out++ = char((bits >> (8 * b)) & 0xFF);
    }
  }
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), std::streamsize(bytes.size()));
  if (!f.flush()) {
    *error = "cannot write '" + path + "'";
    return false;
  }
  return true;
}

bool dump_archive_text(const pbrta::SceneArchive& archive, const std::string& outdir,
                       const DumpOptions& options, std::string* text, std::string* error) {
  Dumper d(archive, outdir, options);
  text->clear();
  if (!d.run(text)) {
    *error = d.error();
    return false;
  }
  return true;
}

bool dump_archive(const pbrta::SceneArchive& archive, const std::string& outdir,
                  const std::string& scene_name, std::string* error) {
  if (!make_dir(outdir, error) || !make_dir(outdir + "/meshes", error)) return false;
  std::string text;
  if (!dump_archive_text(archive, outdir, DumpOptions(), &text, error)) return false;
  std::string path = outdir + "/" + scene_name;
  std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out.flush()) {
      *error = "cannot write '" + path + "'";
      std::remove(tmp.c_str());
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = "cannot write '" + path + "': " + std::strerror(errno);
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace pbrtc
