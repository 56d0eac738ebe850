// runtime/render/stop_flags.cpp — see stop_flags.h.
#include "runtime/render/stop_flags.h"

#include <cmath>
#include <csignal>
#include <cstdlib>

namespace rt {
namespace {

std::atomic<bool> g_interrupted{false};
volatile std::sig_atomic_t g_signal = 0;

void on_signal(int sig) {
  if (g_interrupted.exchange(true)) {  // the second one: stop now
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_signal = sig;
}

// The number at the front of text, and what follows it; false when there is none.
bool leading_number(const std::string& text, double* value, std::string* rest) {
  if (text.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !std::isfinite(*value)) return false;
  *rest = end;
  return true;
}

}  // namespace

bool parse_duration(const std::string& text, double* seconds) {
  double v;
  std::string unit;
  if (!leading_number(text, &v, &unit)) return false;
  const double scale = unit.empty() || unit == "s" ? 1 : unit == "m" ? 60 : unit == "h" ? 3600 : 0;
  if (scale == 0 || !(v > 0)) return false;
  *seconds = v * scale;
  return true;
}

bool parse_percent(const std::string& text, double* fraction) {
  double v;
  std::string unit;
  if (!leading_number(text, &v, &unit) || !(unit.empty() || unit == "%")) return false;
  if (!(v > 0 && v <= 1000)) return false;
  *fraction = v / 100;
  return true;
}

bool parse_stop_value(const std::string& flag, const std::string& text, double* value,
                      std::string* error) {
  if (flag == "target-error") {
    if (parse_percent(text, value)) return true;
    *error = "--target-error needs a percentage above 0, such as 1 or 0.5%, not \"" + text + "\"";
    return false;
  }
  if (parse_duration(text, value)) return true;
  *error = "--" + flag + " needs a duration such as 90, 90s, 10m or 1h, not \"" + text + "\"";
  return false;
}

const std::atomic<bool>* install_interrupt_handlers() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  return &g_interrupted;
}

int interrupt_signal() {
  return int(g_signal);
}

}  // namespace rt
