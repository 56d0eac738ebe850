// tools/mesh/commands.h — the pbrt-mesh subcommands, one file each.
//
// Each add_*_command registers its subcommand, flags and callback on the CLI11 app; the callback
// sets *exit_code (0 on success, 1 on a failure it has reported on stderr as
// "pbrt-mesh: error: <file>: <reason>").
#pragma once

namespace CLI {
class App;
}

namespace meshtools {

void add_convert_command(CLI::App* app, int* exit_code);
void add_info_command(CLI::App* app, int* exit_code);
void add_normals_command(CLI::App* app, int* exit_code);
void add_simplify_command(CLI::App* app, int* exit_code);

}  // namespace meshtools
