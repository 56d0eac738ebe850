#include "compiler/scene_images.h"

#include <tbb/parallel_for.h>

#include <cstdio>
#include <unordered_map>

#include "compiler/scene_builder.h"

namespace pbrtc {

namespace {

struct Job {
  std::string path;
  ImageOptions options;
  bool environment = false;
  float L[3] = {1, 1, 1};  // environment: the light's L times scale, for the distribution
  int32_t image = kNone;   // first index in SceneDesc::images (the distribution follows)
  std::vector<Loc> users;  // where to report a failure
  DecodedImage decoded, distribution;
  std::string error;
};

// Everything that changes the decoded texels, exactly (floats by their bits).
std::string job_key(const Job& j) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "|%u|%d%d|%a|%u|%d|%d|%a|%a|%a", j.options.channels,
                int(j.options.gamma), int(j.options.gamma_if_integer), double(j.options.scale),
                uint32_t(j.options.wrap), int(j.options.flip), int(j.environment), double(j.L[0]),
                double(j.L[1]), double(j.L[2]));
  return j.path + buf;
}

// Sets a float or bool parameter to one value, marked given.
void set_given(Entity* e, std::string_view param, float f, int32_t i) {
  const int slot = e->slot(param);
  if (slot < 0) return;
  Value& v = e->values[size_t(slot)];
  const bool is_float =
      pbrta::kind_store(e->spec().params[size_t(slot)].kind) == pbrta::KindStore::kFloat;
  if (v.count == 0) {
    v.offset = uint32_t(is_float ? e->floats.size() : e->ints.size());
    if (is_float) {
      e->floats.push_back(f);
    } else {
      e->ints.push_back(i);
    }
  } else if (is_float) {
    e->floats[v.offset] = f;
  } else {
    e->ints[v.offset] = i;
  }
  v.count = 1;
  v.given = true;
}

}  // namespace

bool decode_scene_images(SceneDesc* scene, Diagnostics* diag, BuildProgress* progress) {
  std::vector<Job> jobs;
  std::unordered_map<std::string, size_t> job_of;
  int32_t next_image = int32_t(scene->images.size());
  // Returns the image index for the job, adding it if new.
  auto use = [&](Job j, Loc loc) -> int32_t {
    std::string key = job_key(j);
    auto it = job_of.find(key);
    if (it == job_of.end()) {
      j.image = next_image;
      next_image += j.environment ? 2 : 1;
      it = job_of.emplace(std::move(key), jobs.size()).first;
      jobs.push_back(std::move(j));
    }
    jobs[it->second].users.push_back(loc);
    return jobs[it->second].image;
  };

  for (TextureDesc& t : scene->textures) {
    const Entity& e = t.params;
    if (e.type_name() != "imagemap") continue;
    Job j;
    j.path = e.get_string("filename");
    j.options = ImageOptions::for_texture(j.path, e.category == pbrta::Category::kFloatTexture,
                                          e.get_string("wrap"), e.get_float("scale"),
                                          e.given("gamma"), e.get_bool("gamma"));
    t.image = use(std::move(j), e.loc);
    // Image parameters describe the stored texels: the curve and the scale are in them now, so
    // the entity says "no curve, scale 1". A texture compiled from pbrtc --dump's image file
    // (which holds these texels) then stores the same entity as the original.
    set_given(&t.params, "gamma", 0.f, 0);
    set_given(&t.params, "scale", 1.f, 0);
  }
  for (LightDesc& l : scene->lights) {
    const Entity& e = l.params;
    std::string_view type = e.type_name();
    if (type != "infinite" && type != "projection" && type != "goniometric") continue;
    Job j;
    j.path = e.get_string("mapname");
    if (j.path.empty()) continue;  // no map: pbrt-v3 uses L (or 1) alone
    if (type == "infinite") {
      // pbrt-v3 multiplies L * scale into the map before it builds the distribution.
      j.environment = true;
      const float* L = e.get_floats("L");
      const float* scale = e.get_floats("scale");
      for (int k = 0; k < 3; ++k) j.L[k] = (L ? L[k] : 1.f) * (scale ? scale[k] : 1.f);
    }
    l.image = use(std::move(j), e.loc);
  }
  if (jobs.empty()) return true;
  if (progress) progress->phase("images", jobs.size());

  tbb::parallel_for(size_t(0), jobs.size(), [&](size_t i) {
    Job& j = jobs[i];
    if (decode_image(j.path, j.options, &j.decoded, &j.error) && j.environment)
      j.distribution = environment_distribution(j.decoded, j.L);
  });

  bool ok = true;
  // Resampled maps keep their decoded texels too, as one-level images after all the others (in
  // first-use order, so the output does not depend on the thread count).
  int32_t next_source = next_image;
  for (const Job& j : jobs)
    if (j.error.empty() && !j.decoded.source.empty()) ++next_image;
  scene->images.resize(size_t(next_image));
  for (Job& j : jobs) {
    if (!j.error.empty()) {
      for (Loc loc : j.users) diag->error(loc, "cannot read image \"" + j.path + "\": " + j.error);
      ok = false;
      continue;
    }
    ImageDesc& im = scene->images[size_t(j.image)];
    im.source = j.path;
    if (!j.decoded.source.empty()) {
      ImageDesc& src = scene->images[size_t(next_source)];
      im.source_image = next_source++;
      src.source = j.path;
      src.image.width = src.image.source_width = j.decoded.source_width;
      src.image.height = src.image.source_height = j.decoded.source_height;
      src.image.channels = j.decoded.channels;
      src.image.wrap = j.decoded.wrap;
      src.image.levels.push_back(std::move(j.decoded.source));
      j.decoded.source = {};
    }
    im.image = std::move(j.decoded);
    if (j.environment) {
      im.distribution = j.image + 1;
      ImageDesc& d = scene->images[size_t(j.image + 1)];
      d.source = j.path;
      d.image = std::move(j.distribution);
    }
  }
  return ok;
}

}  // namespace pbrtc
