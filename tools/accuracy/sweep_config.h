// tools/accuracy/sweep_config.h — the configurations a sweep compares.
//
// A configuration overrides the scene's sampler, integrator and path light
// strategy (rt::RenderJobOptions); an empty field keeps the scene's own. The
// sweep is the product of the three lists given (an empty list: the scene's
// own), except that a light strategy only means something to the path
// integrator, so a directlighting/whitted/ambientocclusion entry takes no
// strategy and appears once. Names are the non-empty fields joined by "/"
// ("halton", "sobol/path/power"), or "scene" when nothing is overridden.
#pragma once

#include <string>
#include <vector>

namespace accuracy {

struct SweepConfig {
  std::string sampler, integrator, strategy;
  std::string name() const;
};

// "a,b , c" -> {"a", "b", "c"}; empty entries are dropped.
std::vector<std::string> split_list(const std::string& text);

// False with *error naming the unknown entry (and the known ones).
bool make_configs(const std::vector<std::string>& samplers,
                  const std::vector<std::string>& integrators,
                  const std::vector<std::string>& strategies, std::vector<SweepConfig>* out,
                  std::string* error);

}  // namespace accuracy
