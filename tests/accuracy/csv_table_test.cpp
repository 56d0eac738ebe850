// The CSV columns and the time-to-error table read off a sweep.
#include <gtest/gtest.h>

#include <sstream>

#include "tools/accuracy/sweep_csv.h"
#include "tools/accuracy/time_to_error.h"

namespace {

accuracy::SweepRow row(const std::string& config, int spp, double seconds, double relmse) {
  accuracy::SweepRow r;
  r.scene = "tiny";
  r.config = config;
  r.spp = spp;
  r.seconds = seconds;
  r.render_seconds = seconds / 2;
  r.errors.relmse = relmse;
  r.errors.rmse = 0.5;
  r.errors.mare = 0.25;
  return r;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, sep);) out.push_back(item);
  return out;
}

TEST(SweepCsv, HeaderAndOneLinePerRowWithEveryColumn) {
  std::string csv = accuracy::sweep_csv({row("halton", 4, 0.125, 0.0004), row("sobol", 8, 2, 1)});
  std::vector<std::string> lines = split(csv, '\n');
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "scene,config,spp,seconds,relmse,rmse,mare,render_seconds,estimated_error");
  std::vector<std::string> f = split(lines[1], ',');
  ASSERT_EQ(f.size(), 9u) << lines[1];
  EXPECT_EQ(f[0], "tiny");
  EXPECT_EQ(f[1], "halton");
  EXPECT_EQ(f[2], "4");
  EXPECT_DOUBLE_EQ(std::stod(f[3]), 0.125);
  EXPECT_DOUBLE_EQ(std::stod(f[4]), 0.0004);
  EXPECT_DOUBLE_EQ(std::stod(f[5]), 0.5);
  EXPECT_DOUBLE_EQ(std::stod(f[6]), 0.25);
  EXPECT_DOUBLE_EQ(std::stod(f[7]), 0.0625);
  EXPECT_DOUBLE_EQ(std::stod(f[8]), -1);  // no estimate
  EXPECT_EQ(split(lines[2], ',')[1], "sobol");
}

TEST(SweepCsv, CommasInNamesCannotBreakColumns) {
  accuracy::SweepRow r = row("a", 1, 1, 1);
  r.scene = "x,y";
  EXPECT_EQ(split(split(accuracy::sweep_csv({r}), '\n')[1], ',').size(), 9u);
}

TEST(TimeToError, FirstRungAtOrBelowEachTarget) {
  // sqrt(relmse): 0.1, 0.03, 0.009 for "a"; 0.2, 0.04 for "b".
  std::vector<accuracy::SweepRow> rows = {row("a", 1, 0.1, 0.01), row("a", 2, 0.2, 0.0009),
                                          row("a", 4, 0.4, 0.000081), row("b", 1, 0.3, 0.04),
                                          row("b", 2, 0.6, 0.0016)};
  auto t = accuracy::times_to_error(rows, {0.05, 0.02, 0.01});
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].config, "a");
  EXPECT_EQ(t[0].spp, (std::vector<int>{2, 4, 4}));
  EXPECT_DOUBLE_EQ(t[0].seconds[0], 0.2);
  EXPECT_DOUBLE_EQ(t[0].seconds[2], 0.4);
  EXPECT_EQ(t[1].spp, (std::vector<int>{2, 0, 0}));
  EXPECT_LT(t[1].seconds[1], 0);
  EXPECT_EQ(t[1].max_spp, 2);
  std::string table = accuracy::time_to_error_table("tiny", rows, {0.05, 0.02, 0.01});
  EXPECT_NE(table.find("| scene | configuration | 5% | 2% | 1% |"), std::string::npos) << table;
  EXPECT_NE(table.find("| tiny | a | 0.2 s (2 spp) | 0.4 s (4 spp) | 0.4 s (4 spp) |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| tiny | b | 0.6 s (2 spp) | > 2 spp | > 2 spp |"), std::string::npos)
      << table;
}

}  // namespace
