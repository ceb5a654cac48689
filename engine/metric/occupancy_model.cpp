#include "engine/metric/occupancy_model.hpp"

#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::metric {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw Error(ErrorCode::InvalidArgument, "occupancy settings: " + what);
}
}  // namespace

std::int16_t OccupancyModel::quantise(double probability) {
  return static_cast<std::int16_t>(std::lround(std::log(probability / (1.0 - probability)) * kLogOddsScale));
}

double OccupancyModel::probability(std::int16_t log_odds) {
  if (log_odds == kUnknownLogOdds) return 0.5;
  return 1.0 - 1.0 / (1.0 + std::exp(static_cast<double>(log_odds) / kLogOddsScale));
}

OccupancyModel::OccupancyModel(const OccupancySettings& s) : settings_(s) {
  const auto in_open_unit = [](double p) { return p > 0.0 && p < 1.0; };
  require(in_open_unit(s.prob_hit) && s.prob_hit > 0.5,
          "prob_hit must be in (0.5, 1), got " + std::to_string(s.prob_hit));
  require(in_open_unit(s.prob_miss) && s.prob_miss < 0.5,
          "prob_miss must be in (0, 0.5), got " + std::to_string(s.prob_miss));
  require(in_open_unit(s.clamp_min) && s.clamp_min <= s.prob_miss,
          "clamp_min must be in (0, prob_miss], got " + std::to_string(s.clamp_min));
  require(in_open_unit(s.clamp_max) && s.clamp_max >= s.prob_hit,
          "clamp_max must be in [prob_hit, 1), got " + std::to_string(s.clamp_max));
  require(in_open_unit(s.occupied_threshold),
          "occupied_threshold must be in (0, 1), got " + std::to_string(s.occupied_threshold));
  // In 1/32 nat any probability a double holds in (0, 1) fits int16
  // (|log-odds| < 745), so quantising comes before the limits are checked.
  hit_ = quantise(s.prob_hit);
  miss_ = quantise(s.prob_miss);
  min_ = quantise(s.clamp_min);
  max_ = quantise(s.clamp_max);
  threshold_ = quantise(s.occupied_threshold);
  // The map stores log-odds in one byte (semantic_voxel.hpp).
  const double limit = kMaxStoredLogOdds / kLogOddsScale;
  require(max_ <= kMaxStoredLogOdds,
          "clamp_max must be at most " + std::to_string(1 / (1 + std::exp(-limit))) + " (log-odds " +
              std::to_string(limit) + ": the map stores log-odds in one byte), got " + std::to_string(s.clamp_max));
  require(min_ >= -kMaxStoredLogOdds,
          "clamp_min must be at least " + std::to_string(1 / (1 + std::exp(limit))) + " (log-odds -" +
              std::to_string(limit) + ": the map stores log-odds in one byte), got " + std::to_string(s.clamp_min));
  // In units of 1/32 nat a hit or miss this close to 0.5 would change nothing.
  require(hit_ > 0, "prob_hit must be at least 0.504 (log-odds 1/64: smaller steps round to none), got " +
                        std::to_string(s.prob_hit));
  require(miss_ < 0, "prob_miss must be at most 0.496 (log-odds -1/64: smaller steps round to none), got " +
                         std::to_string(s.prob_miss));
}

}  // namespace sarmap::metric
