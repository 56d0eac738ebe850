// tests/pbrt/command_runner.h — runs a built program as a user would, for the command tests.
//
// run_in(dir, command) runs a shell command line in dir, with XDG_CACHE_HOME=dir/cache so
// pbrt's cache never leaks between tests, and returns its exit status (-1 if it did not exit,
// e.g. it crashed), its stdout and stderr, and how long it took. run_on_terminal does the same
// with stdout and stderr on a pseudo-terminal (what programs that draw progress only on a
// terminal show a user), both in `out`; a command still running after 60 s is killed.
// find_in_order checks that a program printed some lines in a given order.
#pragma once

#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <vector>

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

inline Outcome run_on_terminal(const std::string& dir, const std::string& command) {
  Outcome r;
  // Built before the fork: the child of a threaded process may only exec.
  const std::string line = "cd '" + dir + "' && XDG_CACHE_HOME='" + dir + "/cache' " + command;
  auto t0 = std::chrono::steady_clock::now();
  int master = -1;
  const pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
  if (pid < 0) {
    r.out = "run_on_terminal: cannot open a pseudo-terminal (forkpty failed)";
    return r;
  }
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Read until the terminal closes (EIO once the last writer exits).
  char buffer[4096];
  for (;;) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (elapsed > 60) {
      kill(-pid, SIGKILL);  // the shell's whole process group: forkpty made it a session leader
      break;
    }
    pollfd p{master, POLLIN, 0};
    if (poll(&p, 1, 1000) <= 0) continue;
    const ssize_t n = read(master, buffer, sizeof buffer);
    if (n <= 0) break;
    r.out.append(buffer, size_t(n));
  }
  close(master);
  int raw = 0;
  waitpid(pid, &raw, 0);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

// Finds each of `parts` in `text`, each after the one before, and returns where; an empty vector,
// with a test failure naming the part, when one is missing or out of order.
inline std::vector<size_t> find_in_order(const std::string& text,
                                         const std::vector<std::string>& parts) {
  std::vector<size_t> at;
  size_t from = 0;
  for (const std::string& part : parts) {
    const size_t k = text.find(part, from);
    if (k == std::string::npos) {
      ADD_FAILURE() << "missing, or not after the part before it: \"" << part << "\" in\n" << text;
      return {};
    }
    at.push_back(k);
    from = k + part.size();
  }
  return at;
}

}  // namespace testing_support
