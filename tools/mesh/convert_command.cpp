// tools/mesh/convert_command.cpp — `pbrt-mesh convert IN OUT`: any mesh format to any other.
//
// Reads IN with read_mesh, writes OUT with write_mesh, and prints one line saying what went
// through: counts and sizes on both sides, attributes the output format cannot hold, and for a
// Draco output the largest position error actually measured (by decoding the file just written)
// against the bound the quantization bits imply, so a lossy conversion is never silent.
#include <CLI/CLI.hpp>

#include <sys/stat.h>
#include <cstdio>
#include <string>

#include "format/draco_codec.h"
#include "tools/mesh/commands.h"
#include "tools/mesh/mesh.h"

namespace meshtools {
namespace {

struct ConvertArgs {
  std::string in, out;
  int draco_bits = 14;
  bool draco_sequential = false;
  bool ascii = false;
  bool plymesh = false;
  bool quiet = false;
};

long long file_size(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 ? static_cast<long long>(st.st_size) : -1;
}

// Attributes of m the format of ext drops (STL holds positions only; OFF and OBJ have no
// per-face integers).
std::string dropped_attributes(const Mesh& m, const std::string& ext) {
  std::string out;
  auto add = [&](const char* what) { out += out.empty() ? what : std::string(", ") + what; };
  if (ext == "stl") {
    if (!m.normals.empty()) add("normals");
    if (!m.uvs.empty()) add("uv");
  }
  if ((ext == "stl" || ext == "off" || ext == "obj") && !m.face_indices.empty())
    add("face indices");
  return out;
}

pbrta::MeshArrays arrays_of(const Mesh& m) {
  pbrta::MeshArrays a;
  a.positions = m.positions.data();
  a.indices = m.indices.data();
  a.num_vertices = m.num_vertices();
  a.num_triangles = m.num_triangles();
  return a;
}

int run_convert(const ConvertArgs& args) {
  Mesh mesh;
  std::string error;
  if (!read_input_mesh(args.in, &mesh, args.quiet)) return 1;
  WriteOptions opt;
  opt.ply_ascii = args.ascii;
  opt.pbrt = args.plymesh ? PbrtStyle::kPlymesh : PbrtStyle::kInline;
  opt.draco_bits = args.draco_bits;
  opt.draco_sequential = args.draco_sequential;
  if (!write_mesh(args.out, mesh, opt, &error)) {
    std::fprintf(stderr, "pbrt-mesh: error: %s\n", error.c_str());
    return 1;
  }
  const std::string ext = extension_of(args.out);
  std::string draco_note;
  if (ext == "drc") {
    // Measure what the quantization did, on the file as written.
    Mesh decoded;
    if (!read_mesh(args.out, &decoded, &error, true)) {
      std::fprintf(stderr, "pbrt-mesh: error: %s: written but does not decode: %s\n",
                   args.out.c_str(), error.c_str());
      return 1;
    }
    const double bound =
        pbrta::draco_position_bound(mesh.positions.data(), mesh.num_vertices(), args.draco_bits);
    const double slack = pbrta::draco_position_slack(mesh.positions.data(), mesh.num_vertices());
    const bool same_order = args.draco_sequential && decoded.num_vertices() == mesh.num_vertices();
    const double err = pbrta::draco_max_displacement(arrays_of(mesh), arrays_of(decoded),
                                                     bound + slack, same_order);
    char buf[200];
    std::snprintf(buf, sizeof buf, "; %d bits: largest position error %.3g (bound %.3g)%s",
                  args.draco_bits, err, bound + slack,
                  err <= bound + slack ? "" : " EXCEEDS THE BOUND");
    draco_note = buf;
    if (decoded.num_triangles() != mesh.num_triangles())
      draco_note += "; Draco kept " + std::to_string(decoded.num_triangles()) + " triangles";
  }
  if (!args.quiet) {
    const std::string dropped = dropped_attributes(mesh, ext);
    std::printf("%s -> %s: %zu vertices, %zu triangles, %lld -> %lld bytes%s%s\n", args.in.c_str(),
                args.out.c_str(), mesh.num_vertices(), mesh.num_triangles(), file_size(args.in),
                file_size(args.out), draco_note.c_str(),
                dropped.empty() ? "" : ("; dropped (format cannot hold): " + dropped).c_str());
  }
  return 0;
}

}  // namespace

void add_convert_command(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app->add_subcommand(
      "convert", "Convert between OBJ, PLY, OFF, STL, Draco .drc and pbrt shape files");
  cmd->add_option("IN", args->in, "Input mesh (.obj .ply .off .stl .drc .pbrt)")->required();
  cmd->add_option("OUT", args->out, "Output mesh (format by extension)")->required();
  cmd->add_option("--draco-bits", args->draco_bits, "Draco position quantization bits")
      ->check(CLI::Range(pbrta::kDracoMinPositionBits, pbrta::kDracoMaxPositionBits));
  cmd->add_flag("--draco-sequential", args->draco_sequential,
                "Draco: keep vertex and face order (larger file)");
  cmd->add_flag("--ascii", args->ascii, "PLY (also the plymesh beside a .pbrt): write ASCII");
  cmd->add_flag("--plymesh", args->plymesh,
                ".pbrt: write a plymesh shape and the .ply beside it, not an inline trianglemesh");
  cmd->add_flag("--quiet", args->quiet, "No progress and no summary line");
  cmd->callback([args, exit_code]() { *exit_code = run_convert(*args); });
}

}  // namespace meshtools
