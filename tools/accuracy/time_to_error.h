// tools/accuracy/time_to_error.h — "how many seconds for 1% error", read off a sweep.
//
// The relative error here is sqrt(relmse), the RMS of the per-value relative
// error (image_error.h). A configuration reaches a target at its first rung
// (fewest spp) whose error is at or below it; the time is that rung's
// measured seconds — no interpolation between rungs, so the figure is one
// that was actually measured (and may overstate the time by up to the
// ladder's factor of two).
#pragma once

#include <string>
#include <vector>

#include "tools/accuracy/sweep.h"

namespace accuracy {

struct TimeToError {
  std::string config;
  std::vector<double> seconds;  // per target; < 0 when no rung reached it
  std::vector<int> spp;         // the rung that reached it (0 when none)
  int max_spp = 0;              // the ladder's last rung
};

// One entry per configuration, in the order they first appear in rows.
std::vector<TimeToError> times_to_error(const std::vector<SweepRow>& rows,
                                        const std::vector<double>& targets);

// A Markdown table: | scene | configuration | 5% | 2% | 1% | (a header and a
// row per configuration); cells "0.42 s (16 spp)" or "> 64 spp".
std::string time_to_error_table(const std::string& scene, const std::vector<SweepRow>& rows,
                                const std::vector<double>& targets);

}  // namespace accuracy
