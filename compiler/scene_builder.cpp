#include "compiler/scene_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unordered_map>
#include <unordered_set>

#include <tbb/parallel_for.h>

#include <fstream>
#include <sstream>

#include "compiler/bsdf_file.h"
#include "compiler/bssrdf_table.h"
#include "compiler/entity_checks.h"
#include "compiler/mesh_builder.h"
#include "compiler/refine.h"
#include "compiler/scene_images.h"
#include "compiler/spectrum.h"

namespace pbrtc {

using pbrta::Category;

namespace {

// Copy-on-write name tables: attribute blocks share their parent's table until
// they define something, so deep nesting with many names stays cheap.
using SharedNames = std::shared_ptr<NameMap>;
NameMap& writable(SharedNames* m) {
  if (m->use_count() > 1) *m = std::make_shared<NameMap>(**m);
  return **m;
}

enum class BlockKind { kAttribute, kTransform, kObject };
const char* block_begin_name(BlockKind k) {
  return k == BlockKind::kAttribute   ? "AttributeBegin"
         : k == BlockKind::kTransform ? "TransformBegin"
                                      : "ObjectBegin";
}

struct GraphicsState {
  int32_t material = kNone;
  SharedNames named_materials = std::make_shared<NameMap>();
  SharedNames float_textures = std::make_shared<NameMap>();
  SharedNames spectrum_textures = std::make_shared<NameMap>();
  int32_t area_light = kNone;
  Loc area_light_loc;
  std::string inside_medium, outside_medium;
  Loc medium_loc;
  bool reverse_orientation = false;
};

void set_derived(Entity* e, std::string_view name, const float* f, size_t n) {
  Value& v = e->values[size_t(e->slot(name))];
  v.offset = uint32_t(e->floats.size());
  v.count = uint32_t(n);
  v.given = true;
  e->floats.insert(e->floats.end(), f, f + n);
}
void set_derived(Entity* e, std::string_view name, const int32_t* i, size_t n) {
  Value& v = e->values[size_t(e->slot(name))];
  v.offset = uint32_t(e->ints.size());
  v.count = uint32_t(n);
  v.given = true;
  e->ints.insert(e->ints.end(), i, i + n);
}

// The fourier material's table is read now, so the runtime opens no file: its arrays become
// the material's derived parameters (format/fourier_table.h). where: the file name's location.
bool derive_fourier_table(Entity* m, Loc where, Diagnostics* diag) {
  const std::string& path = m->get_string("bsdffile");
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  BsdfTable table;
  std::string err;
  if (!in) err = "cannot be read";
  if (!err.empty() || !read_bsdf_file(bytes.str(), &table, &err)) {
    diag->error(where, "bsdf file \"" + path + "\" " + err);
    return false;
  }
  set_derived(m, "bsdfeta", &table.eta, 1);
  set_derived(m, "bsdfmmax", &table.m_max, 1);
  set_derived(m, "bsdfchannels", &table.channels, 1);
  set_derived(m, "bsdfmu", table.mu.data(), table.mu.size());
  set_derived(m, "bsdfcdf", table.cdf.data(), table.cdf.size());
  set_derived(m, "bsdfoffsets", table.offsets.data(), table.offsets.size());
  set_derived(m, "bsdfcoeffs", table.coeffs.data(), table.coeffs.size());
  return true;
}

struct TransformPair {
  Matrix4 t[2];
};

struct Block {
  BlockKind kind;
  Loc loc;
  TransformPair transforms;
  bool active[2];
  GraphicsState graphics;  // saved only for attribute and object blocks
};

// A 64-bit hash of a transform pair's bits (splitmix-style mixing per word).
uint64_t hash_matrices(const Matrix4& a, const Matrix4& b) {
  uint64_t h = 0x9E3779B97F4A7C15ull;
  auto mix = [&h](double d) {
    uint64_t x;
    std::memcpy(&x, &d, 8);
    h ^= x + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  };
  for (double d : a.m) mix(d);
  for (double d : b.m) mix(d);
  return h;
}

}  // namespace

struct SceneBuilder::State {
  SceneDesc* scene;
  Diagnostics* diag;
  const SourceFiles* files;
  ParamResolver resolver;

  TransformPair cur;
  bool active[2] = {true, true};
  double times[2] = {0, 1};
  GraphicsState gs;
  std::vector<Block> stack;
  std::unordered_map<std::string, TransformPair> coord_systems;
  NameMap named_media;
  std::unordered_set<std::string> reported_media;  // undefined media already reported
  NameMap objects;
  int32_t current_object = kNone;
  // Transforms are deduplicated by hash; a colliding different pair simply
  // gets its own entry without being indexed (correct, merely not shared).
  std::unordered_map<uint64_t, int32_t> transform_index;

  struct PendingPly {
    std::string path;
    Loc loc;
    int32_t mesh;
  };
  std::vector<PendingPly> pending_ply;
  BuildProgress* progress = nullptr;

  // Reads every pending PLY file in parallel; errors and warnings are reported in scene
  // order afterwards, so messages do not depend on thread timing.
  void load_pending_ply() {
    if (progress && !pending_ply.empty()) progress->phase("PLY meshes", pending_ply.size());
    std::vector<std::vector<Diagnostic>> said(pending_ply.size());
    tbb::parallel_for(size_t(0), pending_ply.size(), [&](size_t i) {
      const PendingPly& p = pending_ply[i];
      SourceFiles none;
      Diagnostics local(&none, nullptr);
      if (!load_plymesh(p.path, Loc{}, &local, &scene->meshes[size_t(p.mesh)]) && !local.failed())
        local.error(Loc{}, "cannot read PLY file");
      said[i] = local.all();
    });
    for (size_t i = 0; i < pending_ply.size(); ++i)
      for (const Diagnostic& d : said[i]) {
        if (d.severity == Severity::kError)
          diag->error(pending_ply[i].loc, d.message);
        else
          diag->warning(pending_ply[i].loc, d.message);
      }
    pending_ply.clear();
  }

