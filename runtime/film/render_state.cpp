// runtime/film/render_state.cpp — see render_state.h.
#include "runtime/film/render_state.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "format/checksum.h"
#include "runtime/film/atomic_file.h"

namespace rt {
namespace {

constexpr char kMagic[8] = {'P', 'B', 'R', 'T', 'R', 'S', 'T', '1'};
constexpr uint32_t kVersion = 1;
constexpr size_t kFixedBytes = 108;

template <typename T>
void put(std::string* out, T v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename T>
T get(const std::string& in, size_t* at) {
  T v;
  std::memcpy(&v, in.data() + *at, sizeof v);
  *at += sizeof v;
  return v;
}

std::string bounds_text(const Bounds2i& b) {
  return "[" + std::to_string(b.min.x) + "," + std::to_string(b.max.x) + ")x[" +
         std::to_string(b.min.y) + "," + std::to_string(b.max.y) + ")";
}

// The same film: resolution and cropped pixel bounds.
bool same_windows(Point2i full_a, const Bounds2i& crop_a, Point2i full_b, const Bounds2i& crop_b) {
  return full_a == full_b && crop_a.min == crop_b.min && crop_a.max == crop_b.max;
}

}  // namespace

RenderState capture_state(const Film& film) {
  RenderState s;
  for (int h = 0; h < 2; ++h) {
    s.half_samples[h] = film.half_count(h);
    s.sums[h].reserve(film.half_sums(h).size());
    for (const FilmPixel& p : film.half_sums(h))
      s.sums[h].push_back({{p.rgb[0], p.rgb[1], p.rgb[2]}, p.weight});
    if (film.has_splats())
      s.splats[h].assign(film.half_splats(h).begin(), film.half_splats(h).end());
  }
  s.scale = film.scale();
  s.full_resolution = film.full_resolution();
  s.cropped = film.cropped_pixel_bounds();
  return s;
}

bool film_of_state(const RenderState& state, Film* film, std::string* error) {
  film->build_for_sums(state.full_resolution, state.cropped, float(state.scale));
  if (!state.splats[0].empty()) film->enable_splats();
  return restore_state(state, film, error);
}

bool restore_state(const RenderState& state, Film* film, std::string* error) {
  if (!same_windows(state.full_resolution, state.cropped, film->full_resolution(),
                    film->cropped_pixel_bounds())) {
    *error = "the state is of a " + std::to_string(state.full_resolution.x) + "x" +
             std::to_string(state.full_resolution.y) + " film, pixels " +
             bounds_text(state.cropped) + "; this render's film is " +
             std::to_string(film->full_resolution().x) + "x" +
             std::to_string(film->full_resolution().y) + ", pixels " +
             bounds_text(film->cropped_pixel_bounds()) + " (another resolution or crop)";
    return false;
  }
  if (!state.splats[0].empty() != film->has_splats()) {
    *error = std::string("the state ") + (film->has_splats() ? "has no" : "has") +
             " light-tracing splats and this render's integrator " +
             (film->has_splats() ? "makes them" : "does not");
    return false;
  }
  for (int h = 0; h < 2; ++h) {
    // Exact for a state this film saved; a merge of states (summed in double) is rounded.
    std::vector<FilmPixel>& sums = film->half_sums(h);
    sums.resize(state.sums[h].size());
    for (size_t i = 0; i < sums.size(); ++i) {
      const FilmPixelSum& p = state.sums[h][i];
      sums[i] = {{float(p.rgb[0]), float(p.rgb[1]), float(p.rgb[2])}, float(p.weight)};
    }
    if (film->has_splats())
      film->half_splats(h).assign(state.splats[h].begin(), state.splats[h].end());
  }
  film->set_half_counts(state.half_samples[0], state.half_samples[1]);
  film->set_splat_scale(state.samples() > 0 ? 1.f / float(state.samples()) : 1.f);
  return true;
}

bool write_render_state(const std::string& path, const RenderState& s, std::string* error) {
  std::string out;
  const size_t pixels = s.sums[0].size();
  out.reserve(kFixedBytes + s.config.size() + pixels * 2 * (32 + 24) + 8);
  out.append(kMagic, 8);
  put<uint32_t>(&out, kVersion);
  put<uint32_t>(&out, s.splats[0].empty() ? 0 : 1);
  put<uint64_t>(&out, s.archive_id);
  put<uint64_t>(&out, s.seed);
  put<int64_t>(&out, s.half_samples[0]);
  put<int64_t>(&out, s.half_samples[1]);
  put<int64_t>(&out, s.first);
  put<int64_t>(&out, s.end);
  put<int64_t>(&out, s.planned);
  put<double>(&out, s.scale);
  put<int32_t>(&out, s.full_resolution.x);
  put<int32_t>(&out, s.full_resolution.y);
  for (int32_t v : {s.cropped.min.x, s.cropped.min.y, s.cropped.max.x, s.cropped.max.y})
    put<int32_t>(&out, v);
  put<uint32_t>(&out, uint32_t(s.config.size()));
  out += s.config;
  for (int h = 0; h < 2; ++h)
    for (const FilmPixelSum& p : s.sums[h]) {
      for (double c : p.rgb) put<double>(&out, c);
      put<double>(&out, p.weight);
    }
  if (!s.splats[0].empty())
    for (int h = 0; h < 2; ++h)
      for (double v : s.splats[h]) put<double>(&out, v);
  put<uint64_t>(&out, pbrta::checksum64(out.data(), out.size()));
  return write_file_atomically(path, out, "render state", error);
}

bool read_render_state(const std::string& path, RenderState* s, std::string* error) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    *error = path + ": cannot open the render state";
    return false;
  }
  const std::string in((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  auto bad = [&](const std::string& why) {
    *error = path + ": not a usable render state: " + why;
    return false;
  };
  if (in.size() < kFixedBytes + 8 || std::memcmp(in.data(), kMagic, 8) != 0)
    return bad("no PBRTRST1 header (not a state file, or truncated)");
  size_t at = 8;
  const uint32_t version = get<uint32_t>(in, &at);
  if (version != kVersion)
    return bad("version " + std::to_string(version) + ", this build reads version 1");
  size_t check_at = in.size() - 8;
  if (get<uint64_t>(in, &check_at) != pbrta::checksum64(in.data(), in.size() - 8))
    return bad("checksum mismatch (truncated or damaged)");
  const uint32_t flags = get<uint32_t>(in, &at);
  s->archive_id = get<uint64_t>(in, &at);
  s->seed = get<uint64_t>(in, &at);
  s->half_samples[0] = get<int64_t>(in, &at);
  s->half_samples[1] = get<int64_t>(in, &at);
  s->first = get<int64_t>(in, &at);
  s->end = get<int64_t>(in, &at);
  s->planned = get<int64_t>(in, &at);
  s->scale = get<double>(in, &at);
  s->full_resolution.x = get<int32_t>(in, &at);
  s->full_resolution.y = get<int32_t>(in, &at);
  s->cropped.min.x = get<int32_t>(in, &at);
  s->cropped.min.y = get<int32_t>(in, &at);
  s->cropped.max.x = get<int32_t>(in, &at);
  s->cropped.max.y = get<int32_t>(in, &at);
  const uint32_t config_bytes = get<uint32_t>(in, &at);
  if (s->cropped.empty() || s->cropped.min.x < 0 || s->cropped.min.y < 0 ||
      s->cropped.max.x > s->full_resolution.x || s->cropped.max.y > s->full_resolution.y)
    return bad("its pixel bounds " + bounds_text(s->cropped) + " are not inside the film");
  const uint64_t pixels = uint64_t(s->cropped.area());
  if (pixels > in.size() / 64)  // 64 bytes of sums per pixel at least: no overflow below
    return bad("its pixel bounds " + bounds_text(s->cropped) + " need more bytes than it has");
  const uint64_t need =
      kFixedBytes + config_bytes + pixels * 2 * 32 + ((flags & 1) ? pixels * 2 * 24 : 0) + 8;
  if (need != in.size())
    return bad("it has " + std::to_string(in.size()) + " bytes, its header needs " +
               std::to_string(need));
  if (s->half_samples[0] < 0 || s->half_samples[1] < 0) return bad("negative sample counts");
  s->config.assign(in.data() + at, config_bytes);
  at += config_bytes;
  for (int h = 0; h < 2; ++h) {
    s->sums[h].resize(pixels);
    for (FilmPixelSum& p : s->sums[h]) {
      for (double& c : p.rgb) c = get<double>(in, &at);
      p.weight = get<double>(in, &at);
    }
  }
  for (int h = 0; h < 2; ++h) {
    s->splats[h].clear();
    if (flags & 1) {
      s->splats[h].resize(pixels * 3);
      for (double& v : s->splats[h]) v = get<double>(in, &at);
    }
  }
  return true;
}

bool merge_state(RenderState* into, const RenderState& from, const std::string& from_name,
                 std::string* error) {
  auto refuse = [&](const std::string& why) {
    *error = from_name + ": cannot merge: " + why;
    return false;
  };
  if (from.archive_id != into->archive_id) return refuse("it was rendered from another archive");
  if (!same_windows(from.full_resolution, from.cropped, into->full_resolution, into->cropped))
    return refuse("it has another resolution or crop (" + bounds_text(from.cropped) + " against " +
                  bounds_text(into->cropped) + ")");
  if (from.config != into->config)
    return refuse("it was rendered with other settings (\"" + from.config + "\" against \"" +
                  into->config + "\")");
  if (from.scale != into->scale) return refuse("its film has another scale");
  if (from.splats[0].empty() != into->splats[0].empty())
    return refuse("one state has light-tracing splats and the other not");
  const bool ranges_known = from.first >= 0 && into->first >= 0;
  const bool overlap = !ranges_known || (from.first < into->end && into->first < from.end);
  if (from.seed == into->seed && overlap)
    return refuse("it has the same seed (" + std::to_string(from.seed) +
                  ") and the same samples: merging would count them twice (render with --seed)");
  for (int h = 0; h < 2; ++h) {
    for (size_t i = 0; i < into->sums[h].size(); ++i) {
      for (int c = 0; c < 3; ++c) into->sums[h][i].rgb[c] += from.sums[h][i].rgb[c];
      into->sums[h][i].weight += from.sums[h][i].weight;
    }
    for (size_t i = 0; i < into->splats[h].size(); ++i) into->splats[h][i] += from.splats[h][i];
    into->half_samples[h] += from.half_samples[h];
  }
  // Same seed, ranges that join: still one render's samples, resumable from its end.
  if (from.seed == into->seed && ranges_known &&
      (from.first == into->end || from.end == into->first)) {
    into->first = std::min(into->first, from.first);
    into->end = std::max(into->end, from.end);
  } else {
    into->first = into->end = -1;
  }
  return true;
}

}  // namespace rt
