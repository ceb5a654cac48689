#include "engine/core/stage_profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

namespace sarmap {

StageProfile::ScopedTimer::ScopedTimer(StageProfile& profile, std::string_view stage)
    : profile_(profile), stage_(stage), start_(std::chrono::steady_clock::now()) {}

StageProfile::ScopedTimer::~ScopedTimer() {
  const auto elapsed = std::chrono::steady_clock::now() - start_;
  profile_.add_time(stage_, std::chrono::duration<double>(elapsed).count());
}

namespace {
constexpr double kNoLevel = std::numeric_limits<double>::quiet_NaN();

// Rows of `width` values, one after the other, given one more column
// (holding `fill`) at the end of each row.
void add_column(std::vector<double>& rows, std::size_t row_count, std::size_t width, double fill) {
  std::vector<double> wider(row_count * (width + 1), fill);
  for (std::size_t r = 0; r < row_count; ++r) {
    std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(r * width), width,
                wider.begin() + static_cast<std::ptrdiff_t>(r * (width + 1)));
  }
  rows = std::move(wider);
}
}  // namespace

void StageProfile::begin_scan() {
  times_.resize(times_.size() + order_.size(), 0.0);
  latency_.push_back(0.0);
  level_values_.resize(level_values_.size() + levels_.size(), kNoLevel);
}

void StageProfile::set_latency(double seconds) {
  if (latency_.empty()) begin_scan();
  latency_.back() = seconds;
}

void StageProfile::append(const StageProfile& scans) {
  std::vector<std::size_t> index(scans.order_.size());
  for (std::size_t i = 0; i < scans.order_.size(); ++i) index[i] = stage_index(scans.order_[i]);
  std::vector<std::size_t> level_index(scans.levels_.size());
  for (std::size_t l = 0; l < scans.levels_.size(); ++l) {
    level_index[l] = this->level_index(index[scans.levels_[l].stage], scans.levels_[l].name);
  }
  for (std::size_t r = 0; r < scans.scan_count(); ++r) {
    begin_scan();
    const std::size_t row = scan_count() - 1;
    for (std::size_t i = 0; i < scans.order_.size(); ++i) time_at(row, index[i]) += scans.time_at(r, i);
    latency_.back() = scans.latency_[r];
    for (std::size_t l = 0; l < scans.levels_.size(); ++l) level_at(row, level_index[l]) = scans.level_at(r, l);
  }
  for (std::size_t i = 0; i < scans.order_.size(); ++i) {
    for (const auto& [name, value] : scans.counters_[i]) counters_[index[i]][name] += value;
  }
}

double StageProfile::row_latency(std::size_t scan) const {
  if (latency_[scan] > 0) return latency_[scan];
  double sum = 0;
  for (std::size_t i = 0; i < order_.size(); ++i) sum += time_at(scan, i);
  return sum;
}

std::size_t StageProfile::stage_index(std::string_view stage) {
  for (std::size_t i = 0; i < order_.size(); ++i) {
    if (order_[i] == stage) return i;
  }
  add_column(times_, scan_count(), order_.size(), 0.0);
  order_.emplace_back(stage);
  counters_.emplace_back();
  return order_.size() - 1;
}

void StageProfile::add_time(std::string_view stage, double seconds) {
  const std::size_t i = stage_index(stage);
  if (latency_.empty()) begin_scan();
  time_at(scan_count() - 1, i) += seconds;
}

std::size_t StageProfile::level_index(std::size_t stage, std::string_view level) {
  std::size_t l = 0;
  while (l < levels_.size() && !(levels_[l].stage == stage && levels_[l].name == level)) ++l;
  if (l == levels_.size()) {
    add_column(level_values_, scan_count(), levels_.size(), kNoLevel);
    levels_.push_back({stage, std::string(level)});
  }
  return l;
}

void StageProfile::set_level(std::string_view stage, std::string_view level, double value) {
  const std::size_t l = level_index(stage_index(stage), level);
  if (latency_.empty()) begin_scan();
  level_at(scan_count() - 1, l) = value;
}

void StageProfile::skip_scan(std::size_t index, std::string_view source, std::string_view error, bool row_open) {
  if (row_open && !latency_.empty()) {
    times_.resize(times_.size() - order_.size());
    latency_.pop_back();
    level_values_.resize(level_values_.size() - levels_.size());
  }
  ++skipped_count_;
  if (skipped_.size() < kMaxListedSkips) skipped_.push_back({index, std::string(source), std::string(error)});
}

void StageProfile::add_count(std::string_view stage, std::string_view counter, double value) {
  counters_[stage_index(stage)][std::string(counter)] += value;
}

namespace {
// Nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}
}  // namespace

