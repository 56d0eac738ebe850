#include "tools/accuracy/sweep_config.h"

#include <algorithm>

namespace accuracy {

namespace {

const std::vector<std::string> kSamplers = {"random",     "stratified", "halton",        "sobol",
                                            "02sequence", "maxmindist", "lowdiscrepancy"};
const std::vector<std::string> kIntegrators = {"path", "directlighting", "whitted",
                                               "ambientocclusion"};
const std::vector<std::string> kStrategies = {"uniform", "power", "spatial"};

bool check(const std::vector<std::string>& given, const std::vector<std::string>& known,
           const char* what, std::string* error) {
  for (const std::string& g : given) {
    if (std::find(known.begin(), known.end(), g) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    *error = "unknown " + std::string(what) + " \"" + g + "\" (known: " + list + ")";
    return false;
  }
  return true;
}

// An empty list stands for the scene's own choice: one empty entry.
std::vector<std::string> or_scene(const std::vector<std::string>& list) {
  return list.empty() ? std::vector<std::string>{""} : list;
}

}  // namespace

std::string SweepConfig::name() const {
  std::string n;
  for (const std::string* part : {&sampler, &integrator, &strategy})
    if (!part->empty()) n += (n.empty() ? "" : "/") + *part;
  return n.empty() ? "scene" : n;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    std::string item = text.substr(start, end - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) out.push_back(item);
    start = end + 1;
  }
  return out;
}

bool make_configs(const std::vector<std::string>& samplers,
                  const std::vector<std::string>& integrators,
                  const std::vector<std::string>& strategies, std::vector<SweepConfig>* out,
                  std::string* error) {
  if (!check(samplers, kSamplers, "sampler", error) ||
      !check(integrators, kIntegrators, "integrator", error) ||
      !check(strategies, kStrategies, "light strategy", error))
    return false;
  out->clear();
  for (const std::string& s : or_scene(samplers))
    for (const std::string& i : or_scene(integrators)) {
      bool takes_strategy = i.empty() || i == "path";
      for (const std::string& l : takes_strategy ? or_scene(strategies) : or_scene({}))
        out->push_back({s, i, l});
    }
  return true;
}

}  // namespace accuracy
