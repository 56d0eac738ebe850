// tests/format/isolated_jobs_test.cpp — format/isolated_jobs.h: jobs run in child processes and
// their outputs come back; a job that spins, crashes or over-allocates costs its budget and a
// message, never the caller; the jobs of a stopped child are accounted for; switched off, the
// jobs run in this process.
#include "format/isolated_jobs.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbrta {
namespace {

// A job of a known output size and input bytes (what its budget grows with).
struct Job {
  uint64_t out_size, input_bytes;
};

// run_isolated_blobs over jobs whose work fills out_size bytes at out.
std::vector<std::vector<uint8_t>> run_sized(
    const std::vector<Job>& jobs, int processes, const IsolationBudget& budget,
    const std::function<bool(size_t, uint8_t*, std::string*)>& work,
    std::vector<std::string>* errors, std::vector<char>* by_job = nullptr) {
  std::vector<uint64_t> input;
  for (const Job& j : jobs) input.push_back(j.input_bytes);
  std::vector<std::vector<uint8_t>> outputs;
  run_isolated_blobs(
      input, processes, budget,
      [&](size_t k, std::vector<uint8_t>* out, std::string* error) {
        out->assign(jobs[k].out_size, 0);
        return work(k, out->data(), error);
      },
      &outputs, errors, by_job);
  return outputs;
}

// Job k writes its output's bytes as k + 1, and the pid it ran in after them.

bool fill(size_t k, uint8_t* out, uint64_t size) {
  const pid_t pid = getpid();
  std::memset(out, int(k + 1), size - sizeof pid);
  std::memcpy(out + size - sizeof pid, &pid, sizeof pid);
  return true;
}

pid_t pid_in(const std::vector<uint8_t>& b) {
  pid_t pid;
  std::memcpy(&pid, b.data() + b.size() - sizeof pid, sizeof pid);
  return pid;
}

TEST(IsolatedJobs, OutputsComeBackFromOtherProcesses) {
  ASSERT_TRUE(isolation_enabled());
  std::vector<char> by_job;
  std::vector<Job> jobs;
  for (uint64_t k = 0; k < 7; ++k) jobs.push_back(Job{100 + 1000 * k, 10 * k});
  std::vector<std::string> errors;
  const auto out = run_sized(
      jobs, 2, IsolationBudget{},
      [&](size_t k, uint8_t* out, std::string* error) {
        if (k == 3) {
          *error = "job 3 refuses";
          return false;
        }
        return fill(k, out, jobs[k].out_size);
      },
      &errors, &by_job);
  ASSERT_EQ(errors.size(), jobs.size());
  EXPECT_EQ(by_job, std::vector<char>({0, 0, 0, 1, 0, 0, 0}));
  std::vector<pid_t> pids;
  for (size_t k = 0; k < jobs.size(); ++k) {
    SCOPED_TRACE(k);
    if (k == 3) {
      EXPECT_EQ(errors[k], "job 3 refuses");
      EXPECT_TRUE(out[k].empty());
      continue;
    }
    EXPECT_EQ(errors[k], "");
    EXPECT_EQ(out[k][0], k + 1);
    EXPECT_EQ(out[k][jobs[k].out_size - 1 - sizeof(pid_t)], k + 1);
    EXPECT_NE(pid_in(out[k]), getpid());
    pids.push_back(pid_in(out[k]));
  }
  // Two processes, the largest inputs first, each to the less loaded (the first on a tie):
  // 6 (60), 5 (50), 4 (90 with 5), 3 (90 with 6), 2 (110 with 6 and 3), then 1 and 0 with 5.
  EXPECT_EQ(pid_in(out[6]), pid_in(out[2]));
  EXPECT_EQ(pid_in(out[5]), pid_in(out[4]));
  EXPECT_EQ(pid_in(out[5]), pid_in(out[1]));
  EXPECT_EQ(pid_in(out[5]), pid_in(out[0]));
  EXPECT_NE(pid_in(out[6]), pid_in(out[5]));
}

TEST(IsolatedJobs, ARunawayJobCostsItsBudgetAndTheRestOfItsProcess) {
  const std::vector<Job> jobs(4, Job{64, 1000});
  std::vector<char> by_job;
  IsolationBudget budget;
  budget.base_seconds = 0.2;
  budget.seconds_per_byte = 1e-4;  // 0.2 s + 0.2 s for the 2000 bytes of each child's jobs
  std::vector<std::string> errors;
  const auto out = run_sized(
      jobs, 2, budget,
      [&](size_t k, uint8_t* to, std::string* error) {
        if (k == 0) {
          // Bounded, so that a fork failure (which runs the job here) fails the test instead of
          // hanging it.
          const auto start = std::chrono::steady_clock::now();
          while (std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
          }
          *error = "spun for 20 s";
          return false;
        }
        return fill(k, to, 64);
      },
      &errors, &by_job);
  // Equal inputs: jobs 0 and 2 in one child, 1 and 3 in the other.
  EXPECT_EQ(errors[0],
            "decoding ran past its budget of 0.4 s of CPU time (a forged or damaged stream)");
  EXPECT_EQ(errors[2], "not decoded: an earlier stream in the same process failed to finish");
  EXPECT_EQ(errors[1], "");
  EXPECT_EQ(errors[3], "");
  EXPECT_EQ(out[3][0], 4);
  EXPECT_EQ(by_job, std::vector<char>(4, 0));  // the messages are the runner's, not the jobs'
}

#if !defined(__SANITIZE_ADDRESS__)  // AddressSanitizer turns the signal into exit status 1
TEST(IsolatedJobs, ACrashIsTheChildsAlone) {
  const std::vector<Job> jobs(2, Job{64, 10});
  std::vector<std::string> errors;
  const auto out = run_sized(
      jobs, 1, IsolationBudget{},
      [&](size_t k, uint8_t* to, std::string*) {
        if (k == 1) raise(SIGSEGV);
        return fill(k, to, 64);
      },
      &errors);
  EXPECT_EQ(errors[0], "");
  EXPECT_EQ(out[0][0], 1);
  EXPECT_EQ(errors[1].rfind("the decoder crashed (signal " + std::to_string(SIGSEGV), 0), 0u)
      << errors[1];
}

TEST(IsolatedJobs, MemoryPastTheBudgetIsOutOfMemory) {
  const std::vector<Job> jobs(2, Job{64, 1000});
  IsolationBudget budget;
  budget.base_memory = uint64_t{64} << 20;
  budget.memory_per_byte = 1024;  // 64 MiB + 2 MiB for the child's two jobs
  std::vector<std::string> errors;
  run_sized(
      jobs, 1, budget,
      [&](size_t k, uint8_t* to, std::string*) {
        if (k == 0) {
          std::vector<uint8_t> big(size_t{256} << 20, 1);  // throws std::bad_alloc
          to[0] = big[12345];
        }
        return fill(k, to, 64);
      },
      &errors);
  EXPECT_EQ(errors[0], "out of memory");
  EXPECT_EQ(errors[1], "");  // the child went on with its next job
}
#endif

// Outputs of sizes only the jobs know come back through each child's memory file, in order,
// around a failing job, an empty output and a job that stops its child.
TEST(IsolatedJobs, BlobsComeBackWhateverTheirSize) {
  const std::vector<uint64_t> input = {40, 30, 20, 10, 5, 1};
  IsolationBudget budget;
  budget.base_seconds = 0.3;
  budget.seconds_per_byte = 0;
  std::vector<std::vector<uint8_t>> outputs;
  std::vector<std::string> errors;
  std::vector<char> by_job;
  run_isolated_blobs(
      input, 2, budget,
      [&](size_t k, std::vector<uint8_t>* out, std::string* error) {
        if (k == 2) {
          *error = "job 2 refuses";
          return false;
        }
        if (k == 5) {  // the last job of its child: nothing after it to be left undone
          const auto start = std::chrono::steady_clock::now();
          while (std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
          }
          return false;
        }
        const pid_t pid = getpid();
        out->assign(k == 4 ? 0 : 100000 * (k + 1), uint8_t(k + 1));
        if (k != 4) std::memcpy(out->data(), &pid, sizeof pid);
        return true;
      },
      &outputs, &errors, &by_job);
  // Children: jobs 0, 3 and 4 (40 + 10 + 5 bytes); jobs 1, 2 and 5 (30 + 20 + 1).
  EXPECT_EQ(errors[2], "job 2 refuses");
  EXPECT_EQ(errors[5],
            "decoding ran past its budget of 0.3 s of CPU time (a forged or damaged stream)");
  EXPECT_EQ(by_job, std::vector<char>({0, 0, 1, 0, 0, 0}));  // job 5's message is the runner's
  for (size_t k : {size_t(0), size_t(1), size_t(3)}) {
    SCOPED_TRACE(k);
    EXPECT_EQ(errors[k], "");
    ASSERT_EQ(outputs[k].size(), 100000 * (k + 1));
    EXPECT_EQ(outputs[k].back(), k + 1);
    pid_t pid;
    std::memcpy(&pid, outputs[k].data(), sizeof pid);
    EXPECT_NE(pid, getpid());
  }
  EXPECT_EQ(errors[4], "");
  EXPECT_TRUE(outputs[4].empty());
}

TEST(IsolatedJobs, SwitchedOffTheJobsRunHere) {
  set_isolation_enabled(false);
  const std::vector<Job> jobs(3, Job{64, 10});
  std::vector<std::string> errors;
  const auto out = run_sized(
      jobs, 2, IsolationBudget{},
      [&](size_t k, uint8_t* to, std::string* error) {
        if (k == 2) throw std::runtime_error("thrown by job 2");
        (void)error;
        return fill(k, to, 64);
      },
      &errors);
  set_isolation_enabled(true);
  EXPECT_EQ(errors[0], "");
  EXPECT_EQ(pid_in(out[0]), getpid());
  EXPECT_EQ(pid_in(out[1]), getpid());
  EXPECT_EQ(errors[2], "thrown by job 2");
}

}  // namespace
}  // namespace pbrta
