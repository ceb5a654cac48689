#include "engine/eval/voxel_scores.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"

namespace sarmap::eval {
namespace {

std::optional<double> ratio(std::size_t part, std::size_t whole) {
  if (whole == 0) return std::nullopt;
  return static_cast<double>(part) / static_cast<double>(whole);
}

std::optional<double> harmonic_mean(const std::optional<double>& p, const std::optional<double>& r) {
  if (!p || !r) return std::nullopt;
  if (*p + *r == 0) return 0.0;
  return 2 * *p * *r / (*p + *r);
}

sim::VoxelKey truth_key(const metric::VoxelKey& k) { return {k.x, k.y, k.z}; }
metric::VoxelKey map_key(const sim::VoxelKey& k) { return {k.x, k.y, k.z}; }

// Whether `hit` holds for the key or one of its 26 neighbours.
template <class Key, class Pred>
bool near(const Key& k, Pred&& hit) {
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (hit(Key{k.x + dx, k.y + dy, k.z + dz})) return true;
      }
    }
  }
  return false;
}

}  // namespace

std::optional<double> VoxelScores::precision() const { return ratio(occupied_correct, map_occupied); }
std::optional<double> VoxelScores::recall() const { return ratio(observed_found, truth_observed); }
std::optional<double> VoxelScores::f1() const { return harmonic_mean(precision(), recall()); }
std::optional<double> VoxelScores::precision_within_1() const {
  return ratio(occupied_correct_within_1, map_occupied);
}
std::optional<double> VoxelScores::recall_within_1() const {
  return ratio(observed_found_within_1, truth_observed);
}
std::optional<double> VoxelScores::f1_within_1() const {
  return harmonic_mean(precision_within_1(), recall_within_1());
}
std::optional<double> VoxelScores::free_accuracy() const { return ratio(free_found, truth_free); }
std::optional<double> VoxelScores::free_precision() const { return ratio(map_free_truth_free, map_free); }
std::optional<double> VoxelScores::class_accuracy() const { return classes.accuracy(); }

VoxelScores score_voxels(const metric::MetricMap& map, const sim::GroundTruthGrid& truth) {
  if (!(std::abs(map.resolution() - truth.resolution) <= 1e-9)) {
    throw Error(ErrorCode::InvalidArgument,
                "voxel scores: the map's resolution (" + std::to_string(map.resolution()) +
                    " m) differs from the ground truth's (" + std::to_string(truth.resolution) + " m)");
  }
  VoxelScores s;
  s.resolution = map.resolution();
  s.truth_occupied = truth.occupied.size();
  s.truth_free = truth.free.size();
  const auto truth_occupied = [&truth](const sim::VoxelKey& k) { return truth.occupied.count(k) > 0; };

  // Map side: every known voxel once.
  const metric::OccupancyModel& occupancy = map.occupancy();
  map.blocks().for_each_block(
      [&](const metric::BlockKey& block, const metric::MetricMap::Blocks::Block& voxels) {
        for (int i = 0; i < metric::kBlockVoxels; ++i) {
          const metric::VoxelState state = occupancy.state(voxels.log_odds(i));
          if (state == metric::VoxelState::Unknown) continue;
          const sim::VoxelKey key = truth_key(metric::voxel_of(block, i));
          if (state == metric::VoxelState::Free) {
            ++s.map_free;
            if (truth.free.count(key)) ++s.map_free_truth_free;
            if (truth_occupied(key)) ++s.map_free_on_surface;
            continue;
          }
          ++s.map_occupied;
          const auto it = truth.occupied.find(key);
          if (it != truth.occupied.end()) {
            ++s.occupied_correct;
            ++s.occupied_correct_within_1;
            // A truth voxel without a class (no labelled area) cannot be scored.
            if (it->second.label != ClassId::Unknown) {
              s.classes.add(it->second.label, metric::LabelFusion::dominant(voxels.evidence(i)));
            }
          } else if (near(key, truth_occupied)) {
            ++s.occupied_correct_within_1;
          }
        }
      });

  // Truth side.
  const auto map_occupied = [&map](const metric::VoxelKey& k) {
    return map.state(k) == metric::VoxelState::Occupied;
  };
  for (const auto& [key, voxel] : truth.occupied) {
    if (!voxel.observed) continue;
    ++s.truth_observed;
    const metric::VoxelKey k = map_key(key);
    if (map_occupied(k)) {
      ++s.observed_found;
      ++s.observed_found_within_1;
    } else if (near(k, map_occupied)) {
      ++s.observed_found_within_1;
    }
  }
  for (const sim::VoxelKey& key : truth.free) {
    if (map.state(map_key(key)) == metric::VoxelState::Free) ++s.free_found;
  }
  return s;
}

