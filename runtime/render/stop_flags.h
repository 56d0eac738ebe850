// runtime/render/stop_flags.h — the stopping flags' values, as pbrtrun and pbrt read them,
// and the signal handling that turns Ctrl-C into "stop and write what is done".
//
// parse_duration: "90", "90s", "2.5m", "1h" (seconds, minutes, hours) to seconds > 0.
// parse_percent: "1", "1%", "0.5%" (percent) to a fraction in (0, 1000%].
// parse_stop_value: the value of --target-error (a percent), --time-limit or
// --checkpoint-every (durations), flag named without its dashes; false with the
// message pbrtrun and pbrt print ("--time-limit needs a duration such as ...").
// install_interrupt_handlers: SIGINT and SIGTERM set the returned flag (the renderer
// finishes nothing more and the image so far is written); a second one of either
// ends the process at once, as the default action would. interrupt_signal() says
// which arrived (0: none), for the exit code 128 + signal.
#pragma once

#include <atomic>
#include <string>

namespace rt {

bool parse_duration(const std::string& text, double* seconds);
bool parse_percent(const std::string& text, double* fraction);
bool parse_stop_value(const std::string& flag, const std::string& text, double* value,
                      std::string* error);

const std::atomic<bool>* install_interrupt_handlers();
int interrupt_signal();

}  // namespace rt
