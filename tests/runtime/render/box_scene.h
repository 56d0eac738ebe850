// tests/runtime/render/box_scene.h — the small scene the integrator-consistency tests share.
//
// A 24x24 view into a box lit by a one-sided quad on its ceiling, with a red left wall, a green
// right wall and a blue sphere on the floor; `integrator` is the whole Integrator directive.
// With point_light, a point light joins the quad; with glossy, the right wall and the sphere
// are plastic (a glossy lobe beside the diffuse one) instead of matte.
#pragma once

#include <string>

namespace rt {

inline std::string box_scene(const std::string& integrator, bool point_light, bool glossy) {
  const std::string green =
      glossy
          ? R"(Material "plastic" "rgb Kd" [0.2 0.6 0.2] "rgb Ks" [0.4 0.4 0.4] "float roughness" [0.1])"
          : R"(Material "matte" "rgb Kd" [0.2 0.6 0.2])";
  const std::string blue =
      glossy
          ? R"(Material "plastic" "rgb Kd" [0.3 0.3 0.6] "rgb Ks" [0.3 0.3 0.3] "float roughness" [0.3])"
          : R"(Material "matte" "rgb Kd" [0.3 0.3 0.6])";
  return R"(
LookAt 0 1 -3.5  0 1 0  0 1 0
Camera "perspective" "float fov" [45]
Film "image" "integer xresolution" [24] "integer yresolution" [24]
Sampler "02sequence" "integer pixelsamples" [256]
)" + integrator +
         "\nWorldBegin\n" +
         (point_light ? "LightSource \"point\" \"point from\" [0.5 1.6 0] \"rgb I\" [1 1 1]\n"
                      : "") +
         R"(AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  Shape "trianglemesh" "point P" [-0.4 1.99 -0.4  0.4 1.99 -0.4  0.4 1.99 0.4  -0.4 1.99 0.4]
    "integer indices" [0 1 2 0 2 3]
AttributeEnd
Material "matte" "rgb Kd" [0.6 0.6 0.6]
Shape "trianglemesh" "point P" [-1 0 -4  1 0 -4  1 0 1  -1 0 1] "integer indices" [0 2 1 0 3 2]
Shape "trianglemesh" "point P" [-1 2 -4  1 2 -4  1 2 1  -1 2 1] "integer indices" [0 1 2 0 2 3]
Shape "trianglemesh" "point P" [-1 0 1  1 0 1  1 2 1  -1 2 1] "integer indices" [0 1 2 0 2 3]
Material "matte" "rgb Kd" [0.7 0.2 0.2]
Shape "trianglemesh" "point P" [-1 0 -4  -1 0 1  -1 2 1  -1 2 -4] "integer indices" [0 1 2 0 2 3]
)" + green +
         R"(
Shape "trianglemesh" "point P" [1 0 -4  1 0 1  1 2 1  1 2 -4] "integer indices" [0 2 1 0 3 2]
AttributeBegin
  Translate -0.3 0.35 0.2
  )" + blue +
         R"(
  Shape "sphere" "float radius" [0.35]
AttributeEnd
WorldEnd
)";
}

}  // namespace rt
