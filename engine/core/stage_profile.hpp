// Named stage timers (steady clock) kept per scan and in total, with counters
// summed over scans and levels (sizes after a scan, such as the metric map's
// bytes) kept per scan, printable as a table and as the profile.json that
// `sarmap run` writes:
//   {"version": 1, "units": "s", "scans": N, "wall_s": ..., "scans_per_second": ...,
//    "stages": {"<name>": {"total_s", "mean_s", "p50_s", "p95_s", "max_s", <counters>,
//                          <level>, <level>_max}},
//    "latency": {"mean_s", "p50_s", "p95_s", "max_s"},
//    "per_scan": [{"<name>_s": ..., "latency_s": ..., "<name>_<level>": ...}, ...],
//    "skipped_scans": N, "skipped": [{"scan", "source", "error"}, ...]}
#pragma once

#include <chrono>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/state_stream.hpp"

namespace sarmap {

inline constexpr int kProfileFormatVersion = 1;

class StageProfile {
 public:
  struct StageStats {
    double total_s = 0, mean_s = 0, p50_s = 0, p95_s = 0, max_s = 0;
    std::size_t scans = 0;  // scans in which the stage ran
  };

  // Times a stage until destroyed, then adds the time to the current scan.
  class ScopedTimer {
   public:
    ScopedTimer(StageProfile& profile, std::string_view stage);
    ~ScopedTimer();
    ScopedTimer(const ScopedTimer&) = delete;
    ScopedTimer& operator=(const ScopedTimer&) = delete;

   private:
    StageProfile& profile_;
    std::string stage_;
    std::chrono::steady_clock::time_point start_;
  };

  // Starts a new per-scan row; times added before the first call open one.
  void begin_scan();
  ScopedTimer time(std::string_view stage) { return ScopedTimer(*this, stage); }
  void add_time(std::string_view stage, double seconds);
  // The current scan's latency, from the start of its read to the end of its
  // last stage, where that is not the sum of its stage times (stages of
  // consecutive scans overlapping, Mapper::integrate_stream). Rows without
  // one count their stage times' sum.
  void set_latency(double seconds);
  // Appends `scans`' rows (with their latencies and levels) and adds its counters: the
  // profile of scans timed apart, e.g. one scan in flight while another is.
  void append(const StageProfile& scans);
  // Adds to a named counter of a stage (points in, rays cast, ...), summed over scans.
  void add_count(std::string_view stage, std::string_view counter, double value);
  // Sets a level of a stage for the current scan: a size after the scan (the
  // metric map's bytes), not summed. A scan that does not set it leaves no
  // value in its row.
  void set_level(std::string_view stage, std::string_view level, double value);
  // Records a scan the run skipped (unreadable, or refused by a stage) and
  // drops its per-scan row when one is open for it; the first
  // kMaxListedSkips are listed with their errors, all are counted.
  void skip_scan(std::size_t index, std::string_view source, std::string_view error, bool row_open);
  std::size_t skipped_scans() const { return skipped_count_; }
  // Whole-run wall time, I/O included; scans_per_second derives from it.
  void set_wall_seconds(double seconds) { wall_s_ = seconds; }

  std::size_t scan_count() const { return latency_.size(); }
  double wall_seconds() const { return wall_s_; }
  // Stage names in the order they were first timed.
  const std::vector<std::string>& stage_names() const { return order_; }
  StageStats stats(std::string_view stage) const;
  // Per-scan latency (set_latency, or the row's sum of stage times).
  StageStats latency() const;
  double counter(std::string_view stage, std::string_view counter) const;
  struct LevelStats {
    double last = 0, max = 0;  // over the scans that set the level; 0 if none did
    std::size_t scans = 0;
  };
  LevelStats level(std::string_view stage, std::string_view level) const;

  std::string table() const;
  std::string json() const;

  // Every row, counter and skip, for a checkpoint (state_stream.hpp): a
  // resumed run's profile goes on counting where the saved one stopped.
  void save_state(StateWriter& out) const;
  // Throws sarmap::Error (Parse) naming the offset; unchanged then.
  void load_state(StateReader& in);

 private:
  std::size_t stage_index(std::string_view stage);
  // The index of a stage's level, added (with no value in any row) if new.
  std::size_t level_index(std::size_t stage, std::string_view level);
  double row_latency(std::size_t scan) const;
  double time_at(std::size_t scan, std::size_t stage) const { return times_[scan * order_.size() + stage]; }
  double& time_at(std::size_t scan, std::size_t stage) { return times_[scan * order_.size() + stage]; }
  double level_at(std::size_t scan, std::size_t level) const {
    return level_values_[scan * levels_.size() + level];
  }
  double& level_at(std::size_t scan, std::size_t level) { return level_values_[scan * levels_.size() + level]; }

  // The per-scan rows are kept in one array each, row after row, not an
  // array per scan: small arrays made at every scan and kept for the whole
  // run sit between the stages' large transient ones and keep the heap
  // from reusing or returning that space (docs/perf-history.md).
  std::vector<std::string> order_;
  std::vector<double> times_;    // [scan * stages + stage] seconds
  std::vector<double> latency_;  // [scan] seconds, 0: the row's sum; one per row
  std::vector<std::map<std::string, double>> counters_;  // [stage]
  // Levels by (stage index, name), in the order first set, and their values
  // per scan, NaN where a scan did not set one.
  struct Level {
    std::size_t stage;
    std::string name;
  };
  std::vector<Level> levels_;
  std::vector<double> level_values_;  // [scan * levels + level]
  double wall_s_ = 0;
  struct SkippedScan {
    std::size_t index;
    std::string source;
    std::string error;
  };
  static constexpr std::size_t kMaxListedSkips = 100;
  std::vector<SkippedScan> skipped_;
  std::size_t skipped_count_ = 0;
};

}  // namespace sarmap
