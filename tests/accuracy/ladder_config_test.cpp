// The spp ladder (doubling, sample and time budgets) and the configuration product.
#include <gtest/gtest.h>

#include "tools/accuracy/spp_ladder.h"
#include "tools/accuracy/sweep_config.h"

namespace {

using accuracy::LadderBudget;

TEST(SppLadder, DoublesUpToTheSampleBudget) {
  EXPECT_EQ(accuracy::spp_ladder({1, 64, 0}), (std::vector<int>{1, 2, 4, 8, 16, 32, 64}));
  EXPECT_EQ(accuracy::spp_ladder({3, 20, 0}), (std::vector<int>{3, 6, 12}));
  EXPECT_EQ(accuracy::spp_ladder({1, 1, 0}), (std::vector<int>{1}));
  EXPECT_EQ(accuracy::spp_ladder({1, 5, 0}), (std::vector<int>{1, 2, 4}));
}

TEST(SppLadder, StopsBeforeARungPredictedToBreakTheTimeBudget) {
  LadderBudget b{1, 1024, 10};
  // Spent 3.5 s, the last rung took 2 s: the next (about 4 s) still fits.
  EXPECT_EQ(accuracy::next_rung(b, 4, 2.0, 3.5), 8);
  // Spent 7.5 s, the last took 4 s: the next (about 8 s) would end at 15.5 s.
  EXPECT_EQ(accuracy::next_rung(b, 8, 4.0, 7.5), 0);
  // No time budget: only spp counts.
  EXPECT_EQ(accuracy::next_rung({1, 1024, 0}, 8, 1e9, 1e9), 16);
  EXPECT_EQ(accuracy::next_rung({1, 1024, 0}, 1024, 0, 0), 0);
  // Never overflows near INT_MAX.
  EXPECT_EQ(accuracy::next_rung({1, 2147483647, 0}, 1 << 30, 0, 0), 0);
}

TEST(SweepConfig, ProductWithStrategiesOnlyForPath) {
  std::vector<accuracy::SweepConfig> c;
  std::string error;
  ASSERT_TRUE(accuracy::make_configs({"halton", "sobol"}, {"path", "directlighting"},
                                     {"uniform", "power"}, &c, &error))
      << error;
  std::vector<std::string> names;
  for (const auto& x : c) names.push_back(x.name());
  EXPECT_EQ(names, (std::vector<std::string>{"halton/path/uniform", "halton/path/power",
                                             "halton/directlighting", "sobol/path/uniform",
                                             "sobol/path/power", "sobol/directlighting"}));
}

TEST(SweepConfig, EmptyListsKeepTheScenesOwn) {
  std::vector<accuracy::SweepConfig> c;
  std::string error;
  ASSERT_TRUE(accuracy::make_configs({}, {}, {}, &c, &error));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].name(), "scene");
  EXPECT_TRUE(c[0].sampler.empty() && c[0].integrator.empty() && c[0].strategy.empty());
  ASSERT_TRUE(
      accuracy::make_configs(accuracy::split_list(" random, ,stratified "), {}, {}, &c, &error));
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[1].name(), "stratified");
}

TEST(SweepConfig, UnknownNamesAreRefused) {
  std::vector<accuracy::SweepConfig> c;
  std::string error;
  EXPECT_FALSE(accuracy::make_configs({"halton", "bogus"}, {}, {}, &c, &error));
  EXPECT_NE(error.find("\"bogus\""), std::string::npos) << error;
  EXPECT_FALSE(accuracy::make_configs({}, {"bdpt"}, {}, &c, &error));
  EXPECT_FALSE(accuracy::make_configs({}, {}, {"nearest"}, &c, &error));
}

}  // namespace
