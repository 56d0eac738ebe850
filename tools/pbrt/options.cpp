#include "tools/pbrt/options.h"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "runtime/render/stop_flags.h"

namespace pbrt_tool {

namespace {

bool parse_int(const std::string& s, long long lo, long long hi, long long* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  long long v = std::strtoll(s.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || v < lo || v > hi) return false;
  *out = v;
  return true;
}

bool parse_float(const std::string& s, float* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  float v = std::strtof(s.c_str(), &end);
  if (*end != '\0') return false;
  *out = v;
  return true;
}

}  // namespace

bool parse_size(const std::string& text, uint64_t* bytes) {
  size_t i = 0;
  while (i < text.size() && (std::isdigit((unsigned char)text[i]) || text[i] == '.')) ++i;
  if (i == 0) return false;
  char* end = nullptr;
  double v = std::strtod(text.substr(0, i).c_str(), &end);
  if (*end != '\0' || v < 0) return false;
  std::string unit = text.substr(i);
  for (char& c : unit) c = char(std::tolower((unsigned char)c));
  double scale;
  if (unit.empty() || unit == "m" || unit == "mb" || unit == "mib")
    scale = double(1 << 20);
  else if (unit == "k" || unit == "kb" || unit == "kib")
    scale = 1024.0;
  else if (unit == "g" || unit == "gb" || unit == "gib")
    scale = double(1 << 30);
  else if (unit == "t" || unit == "tb" || unit == "tib")
    scale = double(uint64_t(1) << 40);
  else if (unit == "b")
    scale = 1;
  else
    return false;
  *bytes = uint64_t(v * scale);
  return true;
}

bool parse_options(int argc, char** argv, Options* o, std::string* error) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.size() < 2 || arg[0] != '-') {
      o->files.push_back(arg);
      continue;
    }
    if (arg == "-") {  // standard input, as pbrtc takes it
      o->files.push_back(arg);
      continue;
    }
    std::string name = arg.substr(arg[1] == '-' ? 2 : 1);
    std::string value;
    bool has_value = false;
    if (size_t eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name.resize(eq);
      has_value = true;
    }
    // The option's argument: after '=' or the next word.
    auto take = [&](std::string* v) {
      if (has_value) {
        *v = value;
        return true;
      }
      if (i + 1 >= argc) {
        *error = "missing value after --" + name;
        return false;
      }
      *v = argv[++i];
      return true;
    };
    auto flag = [&]() {
      if (!has_value) return true;
      *error = "--" + name + " takes no value";
      return false;
    };
    std::string v;
    long long n;
    if (name == "help" || name == "h") {
      o->help = true;
    } else if (name == "nthreads") {
      if (!take(&v)) return false;
      if (!parse_int(v, 0, 1 << 16, &n)) {
        *error = "--nthreads needs a thread count, not \"" + v + "\"";
        return false;
      }
      o->nthreads = int(n);
    } else if (name == "outfile") {
      if (!take(&v)) return false;
      o->outfile = v;
    } else if (name == "quick") {
      if (!flag()) return false;
      o->quick = true;
    } else if (name == "quiet") {
      if (!flag()) return false;
      o->quiet = true;
    } else if (name == "cropwindow") {
      std::vector<std::string> words;
      if (has_value) {  // --cropwindow=x0,x1,y0,y1
        size_t start = 0;
        for (size_t c; (c = value.find(',', start)) != std::string::npos; start = c + 1)
          words.push_back(value.substr(start, c - start));
        words.push_back(value.substr(start));
      } else {
        for (int k = 0; k < 4 && i + 1 < argc; ++k) words.push_back(argv[++i]);
      }
      bool ok = words.size() == 4;
      for (int k = 0; ok && k < 4; ++k) ok = parse_float(words[size_t(k)], &o->crop[k]);
      if (!ok) {
        *error = "--cropwindow needs four numbers: x0 x1 y0 y1";
        return false;
      }
      if (o->crop[0] < 0 || o->crop[1] > 1 || o->crop[2] < 0 || o->crop[3] > 1 ||
          o->crop[0] >= o->crop[1] || o->crop[2] >= o->crop[3]) {
        *error = "--cropwindow needs 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1";
        return false;
      }
      o->has_crop = true;
    } else if (name == "cat") {
      if (!flag()) return false;
      o->cat = true;
    } else if (name == "toply") {
      if (!flag()) return false;
      o->toply = true;
    } else if (name == "spp") {
      if (!take(&v)) return false;
      if (!parse_int(v, 1, 1 << 30, &n)) {
        *error = "--spp needs a positive sample count, not \"" + v + "\"";
        return false;
      }
      o->spp = int(n);
    } else if (name == "seed") {
      if (!take(&v)) return false;
      char* end = nullptr;
      o->seed = std::strtoull(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0') {
        *error = "--seed needs a non-negative integer, not \"" + v + "\"";
        return false;
      }
    } else if (name == "stats") {
      if (!flag()) return false;
      o->stats = true;
    } else if (name == "cache-size") {
      if (!take(&v)) return false;
      if (!parse_size(v, &o->cache_bytes)) {
        *error = "--cache-size needs a size in MiB or with a unit (K, M, G, T), not \"" + v + "\"";
        return false;
      }
    } else if (name == "no-cache") {
      if (!flag()) return false;
      o->no_cache = true;
    } else if (name == "preview") {
      if (!take(&v)) return false;
      o->preview = v;
    } else if (name == "target-error" || name == "time-limit" || name == "checkpoint-every") {
      if (!take(&v)) return false;
      double* value = name == "target-error" ? &o->target_error
                      : name == "time-limit" ? &o->time_limit
                                             : &o->checkpoint_every;
      if (!rt::parse_stop_value(name, v, value, error)) return false;
    } else if (name == "error-layer") {
      if (!flag()) return false;
      o->error_layer = true;
    } else if (name == "save-state" || name == "resume") {
      if (!take(&v)) return false;
      (name == "resume" ? o->resume : o->save_state) = v;
    } else if (name == "logtostderr") {
      // pbrt-v3's logging options: accepted so existing scripts run; this pbrt logs nothing.
    } else if (name == "logdir" || name == "minloglevel" || name == "v") {
      if (!take(&v)) return false;
    } else {
      *error = "argument \"" + arg + "\" unknown";
      return false;
    }
  }
  if (o->cat && o->toply) {
    *error = "--cat and --toply cannot both be given";
    return false;
  }
  return true;
}

