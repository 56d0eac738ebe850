#include "compiler/archive_builder.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <unordered_map>
#include <utility>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "compiler/refine.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "format/draco_codec.h"
#include "format/progress_count.h"
#include "format/texel_format.h"
#include "format/zstd_frames.h"

namespace pbrtc {

namespace {

using pbrta::kNoIndex;

uint32_t idx(int32_t i) {
  return i < 0 ? kNoIndex : uint32_t(i);
}

template <class T>
void append(std::vector<uint8_t>* out, const T& v) {
  size_t n = out->size();
  out->resize(n + sizeof(T));
  std::memcpy(out->data() + n, &v, sizeof(T));
}

// A mesh stored with Draco: its stream, the geometry section it decodes to, and its record.
struct DracoMesh {
  bool tried = false, used = false;
  std::vector<uint8_t> stored, raw;
  pbrta::MeshRecord record{};
  DracoMeshStats stats;
};

bool draco_eligible(const TriangleMesh& m, const ArchiveOptions& opt) {
  if (opt.draco_bits <= 0 || !opt.compress || !m.S.empty() ||
      m.num_triangles() < opt.draco_min_triangles)
    return false;
  for (size_t v = 0; v < m.N.size(); v += 3)
    if (m.N[v] == 0 && m.N[v + 1] == 0 && m.N[v + 2] == 0) return false;
  return true;
}

// Encodes the mesh, then decodes the stream exactly as the archive reader will, so the section's
// raw layout and the record match what a reader gets. False (the mesh stays lossless) if Draco
// fails, if it dropped triangles (edgebreaker drops degenerate ones, which would change, say,
// how many lights an area-light mesh is) or if the result exceeds the reader's size bounds.
bool draco_compress(const TriangleMesh& m, uint32_t index, const ArchiveOptions& opt,
                    DracoMesh* out) {
  using clock = std::chrono::steady_clock;
  const pbrta::MeshArrays in = arrays_of(m);
  pbrta::DracoOptions o;
  o.position_bits = opt.draco_bits;
  o.sequential = opt.draco_sequential;
  std::string error;
  const auto t0 = clock::now();
  if (!pbrta::draco_encode(in, o, &out->stored, &error)) return false;
  const auto t1 = clock::now();
  pbrta::DecodedMesh decoded;
  if (!pbrta::draco_decode(out->stored.data(), out->stored.size(), &decoded, &error) ||
      decoded.num_triangles() != in.num_triangles)
    return false;
  pbrta::draco_geometry_section(decoded, &out->record, &out->raw);
  const auto t2 = clock::now();
  if (!pbrta::section_sizes_plausible(pbrta::Codec::kDraco, out->stored.size(), out->raw.size()))
    return false;
  DracoMeshStats& st = out->stats;
  st.mesh = index;
  st.triangles = decoded.num_triangles();
  st.stored_bytes = out->stored.size();
  st.raw_bytes = out->raw.size();
  st.bound = pbrta::draco_position_bound(in.positions, in.num_vertices, o.position_bits);
  st.slack = pbrta::draco_position_slack(in.positions, in.num_vertices);
  st.displacement = pbrta::draco_max_displacement(
      in, decoded.view(), st.bound, o.sequential && decoded.num_vertices() == in.num_vertices);
  st.encode_seconds = std::chrono::duration<double>(t1 - t0).count();
  st.decode_seconds = std::chrono::duration<double>(t2 - t1).count();
  out->used = true;
  return true;
}

// Which images are environment-map sampling distributions: they are pdfs, kept f32 whatever
// --texture-precision says.
std::vector<bool> distribution_images(const SceneDesc& scene) {
  std::vector<bool> out(scene.images.size(), false);
  for (const ImageDesc& d : scene.images)
    if (d.distribution >= 0 && size_t(d.distribution) < out.size())
      out[size_t(d.distribution)] = true;
  return out;
}

// One level's texels to format's bytes; large levels in parallel on up to threads threads
// (0: all; the bytes do not depend on how the work is split).
void encode_level(uint32_t format, const float* in, size_t count, uint8_t* out, int threads) {
  const size_t grain = size_t(1) << 16;
  if (format == uint32_t(pbrta::PixelFormat::kFloat32) || count < 4 * grain || threads == 1) {
    pbrta::encode_texels(format, in, count, out);
    return;
  }
  const size_t bytes_per = pbrta::texel_bytes(format);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, count, grain), [&](const tbb::blocked_range<size_t>& r) {
          pbrta::encode_texels(format, in + r.begin(), r.size(), out + r.begin() * bytes_per);
        });
  });
}

