#include "engine/topo/topo_map.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/core/capacity_bytes.hpp"
#include "engine/core/flat_key_map.hpp"
#include "engine/topo/spanning_forest.hpp"

namespace sarmap::topo {
namespace {

using KeyTuple = std::tuple<int, std::int64_t, std::int64_t, std::int64_t>;

KeyTuple tuple_of(const PlaceKey& k) { return {static_cast<int>(k.type), k.a, k.b, k.c}; }

bool keyed_by_segment(const PlaceKey& k) { return k.type != PlaceKey::Type::Lattice; }

std::uint64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  constexpr std::int64_t kHalf = std::int64_t{1} << 20;
  return static_cast<std::uint64_t>((x + kHalf) & 0x1fffff) | (static_cast<std::uint64_t>((y + kHalf) & 0x1fffff) << 21) |
         (static_cast<std::uint64_t>((z + kHalf) & 0x1fffff) << 42);
}

}  // namespace

TopoMap::TopoMap(const TopoSettings& settings) : settings_(settings) { validate(settings_); }
TopoMap::~TopoMap() = default;
TopoMap::TopoMap(TopoMap&&) noexcept = default;
TopoMap& TopoMap::operator=(TopoMap&&) noexcept = default;

std::size_t TopoMap::memory_bytes() const {
  return capacity_bytes(nodes_) + capacity_bytes(edges_) + grid_.memory_bytes() + voxels_.memory_bytes() +
         columns_.memory_bytes() + grid_scratch_.memory_bytes() +
         (walls_ ? sizeof(WallScene) + walls_->memory_bytes() : 0);
}

TopoUpdate TopoMap::update(const segments::SegmentMap& segment_map, const metric::MetricMap& map,
                           const Bounds* changed) {
  const std::vector<const segments::Segment*> segments = segment_map.segments();
  const ColumnRect reread = voxels_.refresh(map, changed);
  voxels_.columns(map.resolution(), columns_);
  update_traversability_grid(grid_, columns_, settings_, reread, grid_scratch_);
  if (walls_ == nullptr) walls_ = std::make_unique<WallScene>(settings_);
  walls_->rebuild(segments, &columns_, &reread);
  last_ = TopoUpdate();
  last_.wall_boxes = walls_->boxes().size();

  // Places keyed by a segment follow it through merges.
  std::map<KeyTuple, std::uint32_t> by_key;
  for (TopoNode& node : nodes_) {
    if (keyed_by_segment(node.key)) {
      if (const auto survivor = segment_map.resolve(static_cast<std::uint32_t>(node.key.a))) node.key.a = *survivor;
    }
    by_key.emplace(tuple_of(node.key), node.id);  // the lower id keeps a key two nodes now share
  }
  std::vector<bool> seen(nodes_.size(), false);
  for (const Place& place : place_nodes(segments, grid_, *walls_, settings_)) {
    const auto [it, added] = by_key.emplace(tuple_of(place.key), static_cast<std::uint32_t>(nodes_.size()));
    if (added) {
      TopoNode node;
      node.id = static_cast<std::uint32_t>(nodes_.size());
      node.key = place.key;
      nodes_.push_back(node);
      seen.push_back(false);
      ++last_.nodes_added;
    }
    TopoNode& node = nodes_[it->second];
    if (seen[node.id]) continue;  // one place per key
    seen[node.id] = true;
    node.position = place.position;
    node.kind = place.kind;
    node.segment = place.segment;
  }
  for (TopoNode& node : nodes_) {
    if (node.alive && !seen[node.id]) ++last_.nodes_retired;
    node.alive = seen[node.id];
    last_.nodes += node.alive;
  }
  connect();
  return last_;
}

TopoMap TopoMap::restore(const TopoSettings& settings, std::vector<TopoNode> nodes, std::vector<TopoEdge> edges,
                         const std::vector<const segments::Segment*>& segments, const metric::MetricMap& map) {
  TopoMap topo(settings);
  const VoxelColumns columns = voxel_columns(map);
  topo.grid_ = traversability_grid(columns, settings);
  topo.walls_ = std::make_unique<WallScene>(segments, &columns, settings);
  topo.nodes_ = std::move(nodes);
  topo.edges_ = std::move(edges);
  return topo;
}