std::string usage_text() {
  return R"(usage: pbrt [<options>] <filename.pbrt...>
Rendering options:
  --cropwindow <x0,x1,y0,y1> Specify an image crop window.
  --help               Print this help text.
  --nthreads <num>     Use specified number of threads for rendering.
  --outfile <filename> Write the final image to the given filename.
  --quick              Automatically reduce a number of quality settings to
                       render more quickly.
  --quiet              Suppress all text output other than error messages.

Reformatting options:
  --cat                Print a reformatted version of the input file(s) to
                       standard output. Does not render an image.
  --toply              Print a reformatted version of the input file(s) to
                       standard output and convert all triangle meshes to
                       PLY files. Does not render an image.

Options of this pbrt (scenes are compiled once, then rendered from the cache):
  --spp <num>          Samples per pixel (overrides the scene's sampler and
                       --quick).
  --seed <num>         Seed for every random choice (same seed, same image).
  --preview <file.png> Also write an sRGB PNG preview of the image.
  --stats              Print whether the compiled scene came from the cache
                       (cache: hit, miss, rebuilt (corrupt or outdated)) and render
                       statistics.
  --cache-size <size>  Cap the compiled-scene cache at this size, in MiB or
                       with a unit (K, M, G, T). Default: 4G. The cache is in
                       $XDG_CACHE_HOME/pbrtc (default ~/.cache/pbrtc).
  --no-cache           Compile to a temporary file and remove it afterwards.
  --target-error <pct> Stop once the render's own error estimate (relative
                       RMS) is at most this many percent, e.g. 1 or 0.5%.
  --time-limit <t>     Stop before a pass that would end after t (90, 90s,
                       10m, 1h) from the start. The first of --spp,
                       --target-error and --time-limit wins.
  --checkpoint-every <t> Write the image so far (and the state) this often.
                       Ctrl-C writes the image so far and exits non-zero.
  --error-layer        Add the per-pixel error estimate to the EXR (layer
                       "error").
  --save-state <file>  Write the render's raw sums here (pbrt-merge joins
                       several; --resume continues one).
  --resume <file>      Continue the render a --save-state file holds.

pbrt-v3's logging options (--logdir <dir>, --logtostderr, --minloglevel <num>,
--v <verbosity>) are accepted and ignored. With no file, the scene is read
from standard input.
)";
}

}  // namespace pbrt_tool
