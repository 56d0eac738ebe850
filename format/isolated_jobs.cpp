// format/isolated_jobs.cpp — see isolated_jobs.h.
#include "format/isolated_jobs.h"

#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
#define PBRTA_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PBRTA_ASAN 1
#endif
#endif

namespace pbrta {
namespace {

std::atomic<bool> g_enabled{true};

// What a child reports of each job, in the shared mapping. A message longer than the slot is cut.
enum : int32_t { kPending = 0, kRunning = 1, kDone = 2, kFailed = 3 };
struct JobSlot {
  std::atomic<int32_t> state;
  char message[1020];
};
static_assert(sizeof(JobSlot) == 1024);

constexpr uint64_t kAlign = 64;

uint64_t round_up(uint64_t v) {
  return (v + kAlign - 1) / kAlign * kAlign;
}

bool run_one(const IsolatedWork& work, size_t k, uint8_t* out, std::string* error) {
  try {
    return work(k, out, error);
  } catch (const std::bad_alloc&) {
    *error = "out of memory";
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "unknown exception";
  }
  return false;
}

void run_here(const std::vector<size_t>& group, const std::vector<uint8_t*>& dst,
              const IsolatedWork& work, std::vector<std::string>* errors) {
  for (size_t k : group) {
    std::string why;
    if (!run_one(work, k, dst[k], &why)) (*errors)[k] = why.empty() ? "failed" : why;
  }
}

timeval to_timeval(double seconds) {
  timeval t{};
  t.tv_sec = static_cast<time_t>(seconds);
  t.tv_usec = static_cast<suseconds_t>((seconds - double(t.tv_sec)) * 1e6);
  if (t.tv_sec == 0 && t.tv_usec == 0) t.tv_usec = 1;
  return t;
}

#if !defined(PBRTA_ASAN)
// The address space this process has mapped now, from /proc (0 when unknown).
uint64_t mapped_bytes() {
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return 0;
  unsigned long long pages = 0;
  const bool ok = std::fscanf(f, "%llu", &pages) == 1;
  std::fclose(f);
  return ok ? pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE)) : 0;
}
#endif

[[noreturn]] void child_main(const std::vector<size_t>& group, JobSlot* slots, uint8_t* outputs,
                             const std::vector<uint64_t>& offset, double cpu_seconds,
                             uint64_t memory, const IsolatedWork& work) {
  // The parent's handlers and mask are inherited: the budget's signals must kill.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(SIGPROF, &dfl, nullptr);
  sigaction(SIGALRM, &dfl, nullptr);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGPROF);
  sigaddset(&set, SIGALRM);
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  const rlimit no_core{0, 0};
  setrlimit(RLIMIT_CORE, &no_core);
#if !defined(PBRTA_ASAN)
  if (const uint64_t now = mapped_bytes(); now > 0) {
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0) {
      const uint64_t want = now + memory;
      if (as.rlim_cur == RLIM_INFINITY || as.rlim_cur > want) {
        as.rlim_cur = want;
        setrlimit(RLIMIT_AS, &as);
      }
    }
  }
#else
  (void)memory;
#endif
  // No core file from a crash here (RLIMIT_CORE alone does not stop a piped core_pattern).
  prctl(PR_SET_DUMPABLE, 0);
  itimerval cpu{};
  cpu.it_value = to_timeval(cpu_seconds);
  setitimer(ITIMER_PROF, &cpu, nullptr);
  itimerval wall{};
  wall.it_value = to_timeval(4 * cpu_seconds + 10);
  setitimer(ITIMER_REAL, &wall, nullptr);

  for (size_t k : group) {
    JobSlot& slot = slots[k];
    slot.state.store(kRunning);
    std::string why;
    const bool ok = run_one(work, k, outputs + offset[k], &why);
    if (!ok) {
      if (why.empty()) why = "failed";
      const size_t n = std::min(why.size(), sizeof(slot.message) - 1);
      std::memcpy(slot.message, why.data(), n);
      slot.message[n] = '\0';
    }
    slot.state.store(ok ? kDone : kFailed);
  }
  _exit(0);  // no atexit handlers, no flushing of the parent's stdio buffers
}

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", s);
  return buf;
}