  bool in_world = false;
  bool world_ended = false;
  bool saw_world_begin = false;
  Loc camera_medium_loc;
  Loc first_medium_interface;  // the first MediumInterface naming a medium
  std::string camera_medium;
  bool film_given = false, filter_given = false, sampler_given = false, integrator_given = false,
       accel_given = false;

  State(SceneDesc* sc, Diagnostics* d, const SourceFiles* f, std::string base)
      : scene(sc), diag(d), files(f), resolver(d, std::move(base), &sc->input_files) {}

  TextureScope scope() const { return {gs.float_textures.get(), gs.spectrum_textures.get()}; }

  void apply(const Matrix4& m) {
    for (int i = 0; i < 2; ++i)
      if (active[i]) cur.t[i] = mul(cur.t[i], m);
  }

  bool options_only(Loc loc, const char* name) {
    if (world_ended) {
      diag->error(loc, std::string(name) + " after WorldEnd: pbrtc compiles one scene per file");
      return false;
    }
    if (in_world) {
      diag->error(loc, std::string(name) + " is only allowed before WorldBegin");
      return false;
    }
    return true;
  }
  bool world_only(Loc loc, const char* name) {
    if (world_ended) {
      diag->error(loc, std::string(name) + " after WorldEnd: pbrtc compiles one scene per file");
      return false;
    }
    if (!in_world) {
      diag->error(loc, std::string(name) + " is only allowed between WorldBegin and WorldEnd");
      return false;
    }
    return true;
  }
  bool anywhere(Loc loc, const char* name) {
    if (world_ended) {
      diag->error(loc, std::string(name) + " after WorldEnd: pbrtc compiles one scene per file");
      return false;
    }
    return true;
  }

  int32_t add_transform(const Matrix4& start, const Matrix4& end) {
    std::vector<AnimatedTransform>& all = scene->transforms;
    auto same = [&](int32_t i) {
      const AnimatedTransform& t = all[size_t(i)];
      return t.start == start && t.end == end && t.start_time == times[0] && t.end_time == times[1];
    };
    // Consecutive shapes very often share a transform.
    if (!all.empty() && same(int32_t(all.size() - 1))) return int32_t(all.size() - 1);
    uint64_t h = hash_matrices(start, end);
    auto it = transform_index.find(h);
    if (it != transform_index.end() && same(it->second)) return it->second;
    AnimatedTransform at;
    at.start = start;
    at.end = end;
    at.start_time = times[0];
    at.end_time = times[1];
    all.push_back(at);
    int32_t idx = int32_t(all.size() - 1);
    transform_index.emplace(h, idx);
    return idx;
  }

  int32_t lookup_medium(const std::string& name, Loc loc) {
    if (name.empty()) return kNone;
    auto it = named_media.find(name);
    if (it == named_media.end()) {
      // Once per name and MediumInterface, not once per shape and side.
      std::string key = name + '\0' + std::to_string(loc.file) + ':' + std::to_string(loc.offset);
      if (reported_media.insert(key).second)
        diag->error(loc, "undefined medium \"" + name + "\" (named in MediumInterface)");
      return kNone;
    }
    return it->second;
  }

  // A simple "Name type params" entity of the render options.
  void option_entity(Loc loc, const char* directive, Category c, std::string_view type,
                     const ParamList& params, Entity* e, bool* given) {
    if (!options_only(loc, directive)) return;
    Entity tmp;
    if (!resolver.begin(c, type, loc, &tmp)) return;
    resolver.assign_all(&tmp, params, {}, false);
    resolver.report_unused(params, &tmp);
    resolver.check_required(tmp, loc, &params);
    *e = std::move(tmp);
    *given = true;
  }

  void default_entity(Category c, const char* type, Entity* e) {
    resolver.begin(c, type, Loc{}, e);
  }

  // Materials.
  int32_t add_material(Loc loc, std::string_view type, const ParamList& params, std::string name) {
    MaterialDesc m;
    m.name = std::move(name);
    std::string_view t = type.empty() ? std::string_view("none") : type;
    if (!resolver.begin(Category::kMaterial, t, loc, &m.params)) {
      for (const ParsedParam& p : params.params) p.looked_up = true;
      return kNone;
    }
    resolver.assign_all(&m.params, params, scope(), false);
    if (m.params.type_name() == "mix") {
      for (int i = 0; i < 2; ++i) {
        const char* pname = i == 0 ? "namedmaterial1" : "namedmaterial2";
        const std::string& ref = m.params.get_string(pname);
        const ParsedParam* pp = params.find(pname);
        Loc where = pp ? pp->value_loc : loc;
        if (!m.params.given(pname)) continue;  // check_required reports it
        auto it = gs.named_materials->find(ref);
        if (it == gs.named_materials->end()) {
          diag->error(where, "undefined named material \"" + ref + "\" in mix material");
          continue;
        }
        if (it->second == kNone) continue;  // its definition failed, and said why
        m.mix[i] = it->second;
      }
    }
    resolver.report_unused(params, &m.params);
    resolver.check_required(m.params, loc, &params);
    if (m.params.type_name() == "fourier" && m.params.given("bsdffile")) {
      const ParsedParam* fp = params.find("bsdffile");
      derive_fourier_table(&m.params, fp ? fp->value_loc : loc, diag);
    }
    if (m.params.type_name() == "subsurface" || m.params.type_name() == "kdsubsurface") {
      const ParsedParam* np = params.find("name");
      derive_subsurface(&m.params, np ? np->value_loc : loc, diag);
    }
    scene->materials.push_back(std::move(m));
    return int32_t(scene->materials.size() - 1);
  }

