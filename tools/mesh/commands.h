// tools/mesh/commands.h — the pbrt-mesh subcommands, one file each.
//
// Each add_*_command registers its subcommand, flags and callback on the CLI11 app; the callback
// sets *exit_code (0 on success, 1 on a failure it has reported on stderr as
// "pbrt-mesh: error: <file>: <reason>").
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace meshtools {

void add_convert_command(CLI::App* app, int* exit_code);
void add_info_command(CLI::App* app, int* exit_code);
void add_normals_command(CLI::App* app, int* exit_code);
void add_simplify_command(CLI::App* app, int* exit_code);

struct Mesh;
// A subcommand's input: read_mesh, with its warnings printed as "pbrt-mesh: warning: ..." (not
// when quiet) and a failure as "pbrt-mesh: error: ...". False on failure.
bool read_input_mesh(const std::string& path, Mesh* mesh, bool quiet);

}  // namespace meshtools