// Refuses, before anything is written, an image that --texture-precision's format cannot hold,
// naming it, its file and the first texel that does not fit.
bool check_texture_format(const SceneDesc& scene, pbrta::PixelFormat format, std::string* error) {
  if (format == pbrta::PixelFormat::kFloat32) return true;
  const std::vector<bool> is_distribution = distribution_images(scene);
  for (size_t i = 0; i < scene.images.size(); ++i) {
    if (is_distribution[i]) continue;
    const DecodedImage& im = scene.images[i].image;
    const std::vector<float>* arrays[33];
    size_t n = 0;
    for (const std::vector<float>& level : im.levels)
      if (n < 32) arrays[n++] = &level;
    arrays[n++] = &im.source;
    for (size_t a = 0; a < n; ++a) {
      const std::vector<float>& v = *arrays[a];
      for (size_t k = 0; k < v.size(); ++k) {
        if (pbrta::texel_representable(uint32_t(format), v[k])) continue;
        const bool half = format == pbrta::PixelFormat::kHalf16;
        char value[32];
        std::snprintf(value, sizeof value, "%.9g", double(v[k]));
        *error = "--texture-precision " + std::string(pbrta::texel_format_name(uint32_t(format))) +
                 ": image " + std::to_string(i) + " ('" + scene.images[i].source + "') holds " +
                 value + (a + 1 == n ? " before resampling" : " in level " + std::to_string(a)) +
                 ", which " +
                 (half ? "is beyond half precision's range (65504)"
                       : "unorm8 (linear [0, 1]) cannot hold: HDR data or an imagemap scale "
                         "above 1") +
                 "; use --texture-precision " + (half ? "f32" : "f16 or f32");
        return false;
      }
    }
  }
  return true;
}