  int32_t default_material() {
    // pbrt-v3's initial graphics state uses a default matte material.
    if (gs.material == kNone) {
      MaterialDesc m;
      resolver.begin(Category::kMaterial, "matte", Loc{}, &m.params);
      scene->materials.push_back(std::move(m));
      gs.material = int32_t(scene->materials.size() - 1);
    }
    return gs.material;
  }
};

SceneBuilder::SceneBuilder(SceneDesc* scene, Diagnostics* diag, const SourceFiles* files,
                           std::string base_dir, BuildProgress* progress)
    : s_(std::make_unique<State>(scene, diag, files, std::move(base_dir))) {
  s_->progress = progress;
}
SceneBuilder::~SceneBuilder() = default;

// ---- Transforms ----

void SceneBuilder::Identity(Loc loc) {
  if (!s_->anywhere(loc, "Identity")) return;
  for (int i = 0; i < 2; ++i)
    if (s_->active[i]) s_->cur.t[i] = Matrix4();
}

void SceneBuilder::Translate(Loc loc, double x, double y, double z) {
  if (!s_->anywhere(loc, "Translate")) return;
  s_->apply(translate(x, y, z));
}

void SceneBuilder::Scale(Loc loc, double x, double y, double z) {
  if (!s_->anywhere(loc, "Scale")) return;
  s_->apply(scale(x, y, z));
}

void SceneBuilder::Rotate(Loc loc, double angle, double x, double y, double z) {
  if (!s_->anywhere(loc, "Rotate")) return;
  if (x == 0 && y == 0 && z == 0) {
    s_->diag->error(loc, "Rotate axis (0, 0, 0) has no direction");
    return;
  }
  s_->apply(rotate(angle, x, y, z));
}

void SceneBuilder::LookAt(Loc loc, const std::array<double, 9>& v) {
  if (!s_->anywhere(loc, "LookAt")) return;
  Matrix4 m;
  if (!look_at(&v[0], &v[3], &v[6], &m)) {
    s_->diag->error(loc,
                    "degenerate LookAt: the eye and look points coincide, or the up vector "
                    "is parallel to the viewing direction");
    return;
  }
  s_->apply(m);
}

void SceneBuilder::ConcatTransform(Loc loc, const std::array<double, 16>& m) {
  if (!s_->anywhere(loc, "ConcatTransform")) return;
  s_->apply(from_pbrt_columns(m));
}

void SceneBuilder::Transform(Loc loc, const std::array<double, 16>& m) {
  if (!s_->anywhere(loc, "Transform")) return;
  Matrix4 t = from_pbrt_columns(m);
  for (int i = 0; i < 2; ++i)
    if (s_->active[i]) s_->cur.t[i] = t;
}

void SceneBuilder::CoordinateSystem(Loc loc, std::string_view name) {
  if (!s_->anywhere(loc, "CoordinateSystem")) return;
  s_->coord_systems[std::string(name)] = s_->cur;
}

void SceneBuilder::CoordSysTransform(Loc loc, std::string_view name) {
  if (!s_->anywhere(loc, "CoordSysTransform")) return;
  auto it = s_->coord_systems.find(std::string(name));
  if (it == s_->coord_systems.end()) {
    s_->diag->error(loc, "undefined coordinate system \"" + std::string(name) + "\"");
    return;
  }
  s_->cur = it->second;
}

void SceneBuilder::ActiveTransformDirective(Loc loc, ActiveTransform a) {
  if (!s_->anywhere(loc, "ActiveTransform")) return;
  s_->active[0] = a != ActiveTransform::kEnd;
  s_->active[1] = a != ActiveTransform::kStart;
}

void SceneBuilder::TransformTimes(Loc loc, double start, double end) {
  if (!s_->options_only(loc, "TransformTimes")) return;
  if (end < start) {
    s_->diag->error(loc, "TransformTimes end time is before its start time");
    return;
  }
  s_->times[0] = start;
  s_->times[1] = end;
}

// ---- Blocks ----

void SceneBuilder::AttributeBegin(Loc loc) {
  if (!s_->world_only(loc, "AttributeBegin")) return;
  s_->stack.push_back(
      {BlockKind::kAttribute, loc, s_->cur, {s_->active[0], s_->active[1]}, s_->gs});
}

void SceneBuilder::TransformBegin(Loc loc) {
  if (!s_->world_only(loc, "TransformBegin")) return;
  s_->stack.push_back({BlockKind::kTransform, loc, s_->cur, {s_->active[0], s_->active[1]}, {}});
}

namespace {
bool pop_block(std::vector<Block>* stack, BlockKind kind, const char* end_name, Loc loc,
               Diagnostics* diag, const SourceFiles* files, Block* out) {
  if (stack->empty()) {
    diag->error(loc, std::string(end_name) + " without a matching " + block_begin_name(kind));
    return false;
  }
  if (stack->back().kind != kind) {
    diag->error(loc, std::string(end_name) + " closes the " + block_begin_name(stack->back().kind) +
                         " at " + files->format(stack->back().loc));
    return false;
  }
  *out = std::move(stack->back());
  stack->pop_back();
  return true;
}
}  // namespace

void SceneBuilder::AttributeEnd(Loc loc) {
  if (!s_->world_only(loc, "AttributeEnd")) return;
  Block b;
  if (!pop_block(&s_->stack, BlockKind::kAttribute, "AttributeEnd", loc, s_->diag, s_->files, &b))
    return;
  s_->cur = b.transforms;
  s_->active[0] = b.active[0];
  s_->active[1] = b.active[1];
  s_->gs = std::move(b.graphics);
}

void SceneBuilder::TransformEnd(Loc loc) {
  if (!s_->world_only(loc, "TransformEnd")) return;
  Block b;
  if (!pop_block(&s_->stack, BlockKind::kTransform, "TransformEnd", loc, s_->diag, s_->files, &b))
    return;
  s_->cur = b.transforms;
  s_->active[0] = b.active[0];
  s_->active[1] = b.active[1];
}

void SceneBuilder::ObjectBegin(Loc loc, std::string_view name) {
  if (!s_->world_only(loc, "ObjectBegin")) return;
  if (s_->current_object != kNone) {
    s_->diag->error(loc, "ObjectBegin \"" + std::string(name) + "\" inside the definition of \"" +
                             s_->scene->objects[size_t(s_->current_object)].name +
                             "\": object definitions cannot nest");
    return;
  }
  std::string n(name);
  if (s_->objects.count(n)) {
    s_->diag->error(loc, "object \"" + n + "\" is already defined");
    return;
  }
  s_->stack.push_back({BlockKind::kObject, loc, s_->cur, {s_->active[0], s_->active[1]}, s_->gs});
  ObjectDesc o;
  o.name = n;
  o.loc = loc;
  s_->scene->objects.push_back(std::move(o));
  s_->current_object = int32_t(s_->scene->objects.size() - 1);
  s_->objects[n] = s_->current_object;
}

void SceneBuilder::ObjectEnd(Loc loc) {
  if (!s_->world_only(loc, "ObjectEnd")) return;
  Block b;
  if (!pop_block(&s_->stack, BlockKind::kObject, "ObjectEnd", loc, s_->diag, s_->files, &b)) return;
  s_->cur = b.transforms;
  s_->active[0] = b.active[0];
  s_->active[1] = b.active[1];
  s_->gs = std::move(b.graphics);
  s_->current_object = kNone;
}

void SceneBuilder::ObjectInstance(Loc loc, std::string_view name) {
  if (!s_->world_only(loc, "ObjectInstance")) return;
  if (s_->current_object != kNone) {
    s_->diag->error(loc,
                    "ObjectInstance inside an object definition (pbrt-v3 does not nest "
                    "instances)");
    return;
  }
  auto it = s_->objects.find(std::string(name));
  if (it == s_->objects.end()) {
    s_->diag->error(loc, "undefined object \"" + std::string(name) + "\"");
    return;
  }
  InstanceDesc inst;
  inst.object = it->second;
  inst.transform = s_->add_transform(s_->cur.t[0], s_->cur.t[1]);
  inst.loc = loc;
  if (is_projective(s_->cur.t[0]) || is_projective(s_->cur.t[1])) {
    s_->diag->error(loc, "ObjectInstance with a projective transform");
    return;
  }
  s_->scene->instances.push_back(inst);
}

// ---- Render options ----

void SceneBuilder::Camera(Loc loc, std::string_view type, const ParamList& params) {
  if (!s_->options_only(loc, "Camera")) return;
  CameraDesc cam;
  if (!s_->resolver.begin(Category::kCamera, type, loc, &cam.params)) return;
  s_->resolver.assign_all(&cam.params, params, {}, false);
  s_->resolver.report_unused(params, &cam.params);
  // pbrt-v2's "halffov" still works in pbrt-v3: a positive halffov replaces
  // fov (even one given too) with 2 * halffov; others are ignored.
  if (cam.params.given("halffov") && cam.params.get_float("halffov") > 0) {
    int slot = cam.params.slot("fov");
    if (slot >= 0) {
      Value& v = cam.params.values[size_t(slot)];
      v.offset = uint32_t(cam.params.floats.size());
      v.count = 1;
      v.given = true;
      cam.params.floats.push_back(2 * cam.params.get_float("halffov"));
    }
  }
  // The realistic camera's lens description is read now, so the runtime
  // opens no file: 4 numbers per element, as pbrt-v3 reads it.
  if (cam.params.type_name() == "realistic" && cam.params.given("lensfile")) {
    const std::string& path = cam.params.get_string("lensfile");
    const ParsedParam* lp = params.find("lensfile");
    Loc where = lp ? lp->value_loc : loc;
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    std::vector<float> lens;
    SpdError err;
    int line, col, last_line, last_col;
    if (!in || !parse_float_file(text.str(), &lens, &err, &line, &col, &last_line, &last_col)) {
      s_->diag->error(where, "lens file \"" + path + "\"" +
                                 (in ? ":" + std::to_string(err.line) + ":" +
                                           std::to_string(err.column) + ": " + err.message
                                     : ": cannot read it"));
      return;
    }
    if (lens.empty() || lens.size() % 4 != 0) {
      s_->diag->error(where, "lens file \"" + path + "\" has " + std::to_string(lens.size()) +
                                 " numbers; a lens needs 4 per element (radius, thickness, "
                                 "index of refraction, aperture)");
      return;
    }
    int slot = cam.params.slot("lensdata");
    Value& v = cam.params.values[size_t(slot)];
    v.offset = uint32_t(cam.params.floats.size());
    v.count = uint32_t(lens.size());
    v.given = true;
    cam.params.floats.insert(cam.params.floats.end(), lens.begin(), lens.end());
  }
  cam.camera_from_world.start = s_->cur.t[0];
  cam.camera_from_world.end = s_->cur.t[1];
  cam.camera_from_world.start_time = s_->times[0];
  cam.camera_from_world.end_time = s_->times[1];
  cam.given = true;
  TransformPair world_from_camera;
  for (int i = 0; i < 2; ++i) {
    if (!invert(s_->cur.t[i], &world_from_camera.t[i])) {
      s_->diag->error(loc, "the camera transform is singular (a Scale of 0?)");
      return;
    }
  }
  s_->coord_systems["camera"] = world_from_camera;
  s_->camera_medium = s_->gs.outside_medium;
  s_->camera_medium_loc = s_->gs.medium_loc;
  s_->scene->camera = std::move(cam);
}

void SceneBuilder::Film(Loc loc, std::string_view type, const ParamList& params) {
  s_->option_entity(loc, "Film", Category::kFilm, type, params, &s_->scene->film, &s_->film_given);
  if (!s_->film_given) return;
  for (const char* r : {"xresolution", "yresolution"}) {
    if (s_->scene->film.get_int(r) <= 0) {
      const ParsedParam* p = params.find(r);
      s_->diag->error(p ? p->value_loc : loc, std::string("film ") + r + " must be positive, got " +
                                                  std::to_string(s_->scene->film.get_int(r)));
    }
  }
  Entity& film = s_->scene->film;
  int slot = film.slot("cropwindow");
  if (slot >= 0 && film.values[size_t(slot)].given && film.values[size_t(slot)].count == 4) {
    float* crop = film.floats.data() + film.values[size_t(slot)].offset;
    const ParsedParam* p = params.find("cropwindow");
    Loc where = p ? p->value_loc : loc;
    // pbrt-v3 orders each pair and clamps it to [0, 1] without a word.
    auto clamp01 = [](float v) { return std::min(std::max(v, 0.0f), 1.0f); };
    float c[4] = {clamp01(std::min(crop[0], crop[1])), clamp01(std::max(crop[0], crop[1])),
                  clamp01(std::min(crop[2], crop[3])), clamp01(std::max(crop[2], crop[3]))};
    if (!std::equal(c, c + 4, crop)) {
      auto list = [](const float* v) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "[%g %g %g %g]", double(v[0]), double(v[1]), double(v[2]),
                      double(v[3]));
        return std::string(buf);
      };
      s_->diag->warning(where, "film cropwindow " + list(crop) + " is read as " + list(c) +
                                   " (pbrt-v3 orders each pair and clamps it to [0, 1])");
      std::copy(c, c + 4, crop);
    }
    if (c[0] >= c[1] || c[2] >= c[3])
      s_->diag->error(where, "film cropwindow [x0 x1 y0 y1] is empty (needs x0 < x1 and y0 < y1)");
  }
}