GroundProfile TopoMap::check_drive(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const {
  GroundProfile profile = ground_profile(grid_, from, to, settings_);
  const bool open = profile.verdict == DriveVerdict::Passes || profile.verdict == DriveVerdict::Unknown;
  if (!open || walls_ == nullptr) return profile;
  const StandPair pair{from, to};
  std::uint8_t blocked = 0;
  walls_->blocked(std::span<const StandPair>(&pair, 1), std::span<std::uint8_t>(&blocked, 1));
  if (blocked) profile.verdict = DriveVerdict::Wall;
  return profile;
}

void TopoMap::connect() {
  // Candidate pairs: alive nodes within the edge radius, found through cells of that size.
  const double r = settings_.edge_radius;
  // Each cell's alive nodes.
  FlatKeyMap<std::vector<std::uint32_t>> cells(nodes_.size() + 16);
  auto cell_of = [r](double v) { return static_cast<std::int64_t>(std::floor(v / r)); };
  for (const TopoNode& node : nodes_) {
    if (!node.alive) continue;
    cells[cell_key(cell_of(node.position.x()), cell_of(node.position.y()), cell_of(node.position.z()))]
        .push_back(node.id);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (const TopoNode& node : nodes_) {
    if (!node.alive) continue;
    const Eigen::Vector3d& p = node.position;
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const std::vector<std::uint32_t>* members =
              cells.find(cell_key(cell_of(p.x()) + dx, cell_of(p.y()) + dy, cell_of(p.z()) + dz));
          if (members == nullptr) continue;
          for (std::uint32_t other : *members) {
            if (other > node.id && (nodes_[other].position - p).norm() <= r) pairs.emplace_back(node.id, other);
          }
        }
      }
    }
  }
  // A ramp's foot and top are always a candidate, however long the ramp.
  std::map<std::int64_t, std::uint32_t> feet;
  for (const TopoNode& node : nodes_) {
    if (node.alive && node.key.type == PlaceKey::Type::Foot) feet.emplace(node.key.a, node.id);
  }
  for (const TopoNode& node : nodes_) {
    if (!node.alive || node.key.type != PlaceKey::Type::Top) continue;
    const auto foot = feet.find(node.key.a);
    if (foot != feet.end()) pairs.emplace_back(std::min(foot->second, node.id), std::max(foot->second, node.id));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  last_.candidates = pairs.size();

  // The ground first (cheap, in parallel), then walls for what is left.
  std::vector<GroundProfile> profiles(pairs.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      profiles[k] = ground_profile(grid_, nodes_[pairs[k].first].position, nodes_[pairs[k].second].position, settings_);
    }
  });
  std::vector<StandPair> drives;
  std::vector<std::size_t> drive_of;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    // Unknown ground may be a wall's column: a wall is the better reason.
    if (profiles[k].verdict != DriveVerdict::Passes && profiles[k].verdict != DriveVerdict::Unknown) continue;
    drives.push_back({nodes_[pairs[k].first].position, nodes_[pairs[k].second].position});
    drive_of.push_back(k);
  }
  std::vector<std::uint8_t> blocked(drives.size());
  walls_->blocked(drives, blocked);
  for (std::size_t d = 0; d < drives.size(); ++d) {
    if (blocked[d]) profiles[drive_of[d]].verdict = DriveVerdict::Wall;
  }

  edges_.clear();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    switch (profiles[k].verdict) {
      case DriveVerdict::Passes: break;
      case DriveVerdict::Wall: ++last_.rejected_wall; continue;
      case DriveVerdict::Drop: ++last_.rejected_drop; continue;
      case DriveVerdict::Steep: ++last_.rejected_steep; continue;
      case DriveVerdict::Unknown: ++last_.rejected_unknown; continue;
    }
    TopoEdge e;
    e.a = pairs[k].first;
    e.b = pairs[k].second;
    e.length = (nodes_[e.b].position - nodes_[e.a].position).norm();
    e.slope_deg = profiles[k].slope_deg;
    e.ground = profiles[k].ground;
    edges_.push_back(e);
  }
  std::vector<WeightedEdge> weighted(edges_.size());
  for (std::size_t i = 0; i < edges_.size(); ++i) weighted[i] = {edges_[i].a, edges_[i].b, edges_[i].length};
  const SpanningForest forest = minimum_spanning_forest(nodes_.size(), weighted);
  for (EdgeId e : forest.edges) edges_[e].in_tree = true;
  last_.edges = edges_.size();
  last_.tree_edges = forest.edges.size();
  // Trees among alive nodes (retired ones are isolated and not counted).
  last_.components = last_.nodes - forest.edges.size();
}

}  // namespace sarmap::topo
