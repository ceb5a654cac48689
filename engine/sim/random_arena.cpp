#include "engine/sim/random_arena.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/sim/ray_noise.hpp"

namespace sarmap::sim {
namespace {

using OrderedJson = nlohmann::ordered_json;

constexpr double kWallHeight = 1.2;
constexpr double kWallThickness = 0.1;
constexpr double kRobotRadius = 0.35;  // clearance the trajectory keeps
constexpr double kCell = 0.1;          // planning grid

// A counter-based generator: the same seed gives the same arena on any
// platform (std distributions are implementation-defined).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : key_(mix64(seed ^ 0x5A5A5A5A12345678ull)) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(key_, counter_++); }
  int integer(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(std::floor(uniform(0, 1) * (hi - lo + 1)));
  }

 private:
  std::uint64_t key_;
  std::uint64_t counter_ = 0;
};

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

struct Segment {
  Eigen::Vector2d a, b;
};

double distance_to_segment(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d d = s.b - s.a;
  const double len2 = d.squaredNorm();
  const double u = len2 > 0 ? std::clamp((p - s.a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (s.a + u * d)).norm();
}

struct Feature {
  enum Kind { Inclined, Flat, Obstacle } kind;
  Eigen::Vector2d center;
  double radius;  // bounding circle of the footprint
  double yaw_deg;
  OrderedJson json;
};

struct Layout {
  double width = 0, depth = 0;
  std::vector<Segment> walls;
  std::vector<Eigen::Vector2d> doorways;
  std::vector<Feature> features;
};

// Interior walls along x = const (vertical) or y = const between cell edges,
// each with a 1 m doorway, some left out to open rooms into each other.
void add_interior_walls(Layout& l, Rng& rng, const std::vector<double>& xs, const std::vector<double>& ys) {
  auto add_with_door = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const double len = (b - a).norm();
    if (len < 1.6 || rng.uniform(0, 1) < 0.2) return;  // open side
    const double door = 1.0;
    const double start = rng.uniform(0.3, len - door - 0.3);
    const Eigen::Vector2d dir = (b - a) / len;
    if (start > 0.2) l.walls.push_back({a, a + dir * start});
    if (len - start - door > 0.2) l.walls.push_back({a + dir * (start + door), b});
    l.doorways.push_back(a + dir * (start + door / 2));
  };
  for (std::size_t i = 1; i + 1 < xs.size(); ++i) {
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) add_with_door({xs[i], ys[j]}, {xs[i], ys[j + 1]});
  }
  for (std::size_t j = 1; j + 1 < ys.size(); ++j) {
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) add_with_door({xs[i], ys[j]}, {xs[i + 1], ys[j]});
  }
}

bool fits(const Layout& l, const Eigen::Vector2d& c, double r) {
  if (c.x() - r < 0.3 || c.y() - r < 0.3 || c.x() + r > l.width - 0.3 || c.y() + r > l.depth - 0.3) return false;
  for (const Segment& w : l.walls) {
    if (distance_to_segment(c, w) < r + kWallThickness / 2 + 0.3) return false;
  }
  for (const Eigen::Vector2d& d : l.doorways) {
    if ((c - d).norm() < r + 0.8) return false;
  }
  for (const Feature& f : l.features) {
    if ((c - f.center).norm() < r + f.radius + 0.8) return false;
  }
  return true;
}

bool place(Layout& l, Rng& rng, Feature f) {
  for (int attempt = 0; attempt < 300; ++attempt) {
    const Eigen::Vector2d c(rng.uniform(0, l.width), rng.uniform(0, l.depth));
    if (!fits(l, c, f.radius)) continue;
    f.center = c;
    f.json["center"] = f.kind == Feature::Obstacle
                           ? OrderedJson::array({round3(c.x()), round3(c.y()), f.json["center"][2]})
                           : OrderedJson::array({round3(c.x()), round3(c.y())});
    l.features.push_back(std::move(f));
    return true;
  }
  return false;
}

