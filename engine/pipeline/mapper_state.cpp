// The Mapper's checkpoint state: each stage's own part, in stage order. The
// kept points' voxel keys are saved rather than recomputed: a key comes from
// the point as it arrived, and the stored float copy may round into another
// voxel.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "engine/metric/voxel_key.hpp"
#include "engine/pipeline/mapper.hpp"

namespace sarmap::pipeline {

void Mapper::save_state(StateWriter& out) const {
  out.tag("MAPR");
  out.put<std::uint8_t>(merged_ ? 1 : 0);
  out.put(stats_);
  out.put<std::uint64_t>(blocks_dropped_);
  out.put<std::uint64_t>(blocks_dropped_unforgotten_);
  out.put(classify_stages_);
  out.put<std::uint64_t>(classifier_forgets_.size());
  for (const ClassifierForget& pass : classifier_forgets_) {
    out.put(pass.at_classify);
    out.put_vector(pass.kept_blocks);
  }
  classifier_->save_state(out);
  map_.save_state(out);
  segments_.save_state(out);
  topo_.save_state(out);
  semantic_points_.save_state(out);
  // Each kept point's voxel key, in point order (the set itself has no order).
  std::vector<std::uint64_t> keys(semantic_points_.size());
  for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = semantic_key(i);
  out.put_vector(keys);
  profile_.save_state(out);
}

void Mapper::load_state(StateReader& in) {
  in.expect_tag("MAPR");
  const auto merged = in.get<std::uint8_t>();
  if (merged > 1) in.fail("the merged flag holds " + std::to_string(merged) + ", not 0 or 1");
  stats_ = in.get<metric::IntegrationStats>();
  blocks_dropped_ = static_cast<std::size_t>(in.get<std::uint64_t>());
  blocks_dropped_unforgotten_ = static_cast<std::size_t>(in.get<std::uint64_t>());
  classify_stages_ = in.get<std::uint64_t>();
  std::vector<ClassifierForget> forgets(in.get_count(16));
  for (ClassifierForget& pass : forgets) {
    pass.at_classify = in.get<std::uint64_t>();
    pass.kept_blocks = in.get_vector<std::uint64_t>();
    if (!std::is_sorted(pass.kept_blocks.begin(), pass.kept_blocks.end())) {
      in.fail("a pending forgetting pass's blocks are not sorted");
    }
  }
  classifier_forgets_ = std::move(forgets);
  classifier_->load_state(in);
  map_.load_state(in);
  segments_.load_state(in);
  topo_.load_state(in, segments_, map_);
  semantic_points_.load_state(in);
  std::vector<std::uint64_t> keys = in.get_vector<std::uint64_t>();
  if (keys.size() != semantic_points_.size()) {
    in.fail("the kept points hold " + std::to_string(semantic_points_.size()) + " points but " +
            std::to_string(keys.size()) + " voxel keys");
  }
  if (!keys.empty() && config_.semantic_points_voxel <= 0) {
    in.fail("the state holds kept points but semantic_points_voxel keeps none");
  }
  FlatKeySet semantic_keys(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (!metric::within_map_limits(semantic_points_.x()[i], semantic_points_.y()[i], semantic_points_.z()[i])) {
      in.fail("kept point " + std::to_string(i) + " lies beyond the map's limits");
    }
    if (keys[i] != semantic_key(i)) in.fail("kept point " + std::to_string(i) + " lies outside the voxel of its key");
    if (!semantic_keys.insert(keys[i])) in.fail("two kept points share a voxel key");
  }
  semantic_keys_ = std::move(semantic_keys);
  profile_.load_state(in);
  row_open_ = false;
  merged_ = merged == 1;
}

}  // namespace sarmap::pipeline
