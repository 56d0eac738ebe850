#include "compiler/mesh_builder.h"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "format/draco_codec.h"
#include "compiler/ply_reader.h"

namespace pbrtc {

namespace {

std::string desc(const ParsedParam& p) {
  return "\"" + std::string(p.type_name) + " " + std::string(p.name) + "\"";
}

bool has_drc_extension(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".drc";
}

// Reads a whole file; false with a message on any failure.
bool read_bytes(const std::string& path, std::vector<uint8_t>* out, std::string* error) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    *error = std::strerror(errno);
    return false;
  }
  out->clear();
  uint8_t buffer[1 << 16];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0)
    out->insert(out->end(), buffer, buffer + n);
  const bool ok = !std::ferror(f);
  if (!ok) *error = std::strerror(errno);
  std::fclose(f);
  return ok;
}

// A Draco-compressed mesh in place of a PLY file: decoded by the wrapper the archive uses, with
// the limits its size implies, in a budgeted child process (format/draco_codec.h).
bool load_drc(const std::string& path, Loc filename_loc, Diagnostics* diag, TriangleMesh* mesh) {
  std::vector<uint8_t> bytes;
  std::string error;
  pbrta::DecodedMesh decoded;
  if (!read_bytes(path, &bytes, &error) ||
      !pbrta::draco_decode_isolated(bytes.data(), bytes.size(), &decoded, &error)) {
    diag->error(filename_loc, "cannot read Draco file \"" + path + "\": " + error);
    return false;
  }
  mesh->P = std::move(decoded.positions);
  mesh->N = std::move(decoded.normals);
  mesh->uv = std::move(decoded.uv);
  mesh->indices = std::move(decoded.indices);
  mesh->face_indices = std::move(decoded.face_indices);
  return true;
}

}  // namespace

bool build_trianglemesh(const ParamList& params, Loc shape_loc, Diagnostics* diag,
                        TriangleMesh* mesh) {
  const ParsedParam* P = params.find("P");
  if (!P || P->type != ParamType::kPoint3) {
    diag->error(shape_loc, "trianglemesh needs vertex positions \"point3 P\"");
    return false;
  }
  size_t nv = P->count / 3;
  mesh->P = params.take_floats(*P);
  const ParsedParam* I = params.find("indices");
  if (!I) {
    // pbrt-v3: a single triangle may leave out its indices.
    if (nv != 3) {
      diag->error(shape_loc,
                  "trianglemesh needs \"integer indices\" (only a mesh of exactly 3 "
                  "vertices may leave them out)");
      return false;
    }
    mesh->indices = {0, 1, 2};
  } else {
    if (I->type != ParamType::kInteger) {
      diag->error(I->loc, "trianglemesh indices must be \"integer indices\"");
      return false;
    }
    if (I->count % 3 != 0) {
      diag->error(I->value_loc,
                  "trianglemesh has " + std::to_string(I->count) + " indices, not a multiple of 3");
      return false;
    }
    // Validate first, then copy in one block: no zero-fill, no per-element stores.
    const int32_t* src = params.ints_of(*I);
    for (uint32_t i = 0; i < I->count; ++i) {
      if (uint32_t(src[i]) >= nv) {  // negative values wrap to huge
        diag->error(I->value_loc, "trianglemesh index " + std::to_string(src[i]) + " (entry " +
                                      std::to_string(i) +
                                      ") is out of range: " + std::to_string(nv) + " vertices");
        return false;
      }
    }
    mesh->indices = params.take_uints(*I);
  }
  size_t nt = mesh->indices.size() / 3;
  auto per_vertex = [&](const char* name, ParamType type, int width, std::vector<float>* out) {
    const ParsedParam* p = params.find(name);
    if (!p || p->type != type) return true;  // wrong types are warned about by the resolver
    if (p->count != nv * size_t(width)) {
      diag->error(p->value_loc, "trianglemesh " + desc(*p) + " has " +
                                    std::to_string(p->count / size_t(width)) + " elements for " +
                                    std::to_string(nv) + " vertices");
      return false;
    }
    *out = params.take_floats(*p);
    return true;
  };
  if (!per_vertex("N", ParamType::kNormal3, 3, &mesh->N)) return false;
  if (!per_vertex("S", ParamType::kVector3, 3, &mesh->S)) return false;
  // uv: point2 or a flat float list, under "uv" or "st".
  for (const char* uvname : {"uv", "st"}) {
    const ParsedParam* p = params.find(uvname);
    if (!p || mesh->uv.size()) continue;
    if (p->type != ParamType::kPoint2 && p->type != ParamType::kFloat) continue;
    if (p->count != nv * 2) {
      diag->error(p->value_loc, "trianglemesh " + desc(*p) + " has " + std::to_string(p->count) +
                                    " numbers; " + std::to_string(nv) + " vertices need " +
                                    std::to_string(nv * 2));
      return false;
    }
    mesh->uv = params.take_floats(*p);
  }
  if (const ParsedParam* f = params.find("faceIndices"); f && f->type == ParamType::kInteger) {
    if (f->count != nt) {
      diag->error(f->value_loc, "trianglemesh \"integer faceIndices\" has " +
                                    std::to_string(f->count) + " entries for " +
                                    std::to_string(nt) + " triangles");
      return false;
    }
    mesh->face_indices.assign(params.ints_of(*f), params.ints_of(*f) + f->count);
  }
  return true;
}

bool load_plymesh(const std::string& path, Loc filename_loc, Diagnostics* diag,
                  TriangleMesh* mesh) {
  if (has_drc_extension(path)) return load_drc(path, filename_loc, diag, mesh);
  pbrtc::PlyMesh ply;
  pbrtc::PlyError err;
  std::vector<std::string> warnings;
  if (!pbrtc::read_ply(path, &ply, &err, &warnings)) {
    diag->error(filename_loc, "cannot read PLY file \"" + path + "\": " + err.message);
    return false;
  }
  for (const std::string& w : warnings)
    diag->warning(filename_loc, "PLY file \"" + path + "\": " + w);
  mesh->P = std::move(ply.positions);
  mesh->N = std::move(ply.normals);
  mesh->uv = std::move(ply.uvs);
  mesh->indices = std::move(ply.indices);
  mesh->face_indices = std::move(ply.face_indices);
  return true;
}

}  // namespace pbrtc
