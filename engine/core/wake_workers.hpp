// Wakes the calling thread's oneTBB worker threads ahead of a parallel
// stage that follows serial work. oneTBB's workers spin for a while after
// their last task and then sleep; a parallel loop that starts after they
// slept runs alone until one wakes, which on a virtual machine takes tens
// of microseconds (bench/metric/parallel_region_bench.cpp measures both).
// Called that long before the loop, with other work of the caller between,
// the wake-up no longer delays it. Does nothing where one thread is all
// the caller may use.
#pragma once

#include <tbb/task_arena.h>

#include "engine/core/usable_threads.hpp"

namespace sarmap {

inline void wake_workers() {
  // An enqueued task wakes a sleeping worker; an empty one costs it nothing.
  // Not under a limit of one thread: oneTBB then lends the arena a worker
  // for the enqueued task, which would join the caller's loops too.
  if (usable_threads() > 1) tbb::this_task_arena::enqueue([] {});
}

}  // namespace sarmap