void SceneBuilder::PixelFilter(Loc loc, std::string_view type, const ParamList& params) {
  s_->option_entity(loc, "PixelFilter", Category::kFilter, type, params, &s_->scene->filter,
                    &s_->filter_given);
}

void SceneBuilder::Sampler(Loc loc, std::string_view type, const ParamList& params) {
  s_->option_entity(loc, "Sampler", Category::kSampler, type, params, &s_->scene->sampler,
                    &s_->sampler_given);
}

void SceneBuilder::Integrator(Loc loc, std::string_view type, const ParamList& params) {
  s_->option_entity(loc, "Integrator", Category::kIntegrator, type, params, &s_->scene->integrator,
                    &s_->integrator_given);
}

void SceneBuilder::Accelerator(Loc loc, std::string_view type, const ParamList& params) {
  s_->option_entity(loc, "Accelerator", Category::kAccelerator, type, params,
                    &s_->scene->accelerator, &s_->accel_given);
}

void SceneBuilder::MakeNamedMedium(Loc loc, std::string_view name, const ParamList& params) {
  if (!s_->anywhere(loc, "MakeNamedMedium")) return;
  const ParsedParam* tp = params.find("type");
  if (!tp || tp->type != ParamType::kString || tp->count != 1) {
    s_->diag->error(
        loc, "MakeNamedMedium \"" + std::string(name) + "\" needs a \"string type\" parameter");
    return;
  }
  tp->looked_up = true;
  MediumDesc m;
  m.name = std::string(name);
  if (!s_->resolver.begin(Category::kMedium, params.strings[tp->offset], tp->value_loc, &m.params))
    return;
  s_->resolver.assign_all(&m.params, params, {}, false);
  const bool ok = s_->resolver.check_required(m.params, loc, &params);
  s_->resolver.report_unused(params, &m.params);
  if (!ok || !check_medium(&m.params, params, loc, s_->diag) ||
      (m.params.type_name() == "heterogeneous" &&
       !check_heterogeneous_medium(m.params, params, loc, s_->diag)))
    return;
  m.world_from_medium = s_->cur.t[0];
  if (s_->named_media.count(m.name)) s_->diag->warning(loc, "medium \"" + m.name + "\" redefined");
  s_->scene->media.push_back(std::move(m));
  s_->named_media[std::string(name)] = int32_t(s_->scene->media.size() - 1);
}