// An occupancy grid of where the robot's centre may go.
class PlanningGrid {
 public:
  explicit PlanningGrid(const Layout& l)
      : nx_(static_cast<int>(std::ceil(l.width / kCell))), ny_(static_cast<int>(std::ceil(l.depth / kCell))) {
    free_.assign(static_cast<std::size_t>(nx_ * ny_), 0);
    for (int y = 0; y < ny_; ++y) {
      for (int x = 0; x < nx_; ++x) free_[index(x, y)] = is_clear(l, center(x, y));
    }
  }
  static bool is_clear(const Layout& l, const Eigen::Vector2d& p) {
    if (p.x() < kRobotRadius || p.y() < kRobotRadius || p.x() > l.width - kRobotRadius ||
        p.y() > l.depth - kRobotRadius) {
      return false;
    }
    for (const Segment& w : l.walls) {
      if (distance_to_segment(p, w) < kRobotRadius + kWallThickness / 2) return false;
    }
    for (const Feature& f : l.features) {
      if ((p - f.center).norm() < f.radius + kRobotRadius) return false;
    }
    return true;
  }
  Eigen::Vector2d center(int x, int y) const { return {(x + 0.5) * kCell, (y + 0.5) * kCell}; }
  bool free(int x, int y) const { return x >= 0 && y >= 0 && x < nx_ && y < ny_ && free_[index(x, y)]; }
  std::pair<int, int> cell_of(const Eigen::Vector2d& p) const {
    return {static_cast<int>(std::floor(p.x() / kCell)), static_cast<int>(std::floor(p.y() / kCell))};
  }
  // Breadth-first distances (in cells, 8-connected) and parents from a start cell.
  void search(std::pair<int, int> start, std::vector<int>& dist, std::vector<int>& parent) const {
    dist.assign(free_.size(), -1);
    parent.assign(free_.size(), -1);
    std::deque<std::pair<int, int>> queue{start};
    dist[index(start.first, start.second)] = 0;
    while (!queue.empty()) {
      const auto [x, y] = queue.front();
      queue.pop_front();
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || !free(x + dx, y + dy)) continue;
          // No corner cutting past a blocked cell.
          if (dx != 0 && dy != 0 && (!free(x + dx, y) || !free(x, y + dy))) continue;
          const std::size_t n = index(x + dx, y + dy);
          if (dist[n] >= 0) continue;
          dist[n] = dist[index(x, y)] + 1;
          parent[n] = static_cast<int>(index(x, y));
          queue.emplace_back(x + dx, y + dy);
        }
      }
    }
  }
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y * nx_ + x); }
  std::pair<int, int> cell(std::size_t i) const {
    return {static_cast<int>(i % static_cast<std::size_t>(nx_)), static_cast<int>(i / static_cast<std::size_t>(nx_))};
  }
  // Whether the straight segment stays on free cells (sampled every 2.5 cm).
  bool line_free(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.025)));
    for (int s = 0; s <= steps; ++s) {
      const auto [x, y] = cell_of(a + (b - a) * (static_cast<double>(s) / steps));
      if (!free(x, y)) return false;
    }
    return true;
  }

 private:
  int nx_, ny_;
  std::vector<std::uint8_t> free_;
};

// Viewpoints in front of a feature (the low end of an inclined ramp first):
// a spot to reach and a spot 0.3 m closer, so the sensor ends up facing it.
std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> viewpoints(const Feature& f) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> out;
  const double base = (f.yaw_deg + 180.0) * std::numbers::pi / 180.0;  // behind local -x
  for (int k = 0; k < 8; ++k) {
    const double a = base + k * std::numbers::pi / 4;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    const Eigen::Vector2d far = f.center + dir * (f.radius + kRobotRadius + 0.9);
    out.emplace_back(far, far - dir * 0.3);
  }
  return out;
}

std::vector<Eigen::Vector2d> plan_trajectory(const Layout& l, Layout& kept_out) {
  const PlanningGrid grid(l);
  // Start in the free cell nearest the (0, 0) corner.
  std::pair<int, int> start{-1, -1};
  for (int s = 0; s < 400 && start.first < 0; ++s) {
    for (int y = 0; y <= s && start.first < 0; ++y) {
      if (grid.free(s - y, y)) start = {s - y, y};
    }
  }
  if (start.first < 0) throw Error(ErrorCode::InvalidData, "random arena: no free start cell");
  std::vector<Eigen::Vector2d> path{grid.center(start.first, start.second)};
  std::vector<bool> visited(l.features.size(), false);
  std::vector<int> dist, parent;
  auto current = start;
  // Greedy tour: go to the nearest reachable viewpoint of a feature not yet seen.
  for (;;) {
    grid.search(current, dist, parent);
    int best_feature = -1, best_dist = std::numeric_limits<int>::max();
    std::pair<Eigen::Vector2d, Eigen::Vector2d> best_view;
    for (std::size_t i = 0; i < l.features.size(); ++i) {
      if (visited[i]) continue;
      for (const auto& view : viewpoints(l.features[i])) {
        const auto [x, y] = grid.cell_of(view.first);
        if (!grid.free(x, y) || !grid.line_free(view.first, view.second)) continue;
        const int d = dist[grid.index(x, y)];
        if (d >= 0 && d < best_dist) {
          best_dist = d;
          best_feature = static_cast<int>(i);
          best_view = view;
        }
        if (d >= 0) break;  // the first reachable viewpoint of a feature is its best
      }
    }
    if (best_feature < 0) break;
    visited[static_cast<std::size_t>(best_feature)] = true;
    const auto goal = grid.cell_of(best_view.first);
    std::vector<Eigen::Vector2d> leg;
    for (int i = static_cast<int>(grid.index(goal.first, goal.second)); i >= 0; i = parent[static_cast<std::size_t>(i)]) {
      const auto [x, y] = grid.cell(static_cast<std::size_t>(i));
      leg.push_back(grid.center(x, y));
    }
    std::reverse(leg.begin(), leg.end());
    // String pulling: keep only the cells where a straight line must turn.
    std::size_t anchor = 0;
    while (anchor + 1 < leg.size()) {
      std::size_t far = anchor + 1;
      while (far + 1 < leg.size() && grid.line_free(leg[anchor], leg[far + 1])) ++far;
      path.push_back(leg[far]);
      anchor = far;
    }
    path.push_back(best_view.second);
    current = grid.cell_of(best_view.second);
  }
  // Features the tour cannot reach are left out of the arena.
  kept_out = l;
  kept_out.features.clear();
  for (std::size_t i = 0; i < l.features.size(); ++i) {
    if (visited[i]) kept_out.features.push_back(l.features[i]);
  }
  // Drop consecutive duplicates (a zero-length leg).
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : path) {
    if (out.empty() || (p - out.back()).norm() > 1e-6) out.push_back(p);
  }
  return out;
}

