// pbrt-mesh — mesh conversion and checks for pbrt scenes, on OpenMesh and Draco.
//
//   pbrt-mesh convert IN OUT      OBJ, PLY, OFF, STL, Draco .drc and pbrt shapes, any to any
//   pbrt-mesh info MESH           counts, bounds, attributes, topology problems, Draco bits
//   pbrt-mesh normals IN OUT      area/angle-weighted vertex normals with a crease angle
//   pbrt-mesh simplify IN OUT     quadric decimation, reporting the error it introduced
#include <CLI/CLI.hpp>

#include "tools/mesh/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"pbrt-mesh: convert, inspect and process meshes for pbrt scenes"};
  app.require_subcommand(1);
  int exit_code = 0;
  meshtools::add_convert_command(&app, &exit_code);
  meshtools::add_info_command(&app, &exit_code);
  meshtools::add_normals_command(&app, &exit_code);
  meshtools::add_simplify_command(&app, &exit_code);
  CLI11_PARSE(app, argc, argv);
  return exit_code;
}
