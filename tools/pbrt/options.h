// tools/pbrt/options.h — pbrt's command line: pbrt-v3's options, then this project's.
//
// Parsed by hand, as pbrt-v3 parses it, so scripts written for pbrt-v3 run unchanged:
// "--opt value" and "--opt=value", one dash or two, --cropwindow's four numbers as
// separate words (or comma separated after '='), pbrt-v3's logging options accepted and
// ignored. Everything not an option is a scene file; none means standard input.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pbrt_tool {

struct Options {
  std::vector<std::string> files;  // empty: standard input
  int nthreads = 0;                // 0: all cores
  std::string outfile;
  bool quick = false;
  bool quiet = false;
  bool has_crop = false;
  float crop[4] = {0, 1, 0, 1};
  bool cat = false;
  bool toply = false;
  bool help = false;
  // This project's.
  int spp = 0;
  uint64_t seed = 0;
  bool stats = false;
  uint64_t cache_bytes = uint64_t(4) << 30;
  bool no_cache = false;
  std::string preview;
  // Passes and stopping (runtime/render/render_job.h): fractions and seconds, 0 for none.
  double target_error = 0, time_limit = 0, checkpoint_every = 0;
  bool error_layer = false;
  std::string save_state, resume;
};

// False with *error on a bad command line.
bool parse_options(int argc, char** argv, Options* options, std::string* error);

// "512" (MiB), "512M", "4G", "4GiB", "100k", "1T": bytes, or false.
bool parse_size(const std::string& text, uint64_t* bytes);

// The --help text.
std::string usage_text();

}  // namespace pbrt_tool
