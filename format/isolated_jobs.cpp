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
// Plain fields: the parent reads a slot only after waitpid, which orders the child's writes.
struct JobSlot {
  int32_t state;
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

// In a new child: the budget's signals kill, its timers run, its memory is capped (mapped: the
// address space the parent had, measured before the fork so the child calls no stdio).
void enter_budget(double cpu_seconds, uint64_t memory, uint64_t mapped) {
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
  (void)mapped;  // unused under AddressSanitizer
#if !defined(PBRTA_ASAN)
  if (mapped > 0) {
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0) {
      const uint64_t want = mapped + memory;
      if (as.rlim_cur == RLIM_INFINITY || as.rlim_cur > want) {
        as.rlim_cur = want;
        setrlimit(RLIMIT_AS, &as);
      }
    }
  }
#endif
  // Outputs passed back through a file are bounded the same way; with SIGXFSZ ignored, a write
  // past the bound fails with a message instead of killing the child.
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

// What stopped a child whose job did not report (waited: whether status is known).
std::string stop_reason(bool waited, int status, double cpu_seconds) {
  if (!waited) return "the decoder's process could not be waited for";
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

// At most 8 children, whatever the thread count: each may use its memory budget.
constexpr int kMaxProcesses = 8;

Groups make_groups(const std::vector<uint64_t>& input_bytes, int processes) {
  const size_t count =
      std::min<size_t>(input_bytes.size(), size_t(std::clamp(processes, 1, kMaxProcesses)));
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

}  // namespace

void set_isolation_enabled(bool enabled) {
  g_enabled.store(enabled);
}
bool isolation_enabled() {
  return g_enabled.load();
}

namespace {

// All of n bytes, retrying short and interrupted transfers; false on an error or end of file.
template <typename Transfer>
bool transfer_all(Transfer io, size_t n) {
  size_t done = 0;
  while (done < n) {
    const ssize_t got = io(done);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    done += size_t(got);
  }
  return true;
}

}  // namespace

void run_isolated_blobs(const std::vector<uint64_t>& input_bytes, int processes,
                        const IsolationBudget& budget, const IsolatedBlobWork& work,
                        std::vector<std::vector<uint8_t>>* outputs,
                        std::vector<std::string>* errors, std::vector<char>* by_job) {
  const size_t n = input_bytes.size();
  errors->assign(n, std::string());
  outputs->assign(n, std::vector<uint8_t>());
  std::vector<char> own;
  if (by_job == nullptr) by_job = &own;
  by_job->assign(n, 0);
  if (n == 0) return;
  const Groups groups = make_groups(input_bytes, processes);
  const size_t count = groups.jobs.size();
  // A job run in this process instead: every job when isolation is off or the memory files or
  // the slots cannot be had, a group's jobs when no child can be had for it.
  auto run_here = [&](const std::vector<size_t>& list) {
    const Job here = [&](size_t k, std::string* why) { return work(k, &(*outputs)[k], why); };
    for (size_t k : list) (*by_job)[k] = !run_one(here, k, &(*errors)[k]);
  };
  // Each group's outputs go into a memory file of its own, back to back in job order: their
  // sizes are known only once they are made. Each job's state and message go into its slot.
  std::vector<int> file_of_group(count, -1);
  bool ready = isolation_enabled();
  for (size_t g = 0; g < count; ++g) {
    if (ready) file_of_group[g] = memfd_create("pbrta-isolated", MFD_CLOEXEC);
    ready = ready && file_of_group[g] >= 0;
  }
  auto close_files = [&] {
    for (int fd : file_of_group)
      if (fd >= 0) close(fd);
  };
  const uint64_t mapped = round_up(n * sizeof(JobSlot));
  void* shared =
      ready ? mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0)
            : MAP_FAILED;
  if (shared == MAP_FAILED) {
    for (const std::vector<size_t>& list : groups.jobs) run_here(list);
    close_files();
    return;
  }
  auto* slots = static_cast<JobSlot*>(shared);  // zero-filled: every state kPending
#if !defined(PBRTA_ASAN)
  const uint64_t mapped_now = mapped_bytes();
#else
  const uint64_t mapped_now = 0;
#endif
  std::vector<pid_t> pids(count, -1);
  std::vector<double> seconds(count);
  for (size_t g = 0; g < count; ++g) {
    seconds[g] = budget.base_seconds + budget.seconds_per_byte * double(groups.load[g]);
    const pid_t pid = fork();
    if (pid == 0) {
      enter_budget(seconds[g], budget.base_memory + budget.memory_per_byte * groups.load[g],
                   mapped_now);
      const int fd = file_of_group[g];
      for (size_t k : groups.jobs[g]) {
        JobSlot& slot = slots[k];
        slot.state = kRunning;
        std::string why;
        const bool ok = run_one(
            [&](size_t j, std::string* e) {
              std::vector<uint8_t> blob;
              if (!work(j, &blob, e)) return false;
              const off_t at = lseek(fd, 0, SEEK_END);
              errno = 0;
              if (at < 0 || !transfer_all(
                                [&](size_t done) {
                                  return pwrite(fd, blob.data() + done, blob.size() - done,
                                                at + off_t(done));
                                },
                                blob.size())) {
                *e = "cannot pass the output back: " +
                     std::string(errno != 0 ? std::strerror(errno) : "short write");
                if (at >= 0 && ftruncate(fd, at) != 0) _exit(1);  // later outputs: misplaced
                return false;
              }
              slot.blob_offset = uint64_t(at);
              slot.blob_size = blob.size();
              return true;
            },
            k, &why);
        if (!ok) {
          const size_t len = std::min(why.size(), sizeof(slot.message) - 1);
          std::memcpy(slot.message, why.data(), len);
          slot.message[len] = '\0';
        }
        slot.state = ok ? kDone : kFailed;
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
    pid_t got;
    while ((got = waitpid(pids[g], &status, 0)) < 0 && errno == EINTR) {
    }
    bool stopped = false;  // a job of this group did not finish: the later ones never started
    uint64_t next = 0;     // where the group's next output must start, read in job order
    const int fd = file_of_group[g];
    const uint64_t cap = budget.base_memory + budget.memory_per_byte * groups.load[g];
    for (size_t k : groups.jobs[g]) {
      // The child may have been subverted by what it decoded: its slot is read once, its
      // message only up to the slot's end, and its output only where the file holds it.
      const JobSlot slot = slots[k];
      std::string& why = (*errors)[k];
      if (slot.state == kDone) {
        struct stat st {};
        std::vector<uint8_t>& out = (*outputs)[k];
        if (fstat(fd, &st) != 0 || slot.blob_offset != next || slot.blob_size > cap ||
            slot.blob_size > uint64_t(st.st_size) - std::min(uint64_t(st.st_size), next)) {
          why = "the decoder's output is not where it said";
        } else {
          try {
            out.resize(slot.blob_size);
            if (transfer_all(
                    [&](size_t done) {
                      return pread(fd, out.data() + done, out.size() - done,
                                   off_t(slot.blob_offset + done));
                    },
                    out.size()))
              next += slot.blob_size;
            else
              why = "cannot read the decoder's output back";
          } catch (const std::bad_alloc&) {
            why = "out of memory";
          }
          if (!why.empty()) out.clear();
        }
      } else if (slot.state == kFailed) {
        why.assign(slot.message, strnlen(slot.message, sizeof slot.message));
        if (why.empty()) why = "failed";
        (*by_job)[k] = 1;
      } else if (!stopped) {
        why = stop_reason(got == pids[g], status, seconds[g]);
        stopped = true;
      } else {
        why = "not decoded: an earlier stream in the same process failed to finish";
      }
    }
  }
  munmap(shared, mapped);
  close_files();
}

}  // namespace pbrta