void SceneBuilder::MediumInterface(Loc loc, std::string_view inside, std::string_view outside) {
  if (!s_->anywhere(loc, "MediumInterface")) return;
  s_->gs.inside_medium = std::string(inside);
  s_->gs.outside_medium = std::string(outside);
  s_->gs.medium_loc = loc;
  if (!s_->first_medium_interface.valid() && (!inside.empty() || !outside.empty()))
    s_->first_medium_interface = loc;
}

void SceneBuilder::WorldBegin(Loc loc) {
  if (s_->world_ended) {
    s_->diag->error(loc, "WorldBegin after WorldEnd: pbrtc compiles one scene per file");
    return;
  }
  if (s_->in_world) {
    s_->diag->error(loc, "WorldBegin inside the world block");
    return;
  }
  s_->in_world = true;
  s_->saw_world_begin = true;
  s_->cur = TransformPair();
  s_->active[0] = s_->active[1] = true;
  s_->coord_systems["world"] = s_->cur;
}

void SceneBuilder::WorldEnd(Loc loc) {
  if (!s_->world_only(loc, "WorldEnd")) return;
  // pbrt-v3 warns and closes them: the scene is complete, so this is no error.
  for (const Block& b : s_->stack)
    s_->diag->warning(b.loc, std::string(block_begin_name(b.kind)) +
                                 " is not closed before the "
                                 "WorldEnd at " +
                                 s_->files->format(loc));
  s_->stack.clear();
  s_->in_world = false;
  s_->world_ended = true;
}