namespace {
StageProfile::StageStats stats_of(std::vector<double> values) {
  StageProfile::StageStats s;
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  for (double v : values) s.total_s += v;
  s.scans = values.size();
  s.mean_s = s.total_s / static_cast<double>(values.size());
  s.p50_s = percentile(values, 0.50);
  s.p95_s = percentile(values, 0.95);
  s.max_s = values.back();
  return s;
}
}  // namespace

StageProfile::StageStats StageProfile::stats(std::string_view stage) const {
  const auto it = std::find(order_.begin(), order_.end(), stage);
  if (it == order_.end()) return {};
  const auto i = static_cast<std::size_t>(it - order_.begin());
  std::vector<double> values(scan_count());
  for (std::size_t r = 0; r < values.size(); ++r) values[r] = time_at(r, i);
  return stats_of(std::move(values));
}

StageProfile::StageStats StageProfile::latency() const {
  std::vector<double> values(scan_count());
  for (std::size_t r = 0; r < values.size(); ++r) values[r] = row_latency(r);
  return stats_of(std::move(values));
}

double StageProfile::counter(std::string_view stage, std::string_view counter) const {
  const auto it = std::find(order_.begin(), order_.end(), stage);
  if (it == order_.end()) return 0.0;
  const auto& counters = counters_[static_cast<std::size_t>(it - order_.begin())];
  const auto c = counters.find(std::string(counter));
  return c == counters.end() ? 0.0 : c->second;
}

StageProfile::LevelStats StageProfile::level(std::string_view stage, std::string_view level) const {
  LevelStats s;
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    if (order_[levels_[l].stage] != stage || levels_[l].name != level) continue;
    for (std::size_t r = 0; r < scan_count(); ++r) {
      const double v = level_at(r, l);
      if (std::isnan(v)) continue;
      s.max = s.scans == 0 ? v : std::max(s.max, v);
      s.last = v;
      ++s.scans;
    }
  }
  return s;
}

std::string StageProfile::table() const {
  std::ostringstream out;
  char line[160];
  std::snprintf(line, sizeof line, "%-16s %10s %10s %10s %10s %10s\n", "stage", "total s", "mean ms",
                "p50 ms", "p95 ms", "max ms");
  out << line;
  for (const auto& name : order_) {
    const StageStats s = stats(name);
    std::snprintf(line, sizeof line, "%-16s %10.3f %10.3f %10.3f %10.3f %10.3f\n", name.c_str(),
                  s.total_s, s.mean_s * 1e3, s.p50_s * 1e3, s.p95_s * 1e3, s.max_s * 1e3);
    out << line;
  }
  const StageStats l = latency();
  std::snprintf(line, sizeof line, "%-16s %10s %10.3f %10.3f %10.3f %10.3f\n", "latency per scan", "", l.mean_s * 1e3,
                l.p50_s * 1e3, l.p95_s * 1e3, l.max_s * 1e3);
  out << line;
  std::snprintf(line, sizeof line, "%zu scans in %.3f s wall (%.2f scans/s)\n", scan_count(), wall_s_,
                wall_s_ > 0 ? static_cast<double>(scan_count()) / wall_s_ : 0.0);
  out << line;
  return out.str();
}

std::string StageProfile::json() const {
  nlohmann::ordered_json j;
  j["version"] = kProfileFormatVersion;
  j["units"] = "s";
  j["scans"] = scan_count();
  j["wall_s"] = wall_s_;
  j["scans_per_second"] = wall_s_ > 0 ? static_cast<double>(scan_count()) / wall_s_ : 0.0;
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < order_.size(); ++i) {
    const StageStats s = stats(order_[i]);
    nlohmann::ordered_json st;
    st["total_s"] = s.total_s;
    st["mean_s"] = s.mean_s;
    st["p50_s"] = s.p50_s;
    st["p95_s"] = s.p95_s;
    st["max_s"] = s.max_s;
    for (const auto& [name, value] : counters_[i]) st[name] = value;
    for (const Level& level : levels_) {
      if (level.stage != i) continue;
      const LevelStats l = this->level(order_[i], level.name);
      st[level.name] = l.last;
      st[level.name + "_max"] = l.max;
    }
    stages[order_[i]] = st;
  }
  j["stages"] = stages;
  const StageStats l = latency();
  j["latency"] = {{"mean_s", l.mean_s}, {"p50_s", l.p50_s}, {"p95_s", l.p95_s}, {"max_s", l.max_s}};
  nlohmann::ordered_json per_scan = nlohmann::ordered_json::array();
  for (std::size_t scan = 0; scan < scan_count(); ++scan) {
    nlohmann::ordered_json r;
    for (std::size_t i = 0; i < order_.size(); ++i) r[order_[i] + "_s"] = time_at(scan, i);
    r["latency_s"] = row_latency(scan);
    for (std::size_t l = 0; l < levels_.size(); ++l) {
      const double v = level_at(scan, l);
      if (!std::isnan(v)) r[order_[levels_[l].stage] + "_" + levels_[l].name] = v;
    }
    per_scan.push_back(r);
  }
  j["per_scan"] = per_scan;
  j["skipped_scans"] = skipped_count_;
  nlohmann::ordered_json skipped = nlohmann::ordered_json::array();
  for (const SkippedScan& s : skipped_) {
    skipped.push_back({{"scan", s.index}, {"source", s.source}, {"error", s.error}});
  }
  j["skipped"] = skipped;
  return j.dump(2);
}

