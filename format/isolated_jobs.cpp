// format/isolated_jobs.cpp — see isolated_jobs.h.
#include "format/isolated_jobs.h"

#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
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
#include <functional>
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
  uint32_t unused;
  uint64_t blob_offset, blob_size;  // run_isolated_blobs: where the output is in the group's file
  char message[1000];
};
static_assert(sizeof(JobSlot) == 1024);

constexpr uint64_t kAlign = 64;

uint64_t round_up(uint64_t v) {
  return (v + kAlign - 1) / kAlign * kAlign;
}

// A job, whichever kind: true, or false with *error; exceptions become messages.
using Job = std::function<bool(size_t k, std::string* error)>;

bool run_one(const Job& job, size_t k, std::string* error) {
  try {
    if (job(k, error)) return true;
    if (error->empty()) *error = "failed";
  } catch (const std::bad_alloc&) {
    *error = "out of memory";
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "unknown exception";
  }
  return false;
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

// In a new child: the budget's signals kill, its timers run, its memory is capped.
void enter_budget(double cpu_seconds, uint64_t memory) {
  // The parent's handlers and mask are inherited.
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
#endif
  // Outputs passed back through a file are bounded the same way.
  // (ignoring SIGXFSZ makes a write past it fail with a message instead).
  const rlimit fsize{memory, memory};
  setrlimit(RLIMIT_FSIZE, &fsize);
  signal(SIGXFSZ, SIG_IGN);
  // No core file from a crash here (RLIMIT_CORE alone does not stop a piped core_pattern).
  prctl(PR_SET_DUMPABLE, 0);
  itimerval cpu{};
  cpu.it_value = to_timeval(cpu_seconds);
  setitimer(ITIMER_PROF, &cpu, nullptr);
  itimerval wall{};
  wall.it_value = to_timeval(4 * cpu_seconds + 10);
  setitimer(ITIMER_REAL, &wall, nullptr);
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

// The jobs spread over at most `processes` groups: largest input first, each to the least loaded
// group (the first on a tie); then each group in job order.
struct Groups {
  std::vector<std::vector<size_t>> jobs;
  std::vector<uint64_t> load;  // input bytes
};

Groups make_groups(const std::vector<uint64_t>& input_bytes, int processes) {
  const size_t count = std::min<size_t>(input_bytes.size(), size_t(std::max(processes, 1)));
  std::vector<size_t> by_size(input_bytes.size());
  for (size_t k = 0; k < by_size.size(); ++k) by_size[k] = k;
  std::stable_sort(by_size.begin(), by_size.end(),
                   [&](size_t a, size_t b) { return input_bytes[a] > input_bytes[b]; });
  Groups g;
  g.jobs.resize(count);
  g.load.assign(count, 0);
  for (size_t k : by_size) {
    const size_t i = size_t(std::min_element(g.load.begin(), g.load.end()) - g.load.begin());
    g.jobs[i].push_back(k);
    g.load[i] += input_bytes[k];
  }
  for (std::vector<size_t>& list : g.jobs) std::sort(list.begin(), list.end());
  return g;
}

// Runs the jobs of each group in a child of its own: in_child(k, slot, &why) there, then, here,
// collect(k, slot, why) for each job (why empty: it succeeded). here(k, &why) runs a job in this
// process instead, when isolation is off or no child can be had.
void run_groups(size_t num_jobs, const Groups& groups, const IsolationBudget& budget,
                const std::function<bool(size_t, JobSlot&, std::string*)>& in_child,
                const std::function<void(size_t, const JobSlot&, const std::string&)>& collect,
                const Job& here, std::vector<std::string>* errors) {
  auto run_here = [&](const std::vector<size_t>& list) {
    for (size_t k : list) run_one(here, k, &(*errors)[k]);
  };
  const uint64_t mapped = round_up(num_jobs * sizeof(JobSlot));
  void* shared = isolation_enabled() ? mmap(nullptr, mapped, PROT_READ | PROT_WRITE,
                                            MAP_SHARED | MAP_ANONYMOUS, -1, 0)
                                     : MAP_FAILED;
  if (shared == MAP_FAILED) {
    for (const std::vector<size_t>& list : groups.jobs) run_here(list);
    return;
  }
  auto* slots = static_cast<JobSlot*>(shared);  // zero-filled: every state kPending
  const size_t count = groups.jobs.size();
  std::vector<pid_t> pids(count, -1);
  std::vector<double> seconds(count);
  for (size_t g = 0; g < count; ++g) {
    seconds[g] = budget.base_seconds + budget.seconds_per_byte * double(groups.load[g]);
    const pid_t pid = fork();
    if (pid == 0) {
      enter_budget(seconds[g], budget.base_memory + budget.memory_per_byte * groups.load[g]);
      for (size_t k : groups.jobs[g]) {
        JobSlot& slot = slots[k];
        slot.state.store(kRunning);
        std::string why;
        const bool ok =
            run_one([&](size_t j, std::string* e) { return in_child(j, slot, e); }, k, &why);
        if (!ok) {
          const size_t n = std::min(why.size(), sizeof(slot.message) - 1);
          std::memcpy(slot.message, why.data(), n);
          slot.message[n] = '\0';
        }
        slot.state.store(ok ? kDone : kFailed);
      }
      _exit(0);  // no atexit handlers, no flushing of the parent's stdio buffers
    }
    pids[g] = pid;
  }
  for (size_t g = 0; g < count; ++g) {
    if (pids[g] < 0) {  // no process to be had: decode here rather than not at all
      run_here(groups.jobs[g]);
      continue;
    }
    int status = 0;
    while (waitpid(pids[g], &status, 0) < 0 && errno == EINTR) {
    }
    bool stopped = false;  // a job of this group did not finish: the later ones never started
    for (size_t k : groups.jobs[g]) {
      const JobSlot& slot = slots[k];
      const int32_t state = slot.state.load();
      if (state == kDone) {
        collect(k, slot, std::string());
      } else if (state == kFailed) {
        collect(k, slot, slot.message[0] != '\0' ? slot.message : "failed");
      } else if (!stopped) {
        collect(k, slot, stop_reason(status, seconds[g]));
        stopped = true;
      } else {
        collect(k, slot, "not decoded: an earlier stream in the same process failed to finish");
      }
    }
  }
  munmap(shared, mapped);
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
  std::vector<uint64_t> input(jobs.size());
  for (size_t k = 0; k < jobs.size(); ++k) input[k] = jobs[k].input_bytes;
  const Groups groups = make_groups(input, processes);
  const Job here = [&](size_t k, std::string* why) { return work(k, dst[k], why); };
  // The outputs, each at a 64-byte boundary of one shared mapping the children write into.
  std::vector<uint64_t> offset(jobs.size());
  uint64_t total = 0;
  for (size_t k = 0; k < jobs.size(); ++k) {
    offset[k] = total;
    total += round_up(jobs[k].out_size);  // the caller bounded the sizes
  }
  void* shared = isolation_enabled()
                     ? mmap(nullptr, std::max<uint64_t>(total, 1), PROT_READ | PROT_WRITE,
                            MAP_SHARED | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0)
                     : MAP_FAILED;
  if (shared == MAP_FAILED) {
    for (size_t k = 0; k < jobs.size(); ++k) run_one(here, k, &(*errors)[k]);
    return;
  }
  uint8_t* outputs = static_cast<uint8_t*>(shared);
  run_groups(
      jobs.size(), groups, budget,
      [&](size_t k, JobSlot&, std::string* why) { return work(k, outputs + offset[k], why); },
      [&](size_t k, const JobSlot&, const std::string& why) {
        if (why.empty())
          std::memcpy(dst[k], outputs + offset[k], jobs[k].out_size);
        else
          (*errors)[k] = why;
      },
      here, errors);
  munmap(shared, std::max<uint64_t>(total, 1));
}

void run_isolated_blobs(const std::vector<uint64_t>& input_bytes, int processes,
                        const IsolationBudget& budget, const IsolatedBlobWork& work,
                        std::vector<std::vector<uint8_t>>* outputs,
                        std::vector<std::string>* errors) {
  const size_t n = input_bytes.size();
  errors->assign(n, std::string());
  outputs->assign(n, std::vector<uint8_t>());
  if (n == 0) return;
  const Groups groups = make_groups(input_bytes, processes);
  const Job here = [&](size_t k, std::string* why) { return work(k, &(*outputs)[k], why); };
  // Each group's outputs go into a memory file of its own, appended in job order: their sizes
  // are known only once they are made.
  std::vector<int> files(n, -1);
  bool have_files = isolation_enabled();
  for (size_t g = 0; g < groups.jobs.size() && have_files; ++g) {
    const int fd = memfd_create("pbrta-isolated", MFD_CLOEXEC);
    if (fd < 0) have_files = false;
    for (size_t k : groups.jobs[g]) files[k] = fd;
  }
  auto close_files = [&] {
    std::vector<int> closed;
    for (int fd : files)
      if (fd >= 0 && std::find(closed.begin(), closed.end(), fd) == closed.end()) {
        close(fd);
        closed.push_back(fd);
      }
  };
  if (!have_files) {
    close_files();
    for (size_t k = 0; k < n; ++k) run_one(here, k, &(*errors)[k]);
    return;
  }
  run_groups(
      n, groups, budget,
      [&](size_t k, JobSlot& slot, std::string* why) {
        std::vector<uint8_t> blob;
        if (!work(k, &blob, why)) return false;
        const off_t at = lseek(files[k], 0, SEEK_END);
        size_t done = 0;
        while (at >= 0 && done < blob.size()) {
          const ssize_t w =
              pwrite(files[k], blob.data() + done, blob.size() - done, at + off_t(done));
          if (w <= 0) break;
          done += size_t(w);
        }
        if (at < 0 || done != blob.size()) {
          *why = "cannot pass the output back: " + std::string(std::strerror(errno));
          return false;
        }
        slot.blob_offset = uint64_t(at);
        slot.blob_size = blob.size();
        return true;
      },
      [&](size_t k, const JobSlot& slot, const std::string& why) {
        if (!why.empty()) {
          (*errors)[k] = why;
          return;
        }
        // The child wrote it; the sizes are checked against the file all the same.
        struct stat st {};
        std::vector<uint8_t>& out = (*outputs)[k];
        if (fstat(files[k], &st) != 0 || slot.blob_offset > uint64_t(st.st_size) ||
            slot.blob_size > uint64_t(st.st_size) - slot.blob_offset) {
          (*errors)[k] = "the decoder's output is not where it said";
          return;
        }
        out.resize(slot.blob_size);
        size_t done = 0;
        while (done < out.size()) {
          const ssize_t r =
              pread(files[k], out.data() + done, out.size() - done, off_t(slot.blob_offset + done));
          if (r <= 0) break;
          done += size_t(r);
        }
        if (done != out.size()) {
          out.clear();
          (*errors)[k] = "cannot read the decoder's output back";
        }
      },
      here, errors);
  close_files();
}

}  // namespace pbrta
