// tools/mesh/command_input.cpp — how every pbrt-mesh subcommand reads its input mesh.
#include <cstdio>
#include <string>
#include <vector>

#include "tools/mesh/commands.h"
#include "tools/mesh/mesh.h"

namespace meshtools {

bool read_input_mesh(const std::string& path, Mesh* mesh, bool quiet) {
  std::string error;
  std::vector<std::string> warnings;
  if (!read_mesh(path, mesh, &error, quiet, &warnings)) {
    std::fprintf(stderr, "pbrt-mesh: error: %s\n", error.c_str());
    return false;
  }
  if (!quiet)
    for (const std::string& w : warnings)
      std::fprintf(stderr, "pbrt-mesh: warning: %s\n", w.c_str());
  return true;
}

}  // namespace meshtools
