// wake_workers() and usable_threads() under a thread limit: an enqueued task
// makes oneTBB lend the arena a worker even where a global_control allows
// one thread ("mandatory concurrency"), and that worker then joins the
// caller's parallel loops. So with one thread allowed the wake must not
// enqueue: `sarmap run --threads 1` ran its metric stage on two threads
// until it did not.
#include "engine/core/wake_workers.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <mutex>
#include <set>
#include <thread>

namespace sarmap {
namespace {

// The threads that ran a parallel loop of short sleeps started right after a
// wake, over a few rounds (a lent worker needs a moment to arrive).
std::set<std::thread::id> threads_after_wakes() {
  std::mutex m;
  std::set<std::thread::id> seen;
  for (int round = 0; round < 10; ++round) {
    wake_workers();
    tbb::parallel_for(0, 32, [&](int) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      const std::lock_guard<std::mutex> lock(m);
      seen.insert(std::this_thread::get_id());
    });
  }
  return seen;
}

TEST(WakeWorkers, KeepsToAThreadLimitOfOne) {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  EXPECT_EQ(usable_threads(), 1u);
  EXPECT_EQ(threads_after_wakes().size(), 1u);
}

TEST(WakeWorkers, UsableThreadsFollowTheArenaAndTheLimit) {
  const std::size_t all = usable_threads();
  EXPECT_GE(all, 1u);
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_EQ(usable_threads(), 1u);
  }
  tbb::task_arena single(1);
  single.execute([] { EXPECT_EQ(usable_threads(), 1u); });
  EXPECT_EQ(usable_threads(), all);
}

}  // namespace
}  // namespace sarmap
