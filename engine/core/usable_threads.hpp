// How many threads the caller's oneTBB parallel loops may run on.
#pragma once

#include <algorithm>
#include <cstddef>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

namespace sarmap {

// The calling thread's arena's concurrency, as limited by a global_control
// (`sarmap run --threads`), which does not change an arena's own figure.
inline std::size_t usable_threads() {
  return std::min(static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()),
                  tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

}  // namespace sarmap
