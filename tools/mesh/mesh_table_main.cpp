// mesh-table — PLY against Draco for a set of PLY meshes, as a Markdown table (the README's).
//
//   mesh-table [--root DIR] [--bits 11,14,16] [--sequential] FILE.ply...
//
// Each mesh is read with the project's PLY reader, written as binary PLY (compiler/ply_writer.h)
// to measure that size, and encoded and decoded with the project's Draco wrapper at each bit
// depth, with the options pbrtc uses for archives (edgebreaker unless --sequential). The
// position error is measured against the original vertices: with --sequential the order is
// kept and vertices are compared index by index; otherwise each decoded vertex is matched to
// its nearest original, as the wrapper's own draco_max_displacement does. Both errors are per
// axis, the measure the bound limits: "Max" is the largest coordinate difference, "RMS" the root
// mean square of all coordinate differences (so it never exceeds Max).
// Times are the best of several runs, so one slow run (a page fault, another process) does not
// decide them. tools/mesh_table.sh runs this over the shared corpus.
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "format/draco_codec.h"
#include "compiler/ply_reader.h"
#include "compiler/ply_writer.h"

namespace {

using Clock = std::chrono::steady_clock;

// Runs fn at least once and until it has had 0.5 s or 7 runs; returns the fastest run in ms.
template <typename Fn>
double best_ms(Fn fn) {
  double best = 1e300, total = 0;
  for (int run = 0; run < 7 && (run == 0 || total < 500); ++run) {
    auto t0 = Clock::now();
    if (!fn()) return -1;
    double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    best = std::min(best, ms);
    total += ms;
  }
  return best;
}

std::string bytes_text(uint64_t n) {
  char buf[32];
  if (n < 10 * 1024)
    std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(n));
  else if (n < 10 * 1024 * 1024)
    std::snprintf(buf, sizeof buf, "%.1f KiB", n / 1024.0);
  else
    std::snprintf(buf, sizeof buf, "%.2f MiB", n / (1024.0 * 1024.0));
  return buf;
}

std::string g3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mesh-table: PLY against Draco sizes, errors and times, as a Markdown table"};
  std::vector<std::string> files;
  std::string root;
  std::vector<int> bits = {11, 14, 16};
  bool sequential = false;
  app.add_option("files", files, "PLY meshes")->required();
  app.add_option("--root", root, "name meshes relative to this directory");
  app.add_option("--bits", bits, "Draco position bits to measure")
      ->delimiter(',')
      ->check(CLI::Range(pbrta::kDracoMinPositionBits, pbrta::kDracoMaxPositionBits));
  app.add_flag("--sequential", sequential,
               "Draco's sequential encoding (keeps vertex order; errors compared index-wise)");
  CLI11_PARSE(app, argc, argv);

  std::printf(
      "| Mesh | Vertices | Triangles | PLY | Bits | DRC | PLY/DRC | Bits/vertex "
      "| Max error | RMS error | Bound | Encode ms | Decode ms |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  const std::string tmp_ply = (std::filesystem::temp_directory_path() /
                               ("mesh-table-" + std::to_string(::getpid()) + ".ply"))
                                  .string();
  int failures = 0;
  for (const std::string& path : files) {
    std::string name = path;
    if (!root.empty()) {
      auto rel = std::filesystem::path(path).lexically_relative(root);
      if (!rel.empty()) name = rel.generic_string();
    }
    pbrtc::PlyMesh mesh;
    pbrtc::PlyError ply_error;
    if (!pbrtc::read_ply(path, &mesh, &ply_error)) {
      std::fprintf(stderr, "mesh-table: %s: %s\n", path.c_str(), ply_error.message.c_str());
      ++failures;
      continue;
    }
    const pbrta::MeshArrays view = pbrta::arrays_of(mesh);
    std::string error;
    if (!pbrtc::write_ply(tmp_ply, view, &error)) {
      std::fprintf(stderr, "mesh-table: %s: %s\n", tmp_ply.c_str(), error.c_str());
      return 1;
    }
    std::error_code ec;
    const uint64_t ply_bytes = std::filesystem::file_size(tmp_ply, ec);
    std::filesystem::remove(tmp_ply, ec);

    const pbrta::MeshArrays& in = view;
    for (int b : bits) {
      pbrta::DracoOptions opt;
      opt.position_bits = b;
      opt.sequential = sequential;
      std::vector<uint8_t> stream;
      const double enc_ms = best_ms([&] {
        stream.clear();
        return pbrta::draco_encode(in, opt, &stream, &error);
      });
      pbrta::DecodedMesh out;
      const double dec_ms = enc_ms < 0 ? -1 : best_ms([&] {
        return pbrta::draco_decode(stream.data(), stream.size(), &out, &error);
      });
      if (enc_ms < 0 || dec_ms < 0) {
        std::fprintf(stderr, "mesh-table: %s at %d bits: %s\n", path.c_str(), b, error.c_str());
        ++failures;
        continue;
      }
      const double bound = pbrta::draco_position_bound(in.positions, in.num_vertices, b);
      const bool same_order = sequential && out.num_vertices() == in.num_vertices;
      std::vector<uint32_t> nearest;
      const double max_err =
          pbrta::draco_max_displacement(in, out.view(), bound, same_order, &nearest);
      double sum2 = 0;
      for (size_t v = 0; v < out.num_vertices(); ++v) {
        const size_t o = same_order ? v : nearest[v];
        for (int k = 0; k < 3; ++k) {
          const double d = double(out.positions[3 * v + k]) - in.positions[3 * o + k];
          sum2 += d * d;
        }
      }
      const double rms = out.num_vertices() ? std::sqrt(sum2 / (3.0 * out.num_vertices())) : 0;
      char row[512];
      std::snprintf(row, sizeof row,
                    "| %s | %zu | %zu | %s | %d | %s | %.1f | %.1f | %s | %s | %s | %.2f | %.2f |",
                    name.c_str(), in.num_vertices, in.num_triangles, bytes_text(ply_bytes).c_str(),
                    b, bytes_text(stream.size()).c_str(), double(ply_bytes) / stream.size(),
                    8.0 * stream.size() / std::max<size_t>(in.num_vertices, 1), g3(max_err).c_str(),
                    g3(rms).c_str(), g3(bound).c_str(), enc_ms, dec_ms);
      std::printf("%s\n", row);
    }
  }
  return failures ? 1 : 0;
}