// A whole number as an integer, so today's camera reads "fx": 277 as before.
OrderedJson whole_or_real(double v) {
  return v == std::floor(v) && std::abs(v) < 1e9 ? OrderedJson(static_cast<std::int64_t>(v)) : OrderedJson(v);
}

OrderedJson sensor_json(const RandomSensor& s) {
  if (s.type == SensorType::Lidar) {
    return {{"type", "lidar"},
            {"rings", s.rings},
            {"horizontal_samples", s.samples},
            {"vertical_fov_deg", {s.vertical_fov_min_deg, s.vertical_fov_max_deg}},
            {"min_range", s.min_range.value_or(0.4)},
            {"max_range", s.max_range.value_or(12.0)},
            {"noise", "gaussian"},
            {"sigma", 0.01}};
  }
  const double f = round3(277.0 * s.width / 320.0);
  return {{"type", "depth_camera"},
          {"width", s.width},
          {"height", s.image_height},
          {"fx", whole_or_real(f)},
          {"fy", whole_or_real(f)},
          {"cx", whole_or_real(s.width / 2.0)},
          {"cy", whole_or_real(s.image_height / 2.0)},
          {"min_range", s.min_range.value_or(0.3)},
          {"max_range", s.max_range.value_or(5.0)},
          {"noise", "kinect"}};
}

