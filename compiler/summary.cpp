#include "compiler/summary.h"

#include <ostream>

namespace pbrtc {

std::string effects_list(const Effects& fx) {
  std::string s;
  auto add = [&](bool on, const char* name) {
    if (!on) return;
    if (!s.empty()) s += ", ";
    s += name;
  };
  add(fx.media, "media");
  add(fx.motion_blur, "motion blur");
  add(fx.textures, "textures");
  add(fx.area_lights, "area lights");
  add(fx.infinite_lights, "infinite lights");
  add(fx.subsurface, "subsurface");
  add(fx.instancing, "instancing");
  add(fx.alpha, "alpha masks");
  return s.empty() ? "none" : s;
}

void print_summary(std::ostream& out, const std::string& path, const SceneDesc& scene) {
  SceneCounts c = count_scene(scene);
  out << path << ": ok\n";
  out << "  shapes " << c.shapes << " (triangles " << c.triangles << "), lights " << c.lights
      << " (area " << c.area_lights << "), materials " << c.materials << ", textures " << c.textures
      << ", media " << c.media << ", objects " << c.objects << ", instances " << c.instances
      << "\n";
  out << "  effects: " << effects_list(scene.effects) << "\n";
  out << "  camera " << scene.camera.params.type_name() << ", film "
      << scene.film.get_int("xresolution") << "x" << scene.film.get_int("yresolution")
      << ", sampler " << scene.sampler.type_name() << ", filter " << scene.filter.type_name()
      << ", integrator " << scene.integrator.type_name() << "\n";
}

}  // namespace pbrtc
