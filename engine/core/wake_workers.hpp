// Wakes the calling thread's oneTBB worker threads ahead of a parallel
// stage that follows serial work. oneTBB's workers spin for a while after
// their last task and then sleep; a parallel loop that starts after they
// slept runs alone until one wakes, which on a virtual machine takes tens
// of microseconds (bench/metric/parallel_region_bench.cpp measures both).
// Called that long before the loop, with other work of the caller between,
// the wake-up no longer delays it. Does nothing with a single thread.
#pragma once

#include <tbb/task_arena.h>

namespace sarmap {

inline void wake_workers() {
  // An enqueued task wakes a sleeping worker; an empty one costs it nothing.
  if (tbb::this_task_arena::max_concurrency() > 1) tbb::this_task_arena::enqueue([] {});
}

}  // namespace sarmap