void StageProfile::save_state(StateWriter& out) const {
  out.tag("PROF");
  out.put<std::uint64_t>(order_.size());
  for (const std::string& name : order_) out.put_string(name);
  // Row by row, each as an array of its own: the layout of earlier checkpoints.
  const auto put_rows = [&](const std::vector<double>& rows, std::size_t width) {
    for (std::size_t r = 0; r < scan_count(); ++r) {
      const auto first = rows.begin() + static_cast<std::ptrdiff_t>(r * width);
      out.put_vector(std::vector<double>(first, first + static_cast<std::ptrdiff_t>(width)));
    }
  };
  out.put<std::uint64_t>(scan_count());
  put_rows(times_, order_.size());
  out.put_vector(latency_);
  for (const std::map<std::string, double>& counters : counters_) {
    out.put<std::uint64_t>(counters.size());
    for (const auto& [name, value] : counters) {
      out.put_string(name);
      out.put(value);
    }
  }
  out.put<std::uint64_t>(levels_.size());
  for (const Level& level : levels_) {
    out.put<std::uint64_t>(level.stage);
    out.put_string(level.name);
  }
  put_rows(level_values_, levels_.size());
  out.put(wall_s_);
  out.put<std::uint64_t>(skipped_.size());
  for (const SkippedScan& s : skipped_) {
    out.put<std::uint64_t>(s.index);
    out.put_string(s.source);
    out.put_string(s.error);
  }
  out.put<std::uint64_t>(skipped_count_);
}

void StageProfile::load_state(StateReader& in) {
  in.expect_tag("PROF");
  std::vector<std::string> order(in.get_count(8));
  for (std::string& name : order) name = in.get_string();
  const std::size_t rows = in.get_count(8);
  // A row may name fewer stages than the profile (those after it: no time).
  std::vector<double> times;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::vector<double> row = in.get_vector<double>();
    if (row.size() > order.size()) in.fail("a profile row holds more stages than the profile names");
    times.insert(times.end(), row.begin(), row.end());
    times.resize(times.size() + order.size() - row.size(), 0.0);
  }
  std::vector<double> latency = in.get_vector<double>();
  if (latency.size() != rows) in.fail("the profile's latencies do not match its rows");
  std::vector<std::map<std::string, double>> counters(order.size());
  for (std::map<std::string, double>& stage : counters) {
    const std::size_t n = in.get_count(16);
    for (std::size_t i = 0; i < n; ++i) {
      std::string name = in.get_string();
      stage[std::move(name)] = in.get<double>();
    }
  }
  std::vector<Level> levels(in.get_count(16));
  for (Level& level : levels) {
    level.stage = static_cast<std::size_t>(in.get<std::uint64_t>());
    if (level.stage >= order.size()) in.fail("a profile level names a stage the profile does not");
    level.name = in.get_string();
  }
  std::vector<double> level_values;
  for (std::size_t r = 0; r < rows; ++r) {
    const std::vector<double> row = in.get_vector<double>();
    if (row.size() != levels.size()) in.fail("a profile row of levels does not hold one value per level");
    level_values.insert(level_values.end(), row.begin(), row.end());
  }
  const auto wall_s = in.get<double>();
  std::vector<SkippedScan> skipped(in.get_count(24));
  for (SkippedScan& s : skipped) {
    s.index = static_cast<std::size_t>(in.get<std::uint64_t>());
    s.source = in.get_string();
    s.error = in.get_string();
  }
  const auto skipped_count = in.get<std::uint64_t>();
  order_ = std::move(order);
  times_ = std::move(times);
  latency_ = std::move(latency);
  counters_ = std::move(counters);
  levels_ = std::move(levels);
  level_values_ = std::move(level_values);
  wall_s_ = wall_s;
  skipped_ = std::move(skipped);
  skipped_count_ = static_cast<std::size_t>(skipped_count);
}

}  // namespace sarmap
