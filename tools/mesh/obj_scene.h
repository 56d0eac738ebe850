// tools/mesh/obj_scene.h — a Wavefront OBJ scene with its MTL materials, and its pbrt-v3 form.
//
// read_obj_scene parses an OBJ file and every MTL library it names (mtllib, relative to the OBJ's
// directory) into materials and shapes: one shape per object/group name (o, g) and material
// (usemtl), in order of first appearance. OBJ indexes positions, texture coordinates and normals
// separately; a shape gets one vertex per distinct (v, vt, vn) triple it uses, so normals and uv
// survive. Polygons are triangulated as fans (v0 v1 v2, v0 v2 v3, ...), as pbrt-v3's obj2pbrt
// does. Negative (relative) indices and `\` line continuations are supported.
//
// write_obj_scene_pbrt maps the result to pbrt-v3 directives the way pbrt-v3's own obj2pbrt
// (src/tools/obj2pbrt.cpp) does: each material becomes MakeNamedMaterial of type "uber" with Kd,
// Ks, roughness = 1/Ns (0 when Ns is 0), Kt, index = Ni and opacity = d (or 1 - Tr); map_Kd,
// map_Ks and bump/map_bump become "imagemap" textures (an image map times a non-black Kd/Ks is a
// "scale" texture); an emissive material (Ke) adds AreaLightSource "diffuse" to its shapes.
// The output is meant to be Included by a scene (no camera, no WorldBegin) unless
// ObjPbrtOptions::complete_scene asks for a minimal scene around it.
//
// Texture files are looked for as find_texture (obj_scene.cpp) says: the name as written, with
// `\` as a separator, the file name alone beside the MTL or the OBJ, then letter case aside.
//
// Failure: the input is untrusted text. A bad number (NaN, infinite, garbage), an index out of
// range or zero, a face of fewer than 3 vertices or an unreadable MTL library makes
// read_obj_scene return false with one message "path:line: reason". A texture file that cannot
// be found is a warning (the material keeps its constant colour), or that error when strict.
// Things pbrt-v3's obj2pbrt ignores (unknown statements, usemtl of an undefined material, map
// options) are kept as warnings. Every function is reentrant.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "tools/mesh/mesh.h"

namespace meshtools {

struct ObjMaterial {
  std::string name;
  // tinyobjloader's defaults, which pbrt-v3's obj2pbrt inherits: black colours, Ns 1, Ni 1, d 1.
  std::array<float, 3> kd{}, ks{}, kt{}, ke{};
  float ns = 1, ni = 1, d = 1;
  // Texture files as found on disk (see find_texture); "" when none was named or found.
  std::string map_kd, map_ks, map_bump;
};

struct ObjShape {
  std::string name;   // the o/g name ("" before any)
  int material = -1;  // index into ObjScene::materials; -1: no usemtl (the includer's material)
  Mesh mesh;          // normals and uvs only when every vertex of the shape has them
};

struct ObjScene {
  std::vector<ObjMaterial> materials;
  std::vector<ObjShape> shapes;
  std::vector<std::string> warnings;  // "path:line: text", each kind reported once per file
};

bool read_obj_scene(const std::string& path, ObjScene* scene, std::string* error,
                    bool strict = false);
// The same for OBJ text in memory; mtllib and map names resolve against base_dir.
bool parse_obj_scene(const std::string& display_path, const std::string& text,
                     const std::string& base_dir, ObjScene* scene, std::string* error,
                     bool strict = false);

struct ObjPbrtOptions {
  PbrtStyle style = PbrtStyle::kInline;  // kPlymesh: one "<out stem>-<n>.ply" beside the output
  bool complete_scene = false;           // wrap in Camera, Film, WorldBegin, a light and WorldEnd
  bool absolute_paths = false;           // texture and PLY file names absolute, not output-relative
  std::string source_name;               // named in the header comment
};

struct ObjPbrtStats {
  size_t shapes = 0, triangles = 0, area_lights = 0, materials = 0, textures = 0;
};

// Writes the scene to out_path (atomically; PLY files first, each atomically too).
bool write_obj_scene_pbrt(const ObjScene& scene, const std::string& out_path,
                          const ObjPbrtOptions& options, ObjPbrtStats* stats, std::string* error);

// pbrt-v3's roughness for an MTL shininess: 1/Ns, or 0 for Ns = 0 (float arithmetic, as there).
float roughness_from_ns(float ns);

}  // namespace meshtools
