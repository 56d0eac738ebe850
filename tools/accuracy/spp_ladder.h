// tools/accuracy/spp_ladder.h — the sample counts a sweep renders: min_spp,
// then doubling, until a sample or time budget says stop.
//
// Cost grows about linearly with spp, so the next rung is predicted to take
// twice the last one's seconds. A rung is rendered when its spp is at most
// max_spp and, with max_seconds > 0, the seconds spent on this configuration
// so far plus that prediction stay within max_seconds. The first rung always
// renders (a sweep with no point at all would say nothing).
#pragma once

#include <vector>

namespace accuracy {

struct LadderBudget {
  int min_spp = 1;
  int max_spp = 64;
  double max_seconds = 0;  // per configuration; 0: no time limit
};

// The spp of the rung after one at `spp` that took `last_seconds`, with
// `spent_seconds` spent on the configuration in total; 0 when the ladder stops.
int next_rung(const LadderBudget& budget, int spp, double last_seconds, double spent_seconds);

// The whole ladder without a time limit: min_spp, 2 min_spp, ... <= max_spp.
std::vector<int> spp_ladder(const LadderBudget& budget);

}  // namespace accuracy
