#include "tools/accuracy/spp_ladder.h"

namespace accuracy {

int next_rung(const LadderBudget& budget, int spp, double last_seconds, double spent_seconds) {
  if (spp <= 0 || spp > budget.max_spp / 2) return 0;  // also keeps 2 spp from overflowing
  if (budget.max_seconds > 0 && spent_seconds + 2 * last_seconds > budget.max_seconds) return 0;
  return 2 * spp;
}

std::vector<int> spp_ladder(const LadderBudget& budget) {
  std::vector<int> ladder;
  for (int spp = budget.min_spp < 1 ? 1 : budget.min_spp; spp > 0 && spp <= budget.max_spp;
       spp = next_rung(budget, spp, 0, 0))
    ladder.push_back(spp);
  return ladder;
}

}  // namespace accuracy