void SceneBuilder::EndOfInput(Loc loc) {
  // An invalid loc: a lexical error cut the input short, and what it left
  // open is a consequence of that error.
  if (loc.valid()) {
    for (const Block& b : s_->stack)
      s_->diag->error(b.loc,
                      std::string(block_begin_name(b.kind)) + " is not closed at end of file");
    if (!s_->saw_world_begin)
      s_->diag->error(loc, "missing WorldBegin: the file describes no scene");
    else if (!s_->world_ended)
      s_->diag->error(loc, s_->resolver.saw_pbrt_v4_names()
                               ? "missing WorldEnd at end of input (pbrt-v4 scenes end without "
                                 "one; pbrt-v3 needs it)"
                               : "missing WorldEnd at end of input");
  }
  s_->stack.clear();
  s_->load_pending_ply();
  SceneDesc* sc = s_->scene;
  if (!s_->film_given) s_->default_entity(Category::kFilm, "image", &sc->film);
  if (!s_->filter_given) s_->default_entity(Category::kFilter, "box", &sc->filter);
  if (!s_->sampler_given) s_->default_entity(Category::kSampler, "halton", &sc->sampler);
  if (!s_->integrator_given) s_->default_entity(Category::kIntegrator, "path", &sc->integrator);
  if (!s_->accel_given) s_->default_entity(Category::kAccelerator, "bvh", &sc->accelerator);
  if (!sc->camera.given) s_->default_entity(Category::kCamera, "perspective", &sc->camera.params);
  // pbrt-v3 warns about media the integrator cannot simulate (and ignores them).
  std::string_view integrator = sc->integrator.type_name();
  if (loc.valid() && s_->first_medium_interface.valid() && integrator != "volpath" &&
      integrator != "bdpt" && integrator != "mlt")
    s_->diag->warning(s_->integrator_given ? sc->integrator.loc : s_->first_medium_interface,
                      "the scene has participating media, but the " + std::string(integrator) +
                          " integrator ignores them (pbrt-v3 simulates media only with volpath, "
                          "bdpt and mlt)");
  // pbrt-v3 looks the camera's medium up when it builds the camera, after the
  // whole scene is read.
  sc->camera.medium = s_->lookup_medium(s_->camera_medium, s_->camera_medium_loc);
  // Effects the scene calls for.
  Effects& fx = sc->effects;
  fx.instancing = !sc->instances.empty();
  fx.media = sc->camera.medium != kNone;
  fx.motion_blur = sc->camera.camera_from_world.animated();
  for (const LightDesc& l : sc->lights) {
    if (l.params.type_name() == "infinite") fx.infinite_lights = true;
    if (l.medium != kNone) fx.media = true;
  }
  std::vector<bool> material_used(sc->materials.size(), false);
  for (const ShapeDesc& s : sc->shapes) {
    if (s.area_light != kNone) fx.area_lights = true;
    if (s.inside_medium != kNone || s.outside_medium != kNone) fx.media = true;
    if (sc->transforms[size_t(s.transform)].animated()) fx.motion_blur = true;
    if (s.params.get_texture("alpha") != kNone || s.params.given("alpha") ||
        s.params.get_texture("shadowalpha") != kNone || s.params.given("shadowalpha"))
      fx.alpha = true;
    if (s.material != kNone) material_used[size_t(s.material)] = true;
  }
  for (const InstanceDesc& i : sc->instances)
    if (sc->transforms[size_t(i.transform)].animated()) fx.motion_blur = true;
  // Mixes use their two materials.
  for (size_t i = sc->materials.size(); i-- > 0;)
    if (material_used[i])
      for (int32_t m : sc->materials[i].mix)
        if (m != kNone) material_used[size_t(m)] = true;
  for (size_t i = 0; i < sc->materials.size(); ++i) {
    if (!material_used[i]) continue;
    const Entity& m = sc->materials[i].params;
    if (m.type_name() == "subsurface" || m.type_name() == "kdsubsurface") fx.subsurface = true;
    if (m.type_name() == "disney" && !m.get_bool("thin")) {
      // A solid disney material scatters under its surface where it has a scatter distance.
      const Value& sd = m.values[size_t(m.slot("scatterdistance"))];
      const float* d = m.get_floats("scatterdistance");
      if (sd.texture != kNone || d[0] > 0 || d[1] > 0 || d[2] > 0) fx.subsurface = true;
    }
    for (const Value& v : m.values)
      if (v.texture != kNone) fx.textures = true;
  }
  for (const ShapeDesc& s : sc->shapes)
    for (const Value& v : s.params.values)
      if (v.texture != kNone) fx.textures = true;
}

// ---- Materials and textures ----

void SceneBuilder::Material(Loc loc, std::string_view type, const ParamList& params) {
  if (!s_->world_only(loc, "Material")) return;
  int32_t m = s_->add_material(loc, type, params, "");
  if (m != kNone) s_->gs.material = m;
}

