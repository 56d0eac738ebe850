// format/isolated_jobs.h — runs untrusted decoding in child processes, within a budget of time
// and memory.
//
// Why: Draco's decoder can be driven to seconds of work and hundreds of MB by a few forged bytes
// deep in its stream, where no check made before Draco runs can see them (format/draco_codec.h),
// and a bug in it would crash whoever called it. No timer can stop a function mid-call, but the
// kernel can stop a process: each child decodes its share of the jobs into memory shared with
// the caller and is killed when it runs past its budget. The caller's process never runs the
// untrusted code, so it can neither hang nor crash on it.
//
// Budget: a child gets base_seconds plus seconds_per_byte for each input byte of its jobs, in CPU
// time (SIGPROF), and four times that plus 10 s in wall time (SIGALRM, in case it blocks); the
// defaults allow about 20 times what Draco needs on this project's machine. Its address space may
// grow by base_memory plus memory_per_byte per input byte (RLIMIT_AS, so an allocation past it
// fails as out of memory; not set under AddressSanitizer, whose shadow memory that would break).
// A budget that grows with the input makes the cost of a hostile file proportional to its size,
// like any decoder's, however many streams it holds: the jobs of one child share one budget.
//
// Cost: one fork per child. Jobs are spread over at most `processes` children (and never more
// than 8) by input bytes (largest first, each to the least loaded child), and run in ascending
// order within a child: a caller that numbers its jobs in the order it reports failures sees the
// job that stopped a child before the ones that child never started.
//
// set_isolation_enabled(false) makes run_isolated_blobs call the jobs on this thread instead, with
// no budget: for fuzzers, whose coverage counters and crash reports must stay in their own process.
// fork failing (EAGAIN, ENOMEM) falls back to the same.
//
// Thread safety: any number of threads may call these at once (pbrtc decodes .drc files on every
// thread); each call forks and waits for its own children. A child runs only the thread that
// forked it, so a job must not need a lock another thread may hold at the fork: glibc's allocator
// is safe (fork takes its locks), as is C++ exception unwinding with GCC 12 and glibc 2.35 on
// (lock-free _dl_find_object). Were a job to block on such a lock, the wall-clock limit ends it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pbrta {

struct IsolationBudget {
  double base_seconds = 1.0;
  double seconds_per_byte = 5e-6;
  uint64_t base_memory = uint64_t{1} << 30;
  uint64_t memory_per_byte = 512;
};

// Job k: fills *out with its output, of a size only it knows; false with one message in *error.
using IsolatedBlobWork =
    std::function<bool(size_t k, std::vector<uint8_t>* out, std::string* error)>;

// Runs every job, one per entry of input_bytes (what its budget grows with): each child appends
// its jobs' outputs to a memory file (memfd) of its own, within its memory budget, and
// (*outputs)[k] receives job k's bytes. The caller checks them as it would any untrusted input: a
// child may have been subverted by what it decoded. (*errors)[k] is left empty for a job that
// succeeded; otherwise it holds the job's own message, or what stopped its child: "decoding ran
// past its budget of 1.2 s of CPU time", "the decoder crashed (signal 11)", "not decoded: an
// earlier stream in the same process failed to finish". (*by_job)[k], when asked for, says the
// message is the job's own. A job's message is cut at 999 bytes.
void run_isolated_blobs(const std::vector<uint64_t>& input_bytes, int processes,
                        const IsolationBudget& budget, const IsolatedBlobWork& work,
                        std::vector<std::vector<uint8_t>>* outputs,
                        std::vector<std::string>* errors, std::vector<char>* by_job = nullptr);

// Process-wide switch (default true); see above.
void set_isolation_enabled(bool enabled);
bool isolation_enabled();

}  // namespace pbrta
