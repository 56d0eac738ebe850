#include "tools/accuracy/time_to_error.h"

#include <cmath>
#include <cstdio>

namespace accuracy {

std::vector<TimeToError> times_to_error(const std::vector<SweepRow>& rows,
                                        const std::vector<double>& targets) {
  std::vector<TimeToError> out;
  for (const SweepRow& r : rows) {
    TimeToError* t = nullptr;
    for (TimeToError& e : out)
      if (e.config == r.config) t = &e;
    if (!t) {
      out.push_back({r.config, std::vector<double>(targets.size(), -1),
                     std::vector<int>(targets.size(), 0), 0});
      t = &out.back();
    }
    if (r.spp > t->max_spp) t->max_spp = r.spp;
    double err = std::sqrt(r.errors.relmse);
    for (size_t i = 0; i < targets.size(); ++i)
      if (err <= targets[i] && (t->spp[i] == 0 || r.spp < t->spp[i])) {
        t->spp[i] = r.spp;
        t->seconds[i] = r.seconds;
      }
  }
  return out;
}

std::string time_to_error_table(const std::string& scene, const std::vector<SweepRow>& rows,
                                const std::vector<double>& targets) {
  std::string out = "| scene | configuration |";
  std::string rule = "|---|---|";
  char buf[128];
  for (double t : targets) {
    std::snprintf(buf, sizeof buf, " %g%% |", t * 100);
    out += buf;
    rule += "---:|";
  }
  out += "\n" + rule + "\n";
  for (const TimeToError& t : times_to_error(rows, targets)) {
    out += "| " + scene + " | " + t.config + " |";
    for (size_t i = 0; i < targets.size(); ++i) {
      if (t.spp[i] > 0)
        std::snprintf(buf, sizeof buf, " %.3g s (%d spp) |", t.seconds[i], t.spp[i]);
      else
        std::snprintf(buf, sizeof buf, " > %d spp |", t.max_spp);
      out += buf;
    }
    out += "\n";
  }
  return out;
}

}  // namespace accuracy
