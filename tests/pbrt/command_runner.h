// tests/pbrt/command_runner.h — runs a built program as a user would, for the command tests.
//
// run_in(dir, command) runs a shell command line in dir, with XDG_CACHE_HOME=dir/cache so
// pbrt's cache never leaks between tests, and returns its exit status (-1 if it did not exit,
// e.g. it crashed), its stdout and stderr, and how long it took.
#pragma once

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "test_support.h"

namespace testing_support {

const std::string kBin = PBRTC_BINARY_DIR;

struct Outcome {
  int status = -1;
  std::string err, out;
  double seconds = 0;
};

inline Outcome run_in(const std::string& dir, const std::string& command,
                      const std::string& tag = "run") {
  std::string out = dir + "/" + tag + ".stdout", err = dir + "/" + tag + ".stderr";
  std::string line = "cd '" + dir + "' && XDG_CACHE_HOME='" + dir + "/cache' " + command + " > '" +
                     out + "' 2> '" + err + "'";
  auto t0 = std::chrono::steady_clock::now();
  int raw = std::system(line.c_str());
  Outcome r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.err = read_file(err);
  r.out = read_file(out);
  return r;
}

}  // namespace testing_support