// What stopped a child whose job did not report.
std::string stop_reason(int status, double cpu_seconds) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGPROF)
      return "decoding ran past its budget of " + seconds_text(cpu_seconds) +
             " s of CPU time (a forged or damaged stream)";
    if (sig == SIGALRM)
      return "decoding did not finish within " + seconds_text(4 * cpu_seconds + 10) + " s";
    if (sig == SIGKILL) return "the decoder was killed (out of memory?)";
    return "the decoder crashed (signal " + std::to_string(sig) + ": " + strsignal(sig) + ")";
  }
  return "the decoder's process exited with status " + std::to_string(WEXITSTATUS(status)) +
         " before finishing";
}

}  // namespace

void set_isolation_enabled(bool enabled) {
  g_enabled.store(enabled);
}
bool isolation_enabled() {
  return g_enabled.load();
}

void run_isolated(const std::vector<IsolatedJob>& jobs, const std::vector<uint8_t*>& dst,
                  int processes, const IsolationBudget& budget, const IsolatedWork& work,
                  std::vector<std::string>* errors) {
  errors->assign(jobs.size(), std::string());
  if (jobs.empty()) return;

  // Largest input first, each to the least loaded group; then each group in job order.
  const size_t count = std::min<size_t>(jobs.size(), size_t(std::max(processes, 1)));
  std::vector<size_t> by_size(jobs.size());
  for (size_t k = 0; k < jobs.size(); ++k) by_size[k] = k;
  std::stable_sort(by_size.begin(), by_size.end(),
                   [&](size_t a, size_t b) { return jobs[a].input_bytes > jobs[b].input_bytes; });
  std::vector<std::vector<size_t>> groups(count);
  std::vector<uint64_t> load(count, 0);
  for (size_t k : by_size) {
    const size_t g = size_t(std::min_element(load.begin(), load.end()) - load.begin());
    groups[g].push_back(k);
    load[g] += jobs[k].input_bytes;
  }
  for (std::vector<size_t>& g : groups) std::sort(g.begin(), g.end());

  if (!isolation_enabled()) {
    for (const std::vector<size_t>& g : groups) run_here(g, dst, work, errors);
    return;
  }

  // The shared mapping: the slots, then each job's output at a 64-byte boundary.
  std::vector<uint64_t> offset(jobs.size());
  uint64_t total = 0;
  for (size_t k = 0; k < jobs.size(); ++k) {
    offset[k] = total;
    total += round_up(jobs[k].out_size);  // the caller bounded the sizes
  }
  const uint64_t slots_bytes = round_up(jobs.size() * sizeof(JobSlot));
  const uint64_t mapped = slots_bytes + total;
  void* shared = mmap(nullptr, mapped, PROT_READ | PROT_WRITE,
                      MAP_SHARED | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (shared == MAP_FAILED) {
    for (const std::vector<size_t>& g : groups) run_here(g, dst, work, errors);
    return;
  }
  auto* slots = static_cast<JobSlot*>(shared);
  for (size_t k = 0; k < jobs.size(); ++k) new (&slots[k]) JobSlot{{kPending}, {}};
  uint8_t* outputs = static_cast<uint8_t*>(shared) + slots_bytes;

  std::vector<pid_t> pids(count, -1);
  std::vector<double> seconds(count);
  for (size_t g = 0; g < count; ++g) {
    seconds[g] = budget.base_seconds + budget.seconds_per_byte * double(load[g]);
    const uint64_t memory = budget.base_memory + budget.memory_per_byte * load[g];
    const pid_t pid = fork();
    if (pid == 0) child_main(groups[g], slots, outputs, offset, seconds[g], memory, work);
    pids[g] = pid;
  }
  for (size_t g = 0; g < count; ++g) {
    if (pids[g] < 0) {  // no process to be had: decode here rather than not at all
      run_here(groups[g], dst, work, errors);
      continue;
    }
    int status = 0;
    while (waitpid(pids[g], &status, 0) < 0 && errno == EINTR) {
    }
    bool stopped = false;  // a job of this group did not finish: the later ones never started
    for (size_t k : groups[g]) {
      const int32_t state = slots[k].state.load();
      if (state == kDone) {
        std::memcpy(dst[k], outputs + offset[k], jobs[k].out_size);
      } else if (state == kFailed) {
        (*errors)[k] = slots[k].message;
      } else if (!stopped) {
        (*errors)[k] = stop_reason(status, seconds[g]);
        stopped = true;
      } else {
        (*errors)[k] = "not decoded: an earlier stream in the same process failed to finish";
      }
    }
  }
  munmap(shared, mapped);
}

}  // namespace pbrta