OrderedJson make_arena(std::uint64_t seed, std::uint64_t attempt, const RandomSensor& sensor) {
  Rng rng(mix64(seed) ^ attempt);
  Layout l;
  l.width = round3(rng.uniform(8.0, 14.0));
  l.depth = round3(rng.uniform(6.0, 10.0));
  l.walls = {{{0, 0}, {l.width, 0}}, {{l.width, 0}, {l.width, l.depth}},
             {{l.width, l.depth}, {0, l.depth}}, {{0, l.depth}, {0, 0}}};
  const int cols = std::clamp(static_cast<int>(std::lround(l.width / 3.5)), 2, 4);
  const int rows = std::clamp(static_cast<int>(std::lround(l.depth / 3.5)), 2, 3);
  std::vector<double> xs{0}, ys{0};
  for (int i = 1; i < cols; ++i) xs.push_back(round3(l.width * i / cols + rng.uniform(-0.3, 0.3)));
  xs.push_back(l.width);
  if (rows == 3) {
    // Rooms, a corridor 1.6-2 m wide, rooms.
    const double corridor = rng.uniform(1.6, 2.0);
    const double mid = l.depth / 2 + rng.uniform(-0.3, 0.3);
    ys.push_back(round3(mid - corridor / 2));
    ys.push_back(round3(mid + corridor / 2));
  } else {
    ys.push_back(round3(l.depth / 2 + rng.uniform(-0.4, 0.4)));
  }
  ys.push_back(l.depth);
  add_interior_walls(l, rng, xs, ys);

  const int inclined = rng.integer(1, 4), flat = rng.integer(1, 3), obstacles = rng.integer(1, 3);
  int placed_inclined = 0, placed_flat = 0;
  for (int i = 0; i < inclined; ++i) {
    Feature f{Feature::Inclined, Eigen::Vector2d::Zero(), 0, round3(rng.uniform(0, 360)), {}};
    const double length = round3(rng.uniform(1.0, 1.6)), width = round3(rng.uniform(0.8, 1.4));
    f.radius = 0.5 * std::hypot(length, width);
    f.json = {{"type", "inclined_ramp"}, {"center", nullptr}, {"length", length}, {"width", width},
              {"angle_deg", round3(rng.uniform(10, 25))}, {"yaw_deg", f.yaw_deg}};
    placed_inclined += place(l, rng, f);
  }
  for (int i = 0; i < flat; ++i) {
    Feature f{Feature::Flat, Eigen::Vector2d::Zero(), 0, round3(rng.uniform(0, 360)), {}};
    const double sx = round3(rng.uniform(0.8, 1.6)), sy = round3(rng.uniform(0.8, 1.6));
    f.radius = 0.5 * std::hypot(sx, sy);
    f.json = {{"type", "flat_ramp"}, {"center", nullptr}, {"size", {sx, sy}},
              {"height", round3(rng.uniform(0.1, 0.4))}, {"yaw_deg", f.yaw_deg}};
    placed_flat += place(l, rng, f);
  }
  for (int i = 0; i < obstacles; ++i) {
    Feature f{Feature::Obstacle, Eigen::Vector2d::Zero(), 0, round3(rng.uniform(0, 360)), {}};
    const double sx = round3(rng.uniform(0.2, 0.6)), sy = round3(rng.uniform(0.2, 0.6)),
                 sz = round3(rng.uniform(0.2, 0.6));
    f.radius = 0.5 * std::hypot(sx, sy);
    f.json = {{"type", "box"}, {"center", {0, 0, round3(sz / 2)}}, {"size", {sx, sy, sz}},
              {"yaw_deg", f.yaw_deg}, {"label", "other"}};
    place(l, rng, f);
  }
  if (placed_inclined == 0 || placed_flat == 0) return nullptr;

  Layout kept;
  const std::vector<Eigen::Vector2d> path = plan_trajectory(l, kept);
  const auto count = [&kept](Feature::Kind k) {
    return std::count_if(kept.features.begin(), kept.features.end(), [k](const Feature& f) { return f.kind == k; });
  };
  if (count(Feature::Inclined) == 0 || count(Feature::Flat) == 0 || path.size() < 2) return nullptr;

  OrderedJson j;
  j["version"] = 1;
  j["name"] = "random-" + std::to_string(seed);
  j["bounds"] = {{"min", {0, 0, 0}}, {"max", {l.width, l.depth, 2.4}}};
  j["floor"] = true;
  OrderedJson elements = OrderedJson::array();
  for (const Segment& w : kept.walls) {
    elements.push_back({{"type", "wall"}, {"from", {round3(w.a.x()), round3(w.a.y())}},
                        {"to", {round3(w.b.x()), round3(w.b.y())}}, {"height", kWallHeight},
                        {"thickness", kWallThickness}});
  }
  for (const Feature& f : kept.features) elements.push_back(f.json);
  j["elements"] = elements;
  double length = 0;
  OrderedJson waypoints = OrderedJson::array();
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) length += (path[i] - path[i - 1]).norm();
    waypoints.push_back({round3(path[i].x()), round3(path[i].y())});
  }
  // Drawn whatever the sensor, so the draws stay those of a depth camera.
  const double drawn_pitch = round3(rng.uniform(-25, -10));
  const double pitch = sensor.pitch_deg.value_or(sensor.type == SensorType::Lidar ? 0.0 : drawn_pitch);
  j["trajectory"] = {{"waypoints", waypoints},
                     {"height", sensor.height.value_or(0.5)},
                     {"frames", std::clamp(static_cast<int>(std::lround(length / 0.1)), 60, 600)},
                     {"pitch_deg", pitch}};
  j["sensor"] = sensor_json(sensor);
  return j;
}

}  // namespace

std::string random_arena_json(std::uint64_t seed, const RandomSensor& sensor) {
  // A layout whose ramps the tour cannot reach is drawn again.
  for (std::uint64_t attempt = 0; attempt < 64; ++attempt) {
    const OrderedJson j = make_arena(seed, attempt, sensor);
    if (!j.is_null()) return j.dump(2) + "\n";
  }
  throw Error(ErrorCode::InvalidData, "random arena " + std::to_string(seed) + ": no valid layout in 64 attempts");
}

Arena random_arena(std::uint64_t seed, const RandomSensor& sensor) {
  return parse_arena(random_arena_json(seed, sensor), "random-" + std::to_string(seed),
                     std::filesystem::path("."));
}

}  // namespace sarmap::sim
