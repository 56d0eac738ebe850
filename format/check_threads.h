// format/check_threads.h — the threads SceneArchive's record checks run on (format/ only).
//
// One arena serves every check of a load, validate_records() and then validate_geometry(): a new
// arena for each woke the workers again, which cost 70 µs of the mesh checks of a 6 ms load of
// 100k shapes.
#pragma once

#include <optional>

#include <oneapi/tbb/task_arena.h>

namespace pbrta {

class CheckThreads {
 public:
  // threads: 1 for the calling thread alone, 0 for as many as the machine has.
  explicit CheckThreads(int threads) {
    if (threads != 1) arena_.emplace(threads > 0 ? threads : int(tbb::task_arena::automatic));
  }
  // nullptr when the checks run on the calling thread alone.
  tbb::task_arena* arena() { return arena_ ? &*arena_ : nullptr; }

 private:
  std::optional<tbb::task_arena> arena_;
};

}  // namespace pbrta