void SceneBuilder::MakeNamedMaterial(Loc loc, std::string_view name, const ParamList& params) {
  if (!s_->world_only(loc, "MakeNamedMaterial")) return;
  const ParsedParam* tp = params.find("type");
  if (!tp || tp->type != ParamType::kString || tp->count != 1) {
    s_->diag->error(
        loc, "MakeNamedMaterial \"" + std::string(name) + "\" needs a \"string type\" parameter");
    for (const ParsedParam& p : params.params) p.looked_up = true;
    return;
  }
  tp->looked_up = true;
  std::string n(name);
  int32_t m = s_->add_material(tp->value_loc, params.strings[tp->offset], params, n);
  NameMap& names = writable(&s_->gs.named_materials);
  if (m == kNone) {
    // Defined, though in error (reported): its uses are not "undefined" errors on top of it.
    names[n] = kNone;
    return;
  }
  s_->scene->materials[size_t(m)].params.loc = loc;
  if (names.count(n)) s_->diag->warning(loc, "named material \"" + n + "\" redefined");
  names[n] = m;
}

void SceneBuilder::NamedMaterial(Loc loc, std::string_view name) {
  if (!s_->world_only(loc, "NamedMaterial")) return;
  auto it = s_->gs.named_materials->find(std::string(name));
  if (it == s_->gs.named_materials->end()) {
    s_->diag->error(loc, "undefined named material \"" + std::string(name) + "\"");
    return;
  }
  if (it->second == kNone) return;  // its definition failed, and said why
  s_->gs.material = it->second;
}

void SceneBuilder::Texture(Loc loc, std::string_view name, std::string_view klass,
                           std::string_view type, const ParamList& params) {
  if (!s_->world_only(loc, "Texture")) return;
  Category c;
  if (klass == "float") {
    c = Category::kFloatTexture;
  } else if (klass == "spectrum" || klass == "color") {
    c = Category::kSpectrumTexture;
  } else {
    s_->diag->error(loc, "unknown texture class \"" + std::string(klass) +
                             "\" (pbrt-v3 has \"float\" and \"spectrum\")");
    return;
  }
  TextureDesc t;
  t.name = std::string(name);
  SharedNames* map =
      c == Category::kFloatTexture ? &s_->gs.float_textures : &s_->gs.spectrum_textures;
  if (!s_->resolver.begin(c, type, loc, &t.params)) {
    // Defined, though in error (reported): its uses are not "undefined" errors on top of it.
    writable(map)[t.name] = kNone;
    return;
  }
  s_->resolver.assign_all(&t.params, params, s_->scope(), false);
  s_->resolver.report_unused(params, &t.params);
  if (!s_->resolver.check_required(t.params, loc, &params)) {
    writable(map)[t.name] = kNone;
    return;
  }
  t.world_from_texture = s_->cur.t[0];
  s_->scene->textures.push_back(std::move(t));
  int32_t idx = int32_t(s_->scene->textures.size() - 1);
  NameMap& names = writable(map);
  if (names.count(std::string(name)))
    s_->diag->warning(loc, std::string(klass == "float" ? "float" : "spectrum") + " texture \"" +
                               std::string(name) + "\" redefined");
  names[std::string(name)] = idx;
}

// ---- Lights ----

void SceneBuilder::LightSource(Loc loc, std::string_view type, const ParamList& params) {
  if (!s_->world_only(loc, "LightSource")) return;
  LightDesc l;
  if (!s_->resolver.begin(Category::kLight, type, loc, &l.params)) return;
  s_->resolver.assign_all(&l.params, params, {}, false);
  s_->resolver.report_unused(params, &l.params);
  if (!s_->resolver.check_required(l.params, loc, &params)) return;
  l.world_from_light = s_->cur.t[0];
  if (s_->cur.t[0] != s_->cur.t[1])
    s_->diag->warning(loc,
                      "lights do not move: the light uses its start transform (as pbrt-v3 "
                      "does)");
  // pbrt-v3 makes a light with the outside medium of the current MediumInterface and
  // starts its emitted rays there.
  l.medium = s_->lookup_medium(s_->gs.outside_medium, s_->gs.medium_loc);
  s_->scene->lights.push_back(std::move(l));
}

void SceneBuilder::AreaLightSource(Loc loc, std::string_view type, const ParamList& params) {
  if (!s_->world_only(loc, "AreaLightSource")) return;
  Entity e;
  if (!s_->resolver.begin(Category::kAreaLight, type, loc, &e)) return;
  s_->resolver.assign_all(&e, params, {}, false);
  s_->resolver.report_unused(params, &e);
  s_->scene->area_lights.push_back(std::move(e));
  s_->gs.area_light = int32_t(s_->scene->area_lights.size() - 1);
  s_->gs.area_light_loc = loc;
}

void SceneBuilder::ReverseOrientation(Loc loc) {
  if (!s_->world_only(loc, "ReverseOrientation")) return;
  s_->gs.reverse_orientation = !s_->gs.reverse_orientation;
}

// ---- Shapes ----