template <class T>
std::vector<uint8_t> bytes_of(const std::vector<T>& v) {
  std::vector<uint8_t> out(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(out.data(), v.data(), out.size());
  return out;
}

class Builder {
 public:
  Builder(const SceneDesc& scene, const SourceFiles& files, const std::string& base_dir)
      : scene_(scene), files_(files), base_dir_(base_dir) {
    string("");   // string 0 is the empty string
    pstring("");  // in both tables
  }

  // Paths are stored relative to the top-level scene's directory.
  std::string relative(const std::string& path) const {
    if (base_dir_.empty()) return path;
    std::string prefix = base_dir_.back() == '/' ? base_dir_ : base_dir_ + "/";
    if (path.compare(0, prefix.size(), prefix) == 0) return path.substr(prefix.size());
    return path;
  }

  uint32_t string(const std::string& s) {
    auto it = string_index_.find(s);
    if (it != string_index_.end()) return it->second;
    uint32_t i = uint32_t(strings_.size());
    strings_.push_back(s);
    string_index_.emplace(s, i);
    return i;
  }

  uint32_t transform(const AnimatedTransform& t) {
    pbrta::TransformRecord r;
    std::memcpy(r.start, t.start.m.data(), sizeof r.start);
    std::memcpy(r.end, t.end.m.data(), sizeof r.end);
    r.start_time = t.start_time;
    r.end_time = t.end_time;
    std::string key(reinterpret_cast<const char*>(&r), sizeof r);
    auto it = transform_index_.find(key);
    if (it != transform_index_.end()) return it->second;
    uint32_t i = uint32_t(transforms_.size());
    transforms_.push_back(r);
    transform_index_.emplace(std::move(key), i);
    return i;
  }
  uint32_t transform(const Matrix4& m) {
    AnimatedTransform t;
    t.start = t.end = m;
    return transform(t);
  }

  // Provenance strings live in their own table inside the provenance section.
  uint32_t pstring(const std::string& s) {
    auto it = pstring_index_.find(s);
    if (it != pstring_index_.end()) return it->second;
    uint32_t i = uint32_t(pstrings_.size());
    pstrings_.push_back(s);
    pstring_index_.emplace(s, i);
    return i;
  }

  void provenance(Loc loc, const std::string& name = "", const std::string& path = "") {
    pbrta::ProvenanceRecord p{0, 0, pstring(name), pstring(path)};
    if (loc.valid()) {
      p.file = pstring(relative(files_.display_path(loc.file)));
      p.line = files_.line_col(loc).line;
    }
    provenance_.push_back(p);
  }

  // Strings that only say where data came from (file names) or that were
  // resolved to indices (a mix's material names) are kept as provenance and
  // stored as string 0, so the archive's meaning does not depend on names.
  uint32_t entity(const Entity& e, const std::string& name = "") {
    std::string path;
    pbrta::EntityRecord r{};
    r.category = uint8_t(e.category);
    r.type = uint16_t(e.type);
    r.first_value = uint32_t(values_.size());
    r.num_values = uint32_t(e.values.size());
    const pbrta::TypeSpec& ts = e.spec();
    for (size_t i = 0; i < e.values.size(); ++i) {
      const Value& v = e.values[i];
      pbrta::Kind k = ts.params[i].kind;
      pbrta::ValueRecord out{};
      out.offset = uint32_t(words_.size());
      out.count = v.count;
      out.texture = idx(v.texture);
      out.flags = v.given ? uint32_t(pbrta::kValueGiven) : 0u;
      switch (pbrta::kind_store(k)) {
        case pbrta::KindStore::kInt:
          for (uint32_t j = 0; j < v.count; ++j) words_.push_back(uint32_t(e.ints[v.offset + j]));
          break;
        case pbrta::KindStore::kString:
          for (uint32_t j = 0; j < v.count; ++j) {
            const std::string& s = e.strings[v.offset + j];
            bool is_path = ts.params[i].flags & pbrta::kParamFilename;
            bool resolved_name = e.category == pbrta::Category::kMaterial && ts.name == "mix" &&
                                 ts.params[i].name.substr(0, 13) == "namedmaterial";
            if (is_path && path.empty()) path = relative(s);
            words_.push_back(is_path || resolved_name ? 0 : string(s));
          }
          break;
        case pbrta::KindStore::kFloat: {
          uint32_t n = v.count * uint32_t(pbrta::kind_width(k));
          for (uint32_t j = 0; j < n; ++j) {
            uint32_t w;
            std::memcpy(&w, &e.floats[v.offset + j], 4);
            words_.push_back(w);
          }
          break;
        }
      }
      values_.push_back(out);
    }
    entities_.push_back(r);
    provenance(e.loc, name, path);
    return uint32_t(entities_.size() - 1);
  }

  void build(pbrta::ArchiveWriter* w, const ArchiveOptions& opt) {
    const SceneDesc& s = scene_;
    pbrta::SceneRecord sr{};
    sr.camera = entity(s.camera.params);
    sr.camera_transform = transform(s.camera.camera_from_world);
    sr.camera_medium = idx(s.camera.medium);
    sr.film = entity(s.film);
    sr.filter = entity(s.filter);
    sr.sampler = entity(s.sampler);
    sr.integrator = entity(s.integrator);
    sr.accelerator = entity(s.accelerator);

    std::vector<pbrta::TextureRecord> textures;
    for (const TextureDesc& t : s.textures)
      textures.push_back(
          {entity(t.params, t.name), 0, transform(t.world_from_texture), idx(t.image)});
    std::vector<pbrta::MaterialRecord> materials;
    for (const MaterialDesc& m : s.materials)
      materials.push_back({entity(m.params, m.name), 0, {idx(m.mix[0]), idx(m.mix[1])}});
    std::vector<pbrta::MediumRecord> media;
    for (const MediumDesc& m : s.media)
      media.push_back({entity(m.params, m.name), transform(m.world_from_medium), {0, 0}});
    std::vector<pbrta::LightRecord> lights;
    for (const LightDesc& l : s.lights)
      lights.push_back(
          {entity(l.params), transform(l.world_from_light), idx(l.medium), idx(l.image)});
    std::vector<uint32_t> area_lights;
    for (const Entity& a : s.area_lights) area_lights.push_back(entity(a));
    std::vector<pbrta::ShapeRecord> shapes;
    for (const ShapeDesc& sh : s.shapes) {
      pbrta::ShapeRecord r{};
      r.entity = entity(sh.params);
      r.mesh = idx(sh.mesh);
      r.material = idx(sh.material);
      r.area_light = idx(sh.area_light);
      r.inside_medium = idx(sh.inside_medium);
      r.outside_medium = idx(sh.outside_medium);
      r.transform = transform(s.transforms[size_t(sh.transform)]);
      r.object = idx(sh.object);
      r.flags = (sh.reverse_orientation ? uint32_t(pbrta::kShapeReverseOrientation) : 0u) |
                (sh.transform_swaps_handedness ? uint32_t(pbrta::kShapeSwapsHandedness) : 0u);
      shapes.push_back(r);
    }
    std::vector<pbrta::ObjectRecord> objects;
    std::vector<uint32_t> object_shapes;
    for (const ObjectDesc& o : s.objects) {
      objects.push_back({0, uint32_t(object_shapes.size()), uint32_t(o.shapes.size()),
                         uint32_t(provenance_.size())});
      provenance(o.loc, o.name);
      for (int32_t sh : o.shapes) object_shapes.push_back(uint32_t(sh));
    }
    std::vector<pbrta::InstanceRecord> instances;
    for (const InstanceDesc& i : s.instances) {
      instances.push_back({uint32_t(i.object), transform(s.transforms[size_t(i.transform)]),
                           uint32_t(provenance_.size()), 0});
      provenance(i.loc);
    }

    // Geometry: meshes packed into chunks; the records name their section,
    // which is only known once the earlier sections are added, so the
    // geometry sections come last in the table.
    std::vector<pbrta::MeshRecord> meshes;
    std::vector<std::vector<uint8_t>> chunks;
    std::vector<uint32_t> chunk_counts;
    std::vector<uint32_t> mesh_chunk;
    // A refined shape's mesh records the shape it came from.
    std::vector<uint32_t> mesh_source(s.meshes.size(), kNoIndex);
    for (size_t i = 0; i < s.shapes.size(); ++i)
      if (s.shapes[i].mesh != kNone && is_refined_shape(s.shapes[i].params.type_name()))
        mesh_source[size_t(s.shapes[i].mesh)] = uint32_t(i);
    // Draco meshes are encoded (and decoded back) in parallel first; each gets a section of its
    // own, the other meshes share chunks as before.
    std::vector<DracoMesh> draco(s.meshes.size());
    if (opt.draco_bits > 0) {
      uint64_t triangles = 0;
      size_t eligible = 0;
      for (size_t i = 0; i < s.meshes.size(); ++i) {
        draco[i].tried = draco_eligible(s.meshes[i], opt);
        if (draco[i].tried) triangles += s.meshes[i].num_triangles(), ++eligible;
      }
      if (opt.progress) opt.progress->phase("Draco meshes", eligible);
      pbrta::ProgressCount::Report report;
      if (opt.progress)
        report = [p = opt.progress](uint64_t done, uint64_t total) { p->encoded(done, total); };
      pbrta::ProgressCount encoded(triangles, std::move(report));
      tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
      arena.execute([&] {
        tbb::parallel_for(size_t(0), s.meshes.size(), [&](size_t i) {
          if (!draco[i].tried) return;
          draco_compress(s.meshes[i], uint32_t(i), opt, &draco[i]);
          encoded.add(s.meshes[i].num_triangles());
        });
      });
      encoded.finish();
    }
    std::vector<std::vector<uint8_t>> draco_streams;  // per chunk; empty for lossless chunks
    int open_chunk = -1;  // the lossless chunk meshes are being added to
    for (const TriangleMesh& m : s.meshes) {
      const size_t mi = meshes.size();
      if (draco[mi].tried && !draco[mi].used) ++draco_kept_lossless_;
      if (draco[mi].used) {
        pbrta::MeshRecord r = draco[mi].record;
        r.refine_level = m.refine_level;
        r.source_shape = mesh_source[mi];
        chunks.push_back(std::move(draco[mi].raw));
        chunk_counts.push_back(1);
        draco_streams.resize(chunks.size());
        draco_streams.back() = std::move(draco[mi].stored);
        draco_stats_.push_back(draco[mi].stats);
        mesh_chunk.push_back(uint32_t(chunks.size() - 1));
        meshes.push_back(r);
        continue;
      }
      uint64_t need = 16 * 6 + (m.P.size() + m.N.size() + m.S.size() + m.uv.size()) * 4 +
                      m.indices.size() * 4 + m.face_indices.size() * 4;
      if (open_chunk < 0 || (chunks[size_t(open_chunk)].size() + need > opt.geometry_chunk_bytes &&
                             !chunks[size_t(open_chunk)].empty())) {
        chunks.emplace_back();
        chunk_counts.push_back(0);
        open_chunk = int(chunks.size() - 1);
      }
      std::vector<uint8_t>& c = chunks[size_t(open_chunk)];
      ++chunk_counts[size_t(open_chunk)];
      auto put = [&c](const void* data, size_t bytes) -> uint64_t {
        c.resize((c.size() + 15) & ~size_t(15), 0);
        uint64_t at = c.size();
        c.resize(at + bytes);
        if (bytes) std::memcpy(c.data() + at, data, bytes);
        return at;
      };
      pbrta::MeshRecord r{};
      r.num_vertices = uint32_t(m.num_vertices());
      r.num_triangles = uint32_t(m.num_triangles());
      r.positions = put(m.P.data(), m.P.size() * 4);
      if (!m.N.empty()) r.flags |= pbrta::kMeshNormals, r.normals = put(m.N.data(), m.N.size() * 4);
      if (!m.S.empty())
        r.flags |= pbrta::kMeshTangents, r.tangents = put(m.S.data(), m.S.size() * 4);
      if (!m.uv.empty()) r.flags |= pbrta::kMeshUV, r.uv = put(m.uv.data(), m.uv.size() * 4);
      r.indices = put(m.indices.data(), m.indices.size() * 4);
      if (!m.face_indices.empty())
        r.flags |= pbrta::kMeshFaceIndices,
            r.face_indices = put(m.face_indices.data(), m.face_indices.size() * 4);
      r.refine_level = m.refine_level;
      r.source_shape = mesh_source[meshes.size()];
      mesh_chunk.push_back(uint32_t(open_chunk));
      meshes.push_back(r);
    }

    // Strings: count, offsets, data.
    std::vector<uint8_t> strings;
    append(&strings, uint32_t(strings_.size()));
    uint32_t off = 0;
    append(&strings, off);
    for (const std::string& str : strings_) {
      off += uint32_t(str.size());
      append(&strings, off);
    }
    for (const std::string& str : strings_) strings.insert(strings.end(), str.begin(), str.end());

    sr.num_entities = uint32_t(entities_.size());
    sr.num_values = uint32_t(values_.size());
    sr.num_words = uint32_t(words_.size());
    sr.num_strings = uint32_t(strings_.size());
    sr.num_transforms = uint32_t(transforms_.size());
    sr.num_textures = uint32_t(textures.size());
    sr.num_materials = uint32_t(materials.size());
    sr.num_media = uint32_t(media.size());
    sr.num_lights = uint32_t(lights.size());
    sr.num_area_lights = uint32_t(area_lights.size());
    sr.num_shapes = uint32_t(shapes.size());
    sr.num_objects = uint32_t(objects.size());
    sr.num_object_shapes = uint32_t(object_shapes.size());
    sr.num_instances = uint32_t(instances.size());
    sr.num_meshes = uint32_t(meshes.size());
    sr.num_images = uint32_t(s.images.size());

    using K = pbrta::SectionKind;
    // ARCHIVE.md section 5: zstd (raw with --codec none); arrays of 4-byte numbers (records,
    // words, geometry, texels) shuffled, the bytes of the scene record, strings and provenance
    // not.
    const pbrta::Codec codec = opt.compress ? pbrta::Codec::kZstd : pbrta::Codec::kRaw;
    const bool numbers = opt.compress;
    auto add_records = [&](K kind, const auto& records) {
      w->add_section(kind, bytes_of(records), uint32_t(records.size()), codec, numbers);
    };
    std::vector<uint8_t> scene_bytes;
    append(&scene_bytes, sr);
    w->add_section(K::kScene, std::move(scene_bytes), 1, codec);
    w->add_section(K::kStrings, std::move(strings), uint32_t(strings_.size()), codec);
    add_records(K::kEntities, entities_);
    add_records(K::kValues, values_);
    add_records(K::kWords, words_);
    add_records(K::kTransforms, transforms_);
    if (!textures.empty()) add_records(K::kTextures, textures);
    if (!materials.empty()) add_records(K::kMaterials, materials);
    if (!media.empty()) add_records(K::kMedia, media);
    if (!lights.empty()) add_records(K::kLights, lights);
    if (!area_lights.empty()) add_records(K::kAreaLights, area_lights);
    if (!shapes.empty()) add_records(K::kShapes, shapes);
    if (!objects.empty()) add_records(K::kObjects, objects);
    if (!object_shapes.empty()) add_records(K::kObjectShapes, object_shapes);
    if (!instances.empty()) add_records(K::kInstances, instances);
    // Meshes name their geometry section by table index: the meshes section
    // goes in now, the geometry chunks right after it.
    uint32_t first_geometry = w->section_count() + (meshes.empty() ? 0 : 1);
    for (size_t i = 0; i < meshes.size(); ++i) meshes[i].section = first_geometry + mesh_chunk[i];
    if (!meshes.empty()) add_records(K::kMeshes, meshes);
    draco_streams.resize(chunks.size());
    for (size_t c = 0; c < chunks.size(); ++c) {
      if (!draco_streams[c].empty())
        w->add_encoded_section(K::kGeometry, std::move(chunks[c]), std::move(draco_streams[c]),
                               chunk_counts[c], pbrta::Codec::kDraco);
      else
        w->add_section(K::kGeometry, std::move(chunks[c]), chunk_counts[c], codec, numbers);
    }
    add_images(w, opt, codec, numbers);
    // Provenance goes last: an archive recompiled from its own dump then
    // matches byte for byte up to this section's offset.
    std::vector<uint8_t> prov;
    append(&prov, uint32_t(provenance_.size()));
    append(&prov, uint32_t(pstrings_.size()));
    for (const pbrta::ProvenanceRecord& p : provenance_) append(&prov, p);
    uint32_t poff = 0;
    append(&prov, poff);
    for (const std::string& str : pstrings_) {
      poff += uint32_t(str.size());
      append(&prov, poff);
    }
    for (const std::string& str : pstrings_) prov.insert(prov.end(), str.begin(), str.end());
    w->add_section(K::kProvenance, std::move(prov), uint32_t(provenance_.size()), codec);
  }

  // Images: the records, then texels chunks holding whole images (every level of an image in
  // one chunk, each level 16-byte aligned), so large scenes decompress in parallel. The records
  // name their chunk by table index, so the chunks follow the images section. Source images
  // (the last ones) start a chunk of their own, which renderers need not decode.
  void add_images(pbrta::ArchiveWriter* w, const ArchiveOptions& opt, pbrta::Codec codec,
                  bool shuffle) {
    const std::vector<ImageDesc>& in = scene_.images;
    if (in.empty()) return;
    std::vector<pbrta::ImageRecord> images;
    std::vector<std::vector<uint8_t>> chunks;
    std::vector<uint32_t> chunk_counts;
    const uint32_t first_chunk = w->section_count() + 1;
    const std::vector<bool> is_distribution = distribution_images(scene_);
    std::vector<bool> is_source(in.size(), false);
    for (const ImageDesc& d : in)
      if (d.source_image >= 0) is_source[size_t(d.source_image)] = true;
    for (size_t i = 0; i < in.size(); ++i) {
      const ImageDesc& d = in[i];
      const DecodedImage& im = d.image;
      const uint32_t format =
          uint32_t(is_distribution[i] ? pbrta::PixelFormat::kFloat32 : opt.texture_format);
      const uint64_t bytes_per = pbrta::texel_bytes(format);
      uint64_t need = 0;
      for (const std::vector<float>& level : im.levels)
        need += (level.size() * bytes_per + 15) & ~15ull;
      if (chunks.empty() || (is_source[i] && !is_source[i - 1]) ||
          (chunks.back().size() + need > opt.texel_chunk_bytes && !chunks.back().empty())) {
        chunks.emplace_back();
        chunk_counts.push_back(0);
      }
      std::vector<uint8_t>& c = chunks.back();
      ++chunk_counts.back();
      pbrta::ImageRecord r{};
      r.width = im.width;
      r.height = im.height;
      r.channels = im.channels;
      r.levels = uint32_t(im.levels.size());
      r.format = format;
      r.section = first_chunk + uint32_t(chunks.size() - 1);
      r.wrap = uint32_t(im.wrap);
      r.distribution = idx(d.distribution);
      r.source_width = im.source_width;
      r.source_height = im.source_height;
      r.source_image = idx(d.source_image);
      for (size_t l = 0; l < im.levels.size(); ++l) {
        c.resize((c.size() + 15) & ~size_t(15), 0);
        if (l == 0) r.offset = c.size();
        size_t at = c.size(), count = im.levels[l].size();
        c.resize(at + count * bytes_per);
        encode_level(format, im.levels[l].data(), count, c.data() + at, opt.threads);
      }
      images.push_back(r);
    }
    w->add_section(pbrta::SectionKind::kImages, bytes_of(images), uint32_t(images.size()), codec,
                   shuffle);
    for (size_t c = 0; c < chunks.size(); ++c)
      w->add_section(pbrta::SectionKind::kTexels, std::move(chunks[c]), chunk_counts[c], codec,
                     shuffle);
  }

  const std::vector<DracoMeshStats>& draco_stats() const { return draco_stats_; }
  uint32_t draco_kept_lossless() const { return draco_kept_lossless_; }

 private:
  const SceneDesc& scene_;
  const SourceFiles& files_;
  std::string base_dir_;
  std::vector<std::string> strings_;
  std::unordered_map<std::string, uint32_t> string_index_;
  std::vector<pbrta::TransformRecord> transforms_;
  std::unordered_map<std::string, uint32_t> transform_index_;
  std::vector<pbrta::EntityRecord> entities_;
  std::vector<pbrta::ValueRecord> values_;
  std::vector<uint32_t> words_;
  std::vector<pbrta::ProvenanceRecord> provenance_;
  std::vector<std::string> pstrings_;
  std::unordered_map<std::string, uint32_t> pstring_index_;
  std::vector<DracoMeshStats> draco_stats_;
  uint32_t draco_kept_lossless_ = 0;
};

uint64_t effect_bits(const Effects& fx) {
  uint64_t b = 0;
  if (fx.media) b |= pbrta::kEffectMedia;
  if (fx.motion_blur) b |= pbrta::kEffectMotionBlur;
  if (fx.textures) b |= pbrta::kEffectTextures;
  if (fx.area_lights) b |= pbrta::kEffectAreaLights;
  if (fx.infinite_lights) b |= pbrta::kEffectInfiniteLights;
  if (fx.subsurface) b |= pbrta::kEffectSubsurface;
  if (fx.instancing) b |= pbrta::kEffectInstancing;
  if (fx.alpha) b |= pbrta::kEffectAlpha;
  return b;
}

}  // namespace

bool write_archive(const SceneDesc& scene, const SourceFiles& files, const std::string& base_dir,
                   const std::string& path, const ArchiveOptions& options, ArchiveStats* stats,
                   std::string* error) {
  if (!check_texture_format(scene, options.texture_format, error)) return false;
  pbrta::ArchiveWriter writer;
  Builder builder(scene, files, base_dir);
  builder.build(&writer, options);
  pbrta::ArchiveWriter::CompressProgress on_compressed;
  if (options.progress) {
    options.progress->phase(options.compress ? "compressing" : "writing", writer.section_count());
    on_compressed = [p = options.progress](uint64_t done, uint64_t total) {
      p->compressed(done, total);
    };
  }
  if (!writer.write(path, effect_bits(scene.effects), options.zstd_level, options.threads, error,
                    on_compressed))
    return false;
  if (stats) {
    stats->file_size = writer.last_file_size();
    stats->sections = uint32_t(writer.table().size());
    stats->draco = builder.draco_stats();
    stats->draco_kept_lossless = builder.draco_kept_lossless();
    stats->raw_size = 0;
    for (const pbrta::SectionEntry& e : writer.table()) stats->raw_size += e.raw_size;
  }
  return true;
}

}  // namespace pbrtc