namespace {

nlohmann::ordered_json number_or_null(const std::optional<double>& v) {
  return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
}

std::string percent(const std::optional<double>& v) {
  if (!v) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f%%", 100.0 * *v);
  return text;
}

}  // namespace

void add_voxel_scores_json(const VoxelScores& s, nlohmann::ordered_json& out) {
  out["voxel_resolution"] = s.resolution;
  out["voxel_precision"] = number_or_null(s.precision());
  out["voxel_recall"] = number_or_null(s.recall());
  out["voxel_f1"] = number_or_null(s.f1());
  out["voxel_precision_within_1"] = number_or_null(s.precision_within_1());
  out["voxel_recall_within_1"] = number_or_null(s.recall_within_1());
  out["voxel_f1_within_1"] = number_or_null(s.f1_within_1());
  out["free_accuracy"] = number_or_null(s.free_accuracy());
  out["free_precision"] = number_or_null(s.free_precision());
  out["voxel_class_accuracy"] = number_or_null(s.class_accuracy());
  nlohmann::ordered_json counts;
  counts["map_occupied"] = s.map_occupied;
  counts["map_free"] = s.map_free;
  counts["truth_occupied"] = s.truth_occupied;
  counts["truth_observed"] = s.truth_observed;
  counts["truth_free"] = s.truth_free;
  counts["occupied_correct"] = s.occupied_correct;
  counts["occupied_correct_within_1"] = s.occupied_correct_within_1;
  counts["observed_found"] = s.observed_found;
  counts["observed_found_within_1"] = s.observed_found_within_1;
  counts["free_found"] = s.free_found;
  counts["map_free_truth_free"] = s.map_free_truth_free;
  counts["map_free_on_surface"] = s.map_free_on_surface;
  counts["class_scored"] = s.classes.total();
  out["voxel_counts"] = counts;
  nlohmann::ordered_json classes = nlohmann::ordered_json::array();
  nlohmann::ordered_json matrix = nlohmann::ordered_json::array();
  for (std::size_t t = 0; t < kClassCount; ++t) {
    classes.push_back(kClassTable[t].name);
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (std::size_t p = 0; p < kClassCount; ++p) {
      row.push_back(s.classes.count(static_cast<ClassId>(t), static_cast<ClassId>(p)));
    }
    matrix.push_back(row);
  }
  out["voxel_class_confusion"] = {
      {"classes", classes}, {"rows", "ground truth"}, {"columns", "map"}, {"matrix", matrix}};
}

std::string format_voxel_scores(const VoxelScores& s) {
  std::ostringstream out;
  char line[200];
  std::snprintf(line, sizeof line,
                "metric map voxels at %.3f m: %zu occupied, %zu free in the map; truth %zu occupied (%zu "
                "observed), %zu free\n",
                s.resolution, s.map_occupied, s.map_free, s.truth_occupied, s.truth_observed, s.truth_free);
  out << line;
  std::snprintf(line, sizeof line, "  %-22s %10s %16s\n", "", "strict", "within 1 voxel");
  out << line;
  const auto row = [&](const char* name, const std::optional<double>& strict,
                       const std::optional<double>& near1) {
    std::snprintf(line, sizeof line, "  %-22s %10s %16s\n", name, percent(strict).c_str(),
                  percent(near1).c_str());
    out << line;
  };
  row("occupied precision", s.precision(), s.precision_within_1());
  row("occupied recall", s.recall(), s.recall_within_1());
  row("occupied F1", s.f1(), s.f1_within_1());
  out << "  free accuracy          " << percent(s.free_accuracy())
      << " of truth free voxels are free in the map\n";
  out << "  free precision         " << percent(s.free_precision())
      << " of the map's free voxels are truth free (" << s.map_free_on_surface << " hold a surface)\n";
  out << "  class accuracy         " << percent(s.class_accuracy()) << " of " << s.classes.total()
      << " matched occupied voxels\n";
  return out.str();
}

}  // namespace sarmap::eval
