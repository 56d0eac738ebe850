// parse_bench — front-end speed and memory, single-threaded. Never run in CI.
//
//   parse_bench generate-mesh FILE MB      write a mesh-heavy scene of about MB megabytes
//   parse_bench generate-shapes FILE N     write a scene of N small shapes (spheres, tiny meshes)
//   parse_bench FILE... [--repeat N]       parse each file N times (default 3), report the best
//
// For each file it prints the text bytes read (scene plus Includes, not PLY),
// the best wall time and MB/s, the peak heap (every C++ allocation, counted by
// the replaced operator new; the memory-mapped input is not heap) and the size
// of the resolved data (mesh arrays and entity values) the compile produced.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <random>
#include <string>
#include <vector>

#include "compiler/scene_builder.h"
#include "compiler/huge_page_heap.h"

namespace {
std::atomic<size_t> g_current{0};
std::atomic<size_t> g_peak{0};

void note_alloc(size_t n) {
  size_t cur = g_current.fetch_add(n) + n;
  size_t peak = g_peak.load();
  while (cur > peak && !g_peak.compare_exchange_weak(peak, cur)) {
  }
}
}  // namespace

// Every allocation carries its size in a 16-byte prefix so delete can subtract it. The blocks
// come from heap_allocate, as in pbrtc (compiler/huge_page_heap.h).
void* operator new(size_t n) {
  void* p = pbrtc::heap_allocate(n + 16);
  *static_cast<size_t*>(p) = n;
  note_alloc(n);
  return static_cast<char*>(p) + 16;
}
void operator delete(void* p) noexcept {
  if (!p) return;
  char* base = static_cast<char*>(p) - 16;
  g_current.fetch_sub(*reinterpret_cast<size_t*>(base));
  pbrtc::heap_release(base);
}
void operator delete(void* p, size_t) noexcept {
  operator delete(p);
}
void* operator new[](size_t n) {
  return operator new(n);
}
void operator delete[](void* p) noexcept {
  operator delete(p);
}
void operator delete[](void* p, size_t) noexcept {
  operator delete(p);
}

namespace {

// The resolved scene's own size: every element struct plus the arrays it owns,
// decoded images included
// (allocator overhead and unused vector capacity are not counted).
size_t resolved_bytes(const pbrtc::SceneDesc& s) {
  size_t b = sizeof(s);
  for (const auto& m : s.meshes)
    b += sizeof(m) + (m.P.size() + m.N.size() + m.S.size() + m.uv.size()) * 4 +
         m.indices.size() * 4 + m.face_indices.size() * 4;
  auto entity = [&](const pbrtc::Entity& e) {
    b += e.values.size() * sizeof(pbrtc::Value) + e.floats.size() * 4 + e.ints.size() * 4;
    for (const auto& str : e.strings) b += sizeof(str) + str.size();
  };
  for (const auto& sh : s.shapes) b += sizeof(sh), entity(sh.params);
  for (const auto& m : s.materials) b += sizeof(m), entity(m.params);
  for (const auto& t : s.textures) b += sizeof(t), entity(t.params);
  for (const auto& l : s.lights) b += sizeof(l), entity(l.params);
  for (const auto& m : s.media) b += sizeof(m), entity(m.params);
  for (const auto& a : s.area_lights) b += sizeof(a), entity(a);
  for (const auto& o : s.objects) b += sizeof(o) + o.shapes.size() * 4;
  b += s.instances.size() * sizeof(pbrtc::InstanceDesc);
  b += s.transforms.size() * sizeof(pbrtc::AnimatedTransform);
  // Decoded images (environment maps, image textures): their pyramids and
  // distributions are resolved data too, and a scene with a large map would
  // otherwise show a meaningless heap-to-data ratio.
  for (const auto& img : s.images) {
    b += sizeof(img) + img.source.size() + img.image.source.size() * 4;
    for (const auto& level : img.image.levels) b += level.size() * 4;
  }
  return b;
}

// A grid-tessellated bumpy sphere per mesh, written as pbrt text.
void generate_mesh(const char* path, double mb) {
  FILE* f = std::fopen(path, "wb");
  if (!f) {
    std::perror(path);
    std::exit(1);
  }
  std::fprintf(f, "LookAt 0 0 -10 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n");
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1, 1);
  const int n = 200;  // 200x200 grid: 40k vertices, 79k triangles per mesh
  size_t target = size_t(mb * 1e6);
  int mesh = 0;
  while (size_t(std::ftell(f)) < target) {
    std::fprintf(f, "AttributeBegin\nTranslate %d 0 0\nShape \"trianglemesh\" \"point3 P\" [\n",
                 mesh++ % 100);
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        float th = 3.14159265f * j / (n - 1), ph = 6.2831853f * i / (n - 1);
        float r = 1 + 0.01f * u(rng);
        std::fprintf(f, "%.6g %.6g %.6g ", r * std::sin(th) * std::cos(ph),
                     r * std::sin(th) * std::sin(ph), r * std::cos(th));
      }
      std::fputc('\n', f);
    }
    std::fprintf(f, "]\n\"normal N\" [\n");
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        float th = 3.14159265f * j / (n - 1), ph = 6.2831853f * i / (n - 1);
        std::fprintf(f, "%.5f %.5f %.5f ", std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                     std::cos(th));
      }
      std::fputc('\n', f);
    }
    std::fprintf(f, "]\n\"integer indices\" [\n");
    for (int j = 0; j + 1 < n; ++j) {
      for (int i = 0; i + 1 < n; ++i) {
        int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
        std::fprintf(f, "%d %d %d %d %d %d ", a, b, d, a, d, c);
      }
      std::fputc('\n', f);
    }
    std::fprintf(f, "]\nAttributeEnd\n");
  }
  std::fprintf(f, "WorldEnd\n");
  std::fclose(f);
}

