#include "tools/accuracy/sweep_csv.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

namespace accuracy {

const char kCsvHeader[] =
    "scene,config,spp,seconds,relmse,rmse,mare,render_seconds,estimated_error";

namespace {

std::string no_commas(std::string s) {
  std::replace(s.begin(), s.end(), ',', '_');
  return s;
}

}  // namespace

std::string sweep_csv(const std::vector<SweepRow>& rows) {
  std::string out = std::string(kCsvHeader) + "\n";
  char buf[256];
  for (const SweepRow& r : rows) {
    std::snprintf(buf, sizeof buf, ",%d,%.6g,%.6e,%.6e,%.6e,%.6g,%.6g\n", r.spp, r.seconds,
                  r.errors.relmse, r.errors.rmse, r.errors.mare, r.render_seconds,
                  r.estimated_error);
    out += no_commas(r.scene) + "," + no_commas(r.config) + buf;
  }
  return out;
}

bool write_sweep_csv(const std::string& path, const std::vector<SweepRow>& rows,
                     std::string* error) {
  std::ofstream f(path, std::ios::binary);
  f << sweep_csv(rows);
  f.close();
  if (!f) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

}  // namespace accuracy
