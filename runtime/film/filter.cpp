// runtime/film/filter.cpp — filter values and the scene's filter entity.
#include "runtime/film/filter.h"

#include <cmath>
#include <string_view>

namespace rt {
namespace {

float gaussian_1d(float d, float alpha, float exp_r) {
  return std::max(0.f, std::exp(-alpha * d * d) - exp_r);
}

// Mitchell & Netravali, "Reconstruction Filters in Computer Graphics" (1988):
// the cubic k(t) on |t| < 2. The filter maps [-radius, radius] onto [-2, 2].
float mitchell_1d(float x, float b, float c) {
  float t = std::fabs(2 * x);
  if (t >= 2) return 0;
  if (t > 1)
    return ((-b - 6 * c) * t * t * t + (6 * b + 30 * c) * t * t + (-12 * b - 48 * c) * t +
            (8 * b + 24 * c)) *
           (1.f / 6);
  return ((12 - 9 * b - 6 * c) * t * t * t + (-18 + 12 * b + 6 * c) * t * t + (6 - 2 * b)) *
         (1.f / 6);
}

float sinc(float x) {
  x = std::fabs(x);
  // sin(pi x) / (pi x) loses all precision near 0, where its value is 1.
  if (x < 1e-5f) return 1;
  return std::sin(kPi * x) / (kPi * x);
}

// Lanczos: sinc windowed by a wider sinc stretched by tau.
float windowed_sinc(float x, float radius, float tau) {
  x = std::fabs(x);
  if (x > radius) return 0;
  return sinc(x) * sinc(x / tau);
}

}  // namespace

float Filter::evaluate(Vec2 p) const {
  if (!(std::fabs(p.x) <= radius.x && std::fabs(p.y) <= radius.y)) return 0;
  switch (type) {
    case Type::kBox:
      return 1;
    case Type::kTriangle:
      return std::max(0.f, radius.x - std::fabs(p.x)) * std::max(0.f, radius.y - std::fabs(p.y));
    case Type::kGaussian:
      return gaussian_1d(p.x, alpha, exp_x) * gaussian_1d(p.y, alpha, exp_y);
    case Type::kMitchell:
      return mitchell_1d(p.x / radius.x, b, c) * mitchell_1d(p.y / radius.y, b, c);
    case Type::kSinc:
      return windowed_sinc(p.x, radius.x, tau) * windowed_sinc(p.y, radius.y, tau);
  }
  return 0;
}

void finish_gaussian(Filter* f) {
  f->exp_x = std::exp(-f->alpha * f->radius.x * f->radius.x);
  f->exp_y = std::exp(-f->alpha * f->radius.y * f->radius.y);
}

bool make_filter(const pbrta::SceneArchive& archive, Filter* out, std::string* error) {
  uint32_t e = archive.scene().filter;
  if (e >= archive.entities.size) {
    *error = "the archive has no filter entity";
    return false;
  }
  std::string_view name = archive.type_name(e);
  Filter f;
  // Default radii are pbrt-v3's: they come from the schema, so only the type
  // decides which parameters exist.
  if (name == "box") {
    f.type = Filter::Type::kBox;
  } else if (name == "triangle") {
    f.type = Filter::Type::kTriangle;
  } else if (name == "gaussian") {
    f.type = Filter::Type::kGaussian;
    f.alpha = archive.get_float(e, "alpha", 2);
  } else if (name == "mitchell") {
    f.type = Filter::Type::kMitchell;
    f.b = archive.get_float(e, "B", 1.f / 3);
    f.c = archive.get_float(e, "C", 1.f / 3);
  } else if (name == "sinc") {
    f.type = Filter::Type::kSinc;
    f.tau = archive.get_float(e, "tau", 3);
  } else {
    *error = "not supported yet: filter \"" + std::string(name) + "\" (" + archive.where(e) + ")";
    return false;
  }
  float r = f.type == Filter::Type::kBox ? 0.5f : (f.type == Filter::Type::kSinc ? 4.f : 2.f);
  f.radius = {archive.get_float(e, "xwidth", r), archive.get_float(e, "ywidth", r)};
  // A zero or infinite radius has no pixel footprint (and 1/radius is used to
  // index the filter table).
  if (!(f.radius.x > 0 && f.radius.y > 0 && std::isfinite(f.radius.x) &&
        std::isfinite(f.radius.y))) {
    *error = "filter \"" + std::string(name) +
             "\": xwidth and ywidth must be positive and finite (" + archive.where(e) + ")";
    return false;
  }
  if (f.type == Filter::Type::kSinc && !(f.tau > 0)) {
    *error = "filter \"sinc\": tau must be positive (" + archive.where(e) + ")";
    return false;
  }
  if (f.type == Filter::Type::kGaussian) finish_gaussian(&f);
  *out = f;
  return true;
}

}  // namespace rt