void generate_shapes(const char* path, long count) {
  FILE* f = std::fopen(path, "wb");
  if (!f) {
    std::perror(path);
    std::exit(1);
  }
  std::fprintf(f, "LookAt 0 0 -10 0 0 0 0 1 0\nCamera \"perspective\"\nWorldBegin\n");
  std::fprintf(f, "MakeNamedMaterial \"m\" \"string type\" \"plastic\" \"rgb Kd\" [.5 .4 .3]\n");
  for (long i = 0; i < count; ++i) {
    std::fprintf(f, "AttributeBegin\n  Translate %ld %ld %ld\n", i % 100, (i / 100) % 100,
                 i / 10000);
    if (i % 2 == 0) {
      std::fprintf(f, "  NamedMaterial \"m\"\n  Shape \"sphere\" \"float radius\" 0.25\n");
    } else {
      std::fprintf(f, "  Material \"matte\" \"rgb Kd\" [%.3f .5 .5]\n", (i % 97) / 97.0);
      std::fprintf(f,
                   "  Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] "
                   "\"integer indices\" [0 1 2]\n");
    }
    std::fprintf(f, "AttributeEnd\n");
  }
  std::fprintf(f, "WorldEnd\n");
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 4 && std::strcmp(argv[1], "generate-mesh") == 0) {
    generate_mesh(argv[2], std::atof(argv[3]));
    return 0;
  }
  if (argc >= 4 && std::strcmp(argv[1], "generate-shapes") == 0) {
    generate_shapes(argv[2], std::atol(argv[3]));
    return 0;
  }
  int repeat = 3;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
      repeat = std::atoi(argv[++i]);
    else
      files.push_back(argv[i]);
  }
  if (files.empty()) {
    std::fprintf(stderr,
                 "usage: parse_bench FILE... [--repeat N] | generate-mesh FILE MB | "
                 "generate-shapes FILE N\n");
    return 2;
  }
  std::printf("%-60s %10s %9s %9s %11s %11s %6s\n", "file", "text MB", "best s", "MB/s",
              "peak heap MB", "resolved MB", "ratio");
  for (const std::string& path : files) {
    double best = 1e30;
    size_t text = 0, peak = 0, resolved = 0;
    for (int r = 0; r < repeat; ++r) {
      g_peak = g_current.load();
      size_t base = g_current.load();
      auto t0 = std::chrono::steady_clock::now();
      {
        pbrtc::SourceFiles files_read;
        pbrtc::Diagnostics diag(&files_read, nullptr);
        pbrtc::SceneDesc scene;
        bool ok = pbrtc::build_scene(path, &files_read, &diag, &scene);
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!ok) {
          std::fprintf(stderr, "%s: %d errors\n", path.c_str(), diag.error_count());
          for (const auto& d : diag.all()) std::fprintf(stderr, "%s\n", d.text.c_str());
          return 1;
        }
        best = std::min(best, s);
        text = 0;
        for (size_t i = 0; i < files_read.size(); ++i) text += files_read.text(uint32_t(i)).size();
        peak = g_peak.load() - base;
        resolved = resolved_bytes(scene);
      }
    }
    std::printf("%-60s %10.1f %9.3f %9.1f %11.1f %11.1f %6.2f\n", path.c_str(), text / 1e6, best,
                text / 1e6 / best, peak / 1e6, resolved / 1e6,
                resolved ? double(peak) / resolved : 0);
  }
  return 0;
}
