// Mapper::integrate_stream: scans read, classified and mapped one after the
// other, or overlapped in a oneTBB pipeline. The classify stage touches only
// the classifier and its scan, and hands the metric stage what it needs of
// the classifier (voxel_classes_from_point_map) before the next scan's
// classification starts; the maps' stages touch only the maps. Between them
// the metric stage's rays are traced (RayIntegrator::trace), which reads
// nothing of the maps, into the integrator's slot of the scan's place in
// flight. So consecutive scans in different filters share no state, and
// each filter still sees the scans in input order: the maps come out as in
// order.
#include <chrono>
#include <mutex>
#include <vector>

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Reads the next scan into `item`; false at the end of the input.
bool read_next(const Mapper::ScanReader& read, std::size_t frame, StreamedScan& item) {
  item = StreamedScan{};
  item.frame = frame;
  item.read_start_s = now_s();
  try {
    if (!read(frame, item.scan)) return false;
  } catch (const Error& e) {
    item.read_failed = true;
    item.error = e;
    return true;
  }
  item.profile.begin_scan();
  item.profile.add_time("read", now_s() - item.read_start_s);
  return true;
}

}  // namespace

void Mapper::integrate_stream(std::size_t first_frame, const ScanReader& read, const ScanDone& done,
                              StageOverlap overlap) {
  refuse_scans_if_merged();
  if (overlap == StageOverlap::On) {
    stream_overlapped(first_frame, read, done);
  } else {
    stream_in_order(first_frame, read, done);
  }
}

void Mapper::stream_in_order(std::size_t first_frame, const ScanReader& read, const ScanDone& done) {
  StreamedScan item;
  for (std::size_t frame = first_frame; read_next(read, frame, item); ++frame) {
    if (!item.read_failed) {
      try {
        const std::uint64_t number = classify_half(item.scan, item.profile, item.voxel_classes);
        maps_half(item.scan, number, item.profile, item.voxel_classes);
        item.mapped = true;
        item.profile.set_latency(now_s() - item.read_start_s);
        profile_.append(item.profile);
      } catch (const Error& e) {
        item.error = scan_error(item.scan, e);
      }
    }
    done(item);
  }
}

void Mapper::stream_overlapped(std::size_t first_frame, const ScanReader& read, const ScanDone& done) {
  // Two scans in flight: the next one is read and classified while the maps
  // take this one, and the one after is read only when this one is done (a
  // forgetting pass relies on it: kClassifierForgetLag). One slot per scan in
  // flight: each filter is serial and in order, so the tokens visit the
  // slots round robin.
  constexpr std::size_t kInFlight = kClassifierForgetLag;
  static_assert(kInFlight <= metric::RayIntegrator::kSlots, "a scan in flight traces into its own slot");
  std::vector<StreamedScan> slots(kInFlight);
  std::size_t next_frame = first_frame;
  // oneTBB runs one filter's calls, and one item's filters, in order, but
  // possibly on different threads, handing over through its own atomics:
  // inside Debian's libtbb, not built for ThreadSanitizer, and not reported
  // through ITT (tests/tsan_itt_collector.cpp). A mutex touched as each call
  // starts and ends shows ThreadSanitizer that order (a few uncontended
  // locks per scan).
  std::mutex handoff;
  // Touched as a call starts and again as it ends, also when the call throws
  // (an error from `done` or the reader): that last touch is what orders the
  // call's reads of the slot before this thread frees it.
  struct HandOver {
    std::mutex& m;
    explicit HandOver(std::mutex& mutex) : m(mutex) { const std::lock_guard<std::mutex> order(m); }
    ~HandOver() { const std::lock_guard<std::mutex> order(m); }
    HandOver(const HandOver&) = delete;
    HandOver& operator=(const HandOver&) = delete;
  };
  // Its closing touch comes last of all (oneTBB waits for every call before
  // it rethrows): before this thread reads the maps or frees the slots.
  const HandOver at_exit(handoff);
  const auto input = [&](tbb::flow_control& control) -> StreamedScan* {
    const HandOver order(handoff);
    StreamedScan& item = slots[(next_frame - first_frame) % kInFlight];
    if (!read_next(read, next_frame, item)) {
      control.stop();
      return nullptr;
    }
    ++next_frame;
    return &item;
  };
  // Each half runs isolated: a thread waiting inside one half's parallel
  // loop takes no task of the other half, whose per-thread scratch it could
  // otherwise enter twice.
  const auto classify = [&](StreamedScan* item) -> StreamedScan* {
    const HandOver order(handoff);
    if (!item->read_failed) {
      tbb::this_task_arena::isolate([&] {
        try {
          item->classify_number = classify_half(item->scan, item->profile, item->voxel_classes);
        } catch (const Error& e) {
          item->error = scan_error(item->scan, e);
        }
      });
    }
    return item;
  };
  // The rays of the next scan are traced while the maps take this one (the
  // overlap of RayIntegrator::integrate_sequence, which the benchmark
  // measures, for scans that arrive one by one).
  const auto trace = [&](StreamedScan* item) -> StreamedScan* {
    const HandOver order(handoff);
    if (!item->read_failed && !item->error) {
      tbb::this_task_arena::isolate([&] {
        try {
          const auto slot = static_cast<std::size_t>(item - slots.data());
          item->traced_rays = TracedRays{slot, trace_rays(item->scan, slot, item->profile)};
        } catch (const Error& e) {
          item->error = scan_error(item->scan, e);
        }
      });
    }
    return item;
  };
  const auto maps = [&](StreamedScan* item) {
    const HandOver order(handoff);
    if (!item->read_failed && !item->error) {
      tbb::this_task_arena::isolate([&] {
        try {
          maps_half(item->scan, item->classify_number, item->profile, item->voxel_classes, item->traced_rays);
          item->mapped = true;
          item->profile.set_latency(now_s() - item->read_start_s);
          profile_.append(item->profile);
        } catch (const Error& e) {
          item->error = scan_error(item->scan, e);
        }
      });
    }
    done(*item);
  };
  tbb::parallel_pipeline(
      kInFlight,
      tbb::make_filter<void, StreamedScan*>(tbb::filter_mode::serial_in_order, input) &
          tbb::make_filter<StreamedScan*, StreamedScan*>(tbb::filter_mode::serial_in_order, classify) &
          tbb::make_filter<StreamedScan*, StreamedScan*>(tbb::filter_mode::serial_in_order, trace) &
          tbb::make_filter<StreamedScan*, void>(tbb::filter_mode::serial_in_order, maps));
}

}  // namespace sarmap::pipeline
