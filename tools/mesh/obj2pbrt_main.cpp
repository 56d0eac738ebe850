// obj2pbrt — a Wavefront OBJ scene with its MTL materials to pbrt-v3 scene text.
//
//   obj2pbrt scene.obj scene.pbrt [--plymesh] [--scene] [--absolute-paths] [--strict] [--quiet]
//
// The materials are mapped as pbrt-v3's own obj2pbrt maps them (tools/mesh/obj_scene.h). The
// output is a fragment to Include after WorldBegin, unless --scene wraps it in a minimal scene.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

#include "tools/mesh/obj_scene.h"

int main(int argc, char** argv) {
  CLI::App app{
      "obj2pbrt: convert an OBJ scene and its MTL materials to pbrt-v3 scene text.\n\n"
      "The output holds Texture, MakeNamedMaterial, AreaLightSource and Shape directives only\n"
      "(no Camera, no WorldBegin): Include it after WorldBegin in a scene of your own, placed in\n"
      "the same directory (pbrt-v3 resolves file names against the top-level scene's\n"
      "directory). Each material becomes an \"uber\" material as pbrt-v3's obj2pbrt makes it;\n"
      "each OBJ object/group and material becomes one shape. --scene writes a complete scene\n"
      "instead (camera looking at the bounds, an infinite light) that compiles directly."};
  std::string input, output;
  bool plymesh = false, quiet = false, complete = false, absolute = false, strict = false;
  app.add_option("input", input, "the .obj file (mtllib files are read beside it)")->required();
  app.add_option("output", output, "the .pbrt file to write")->required();
  app.add_flag("--plymesh", plymesh,
               "write each shape as a binary PLY file beside the output (OUT-<n>.ply) and a "
               "plymesh shape naming it, instead of an inline trianglemesh");
  app.add_flag("--scene", complete,
               "wrap the shapes in a minimal complete scene (Camera, Film, WorldBegin, an "
               "infinite light, WorldEnd)");
  app.add_flag("--absolute-paths", absolute,
               "write texture and PLY file names as absolute paths, not relative to the output");
  app.add_flag("--strict", strict,
               "a texture file that cannot be found is an error (by default a warning, and the "
               "material keeps its constant colour)");
  app.add_flag("--quiet,-q", quiet, "print errors only");
  CLI11_PARSE(app, argc, argv);

  meshtools::ObjScene scene;
  std::string error;
  if (!meshtools::read_obj_scene(input, &scene, &error, strict)) {
    std::fprintf(stderr, "obj2pbrt: error: %s\n", error.c_str());
    return 1;
  }
  if (!quiet)
    for (const std::string& w : scene.warnings)
      std::fprintf(stderr, "obj2pbrt: warning: %s\n", w.c_str());
  meshtools::ObjPbrtOptions options;
  options.style = plymesh ? meshtools::PbrtStyle::kPlymesh : meshtools::PbrtStyle::kInline;
  options.complete_scene = complete;
  options.absolute_paths = absolute;
  options.source_name = input;
  meshtools::ObjPbrtStats stats;
  if (!meshtools::write_obj_scene_pbrt(scene, output, options, &stats, &error)) {
    std::fprintf(stderr, "obj2pbrt: error: %s\n", error.c_str());
    return 1;
  }
  if (!quiet)
    std::fprintf(stderr,
                 "obj2pbrt: %s: %zu shapes, %zu triangles, %zu materials, %zu textures, %zu area "
                 "lights\n",
                 output.c_str(), stats.shapes, stats.triangles, stats.materials, stats.textures,
                 stats.area_lights);
  return 0;
}