void SceneBuilder::Shape(Loc loc, std::string_view type, const ParamList& params) {
  if (!s_->world_only(loc, "Shape")) return;
  ShapeDesc sh;
  if (!s_->resolver.begin(Category::kShape, type, loc, &sh.params)) {
    for (const ParsedParam& p : params.params) p.looked_up = true;
    return;
  }
  std::string_view tn = sh.params.type_name();
  bool is_mesh = tn == "trianglemesh" || tn == "plymesh";
  s_->resolver.assign_all(&sh.params, params, s_->scope(), is_mesh);
  if (tn == "trianglemesh" && !params.find("indices")) {
    // pbrt-v3: a mesh of exactly 3 vertices may leave out its indices.
    const ParsedParam* P = params.find("P");
    if (P && P->type == ParamType::kPoint3 && P->count == 9)
      sh.params.values[size_t(sh.params.slot("indices"))].given = true;
  }
  bool ok = s_->resolver.check_required(sh.params, loc, &params);

  // Per-shape material overrides: parameters the shape does not know but the
  // current material does make a new material for this shape.
  int32_t material = s_->default_material();
  {
    // The schema entry is static; a reference into materials would dangle
    // once the override is appended.
    const pbrta::TypeSpec& material_spec = s_->scene->materials[size_t(material)].params.spec();
    MaterialDesc* over = nullptr;
    for (const ParsedParam& p : params.params) {
      if (p.looked_up) continue;
      int slot = pbrta::find_param(material_spec, p.name);
      // Derived parameters come from the material's file, never from scene text.
      if (slot < 0 || (material_spec.params[slot].flags & pbrta::kParamDerived)) continue;
      if (!over) {
        s_->scene->materials.push_back(s_->scene->materials[size_t(material)]);
        over = &s_->scene->materials.back();
        over->name.clear();
        over->params.loc = loc;
      }
      if (s_->resolver.assign(&over->params, slot, p, params, s_->scope()) &&
          material_spec.name == "fourier" && p.name == "bsdffile")
        derive_fourier_table(&over->params, p.value_loc, s_->diag);
    }
    // A shape's own g or eta makes a new profile (pbrt-v3 makes a new material for it).
    if (over && (material_spec.name == "subsurface" || material_spec.name == "kdsubsurface"))
      derive_subsurface(&over->params, loc, s_->diag);
    if (over) material = int32_t(s_->scene->materials.size() - 1);
  }
  s_->resolver.report_unused(params, &sh.params);
  if (!ok || (tn == "curve" && !check_curve(sh.params, params, loc, s_->diag))) return;

  if (tn == "trianglemesh") {
    TriangleMesh mesh;
    if (!build_trianglemesh(params, loc, s_->diag, &mesh)) return;
    s_->scene->meshes.push_back(std::move(mesh));
    sh.mesh = int32_t(s_->scene->meshes.size() - 1);
  } else if (tn == "plymesh") {
    // PLY files are read after the whole scene is parsed, in parallel.
    const ParsedParam* fp = params.find("filename");
    s_->scene->meshes.emplace_back();
    sh.mesh = int32_t(s_->scene->meshes.size() - 1);
    s_->pending_ply.push_back(
        {sh.params.get_string("filename"), fp ? fp->value_loc : loc, sh.mesh});
  } else if (is_refined_shape(tn)) {
    // pbrt-v3 refines these into triangles when it builds the scene; the archive holds the
    // triangles instead.
    TriangleMesh mesh;
    std::string error;
    if (!refine_shape(sh.params, &mesh, &error)) {
      s_->diag->error(loc, error);
      return;
    }
    s_->scene->meshes.push_back(std::move(mesh));
    sh.mesh = int32_t(s_->scene->meshes.size() - 1);
  }

  sh.material = material;
  sh.transform = s_->add_transform(s_->cur.t[0], s_->cur.t[1]);
  sh.reverse_orientation = s_->gs.reverse_orientation;
  sh.transform_swaps_handedness = swaps_handedness(s_->cur.t[0]);
  sh.inside_medium = s_->lookup_medium(s_->gs.inside_medium, s_->gs.medium_loc);
  sh.outside_medium = s_->lookup_medium(s_->gs.outside_medium, s_->gs.medium_loc);
  sh.object = s_->current_object;
  if (s_->gs.area_light != kNone) {
    if (s_->current_object != kNone) {
      s_->diag->warning(loc,
                        "area lights are not supported inside object instances (ignored, "
                        "as pbrt-v3 does)");
    } else if (s_->cur.t[0] != s_->cur.t[1]) {
      s_->diag->warning(loc,
                        "area lights are not supported on shapes with animated transforms "
                        "(ignored, as pbrt-v3 does)");
    } else {
      sh.area_light = s_->gs.area_light;
    }
  }
  s_->scene->shapes.push_back(std::move(sh));
  if (s_->progress) s_->progress->shapes(*s_->scene);
  if (s_->current_object != kNone)
    s_->scene->objects[size_t(s_->current_object)].shapes.push_back(
        int32_t(s_->scene->shapes.size() - 1));
}

// ---- Entry points ----

bool build_scene(const std::string& path, SourceFiles* files, Diagnostics* diag, SceneDesc* scene,
                 BuildProgress* progress) {
  int before = diag->error_count();
  SceneBuilder builder(scene, diag, files, path == "-" ? "" : directory_of(path), progress);
  parse_file(path, files, diag, &builder);
  for (size_t i = 0; i < files->size(); ++i)
    scene->input_files.push_back(files->display_path(uint32_t(i)));
  // Images only once the scene is sound: decoding is the slow part of a compile.
  if (diag->error_count() == before) {
    decode_scene_images(scene, diag, progress);
  }
  return diag->error_count() == before;
}

bool build_scene_from_string(const std::string& display_path, std::string text,
                             const std::string& base_dir, SourceFiles* files, Diagnostics* diag,
                             SceneDesc* scene) {
  int before = diag->error_count();
  SceneBuilder builder(scene, diag, files, base_dir);
  size_t first_file = files->size();
  parse_string(display_path, std::move(text), base_dir, files, diag, &builder);
  // The text itself is no file, but what it Included is.
  for (size_t i = first_file + 1; i < files->size(); ++i)
    scene->input_files.push_back(files->display_path(uint32_t(i)));
  if (diag->error_count() == before) decode_scene_images(scene, diag);
  return diag->error_count() == before;
}

}  // namespace pbrtc
