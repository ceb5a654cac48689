#include "engine/eval/truth_surfaces.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include "engine/eval/face_pieces.hpp"
#include "engine/sim/arena_mesh.hpp"

namespace sarmap::eval {
namespace {

// Mesh vertices are floats: coplanar triangles agree to about 1e-7 relative,
// and distinct faces of a box or wedge differ by far more than this.
constexpr double kSameNormal = 1e-4;
constexpr double kSameOffset = 1e-4;  // metres

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Andrew's monotone chain: counter-clockwise, collinear points dropped.
std::vector<std::size_t> convex_hull(const std::vector<Eigen::Vector2d>& pts) {
  std::vector<std::size_t> order(pts.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return pts[a].x() != pts[b].x() ? pts[a].x() < pts[b].x() : pts[a].y() < pts[b].y();
  });
  if (order.size() < 3) return order;
  std::vector<std::size_t> hull(2 * order.size());
  std::size_t k = 0;
  // The tolerance drops points on an edge, which a quad's diagonal leaves.
  const double eps = 1e-12;
  for (std::size_t i : order) {
    while (k >= 2 && cross2(pts[hull[k - 2]], pts[hull[k - 1]], pts[i]) <= eps) --k;
    hull[k++] = i;
  }
  const std::size_t lower = k + 1;
  for (auto it = order.rbegin() + 1; it != order.rend(); ++it) {
    while (k >= lower && cross2(pts[hull[k - 2]], pts[hull[k - 1]], pts[*it]) <= eps) --k;
    hull[k++] = *it;
  }
  hull.resize(k - 1);
  return hull;
}

struct FaceBuilder {
  Eigen::Vector3d normal;
  double offset = 0;
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d weighted_center = Eigen::Vector3d::Zero();
  double area = 0;
};

// Groups a mesh's triangles into planes: each element is convex, so one
// plane of it is one face.
std::vector<FaceBuilder> coplanar_groups(const sim::ClassedMesh& mesh) {
  std::vector<FaceBuilder> groups;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const Eigen::Vector3d a = mesh.vertices[mesh.indices[t]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[mesh.indices[t + 1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[mesh.indices[t + 2]].cast<double>();
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double twice_area = cross.norm();
    if (!(twice_area > 1e-12)) continue;  // degenerate: no plane
    const Eigen::Vector3d n = cross / twice_area;
    const double offset = -n.dot(a);
    auto it = std::find_if(groups.begin(), groups.end(), [&](const FaceBuilder& g) {
      return (g.normal - n).norm() < kSameNormal && std::abs(g.offset - offset) < kSameOffset;
    });
    if (it == groups.end()) {
      groups.push_back({n, offset, {}, Eigen::Vector3d::Zero(), 0});
      it = groups.end() - 1;
    }
    it->points.insert(it->points.end(), {a, b, c});
    it->weighted_center += 0.5 * twice_area * (a + b + c) / 3.0;
    it->area += 0.5 * twice_area;
  }
  return groups;
}

std::vector<Eigen::Vector3d> outline(const FaceBuilder& g) {
  const auto [u, v] = in_plane_axes(g.normal);
  std::vector<Eigen::Vector2d> flat;
  flat.reserve(g.points.size());
  for (const Eigen::Vector3d& p : g.points) flat.emplace_back(p.dot(u), p.dot(v));
  std::vector<Eigen::Vector3d> polygon;
  for (std::size_t i : convex_hull(flat)) polygon.push_back(g.points[i]);
  return polygon;
}

// The kind of a face of an element, from its normal; nullopt for elements
// that give no truth faces.
std::optional<FaceKind> face_kind(const sim::ArenaElement& element, const Eigen::Vector3d& n) {
  constexpr double kLevel = 1e-3;  // |n.z| below this: a vertical face
  if (const auto* w = std::get_if<sim::WallSpec>(&element.shape)) {
    // The same direction arena_mesh builds the wall's box along.
    const Eigen::Vector2d d = w->to - w->from;
    const double yaw = std::atan2(d.y(), d.x());
    const bool along = std::abs(n.x() * std::cos(yaw) + n.y() * std::sin(yaw)) < kLevel;
    return std::abs(n.z()) < kLevel && along ? FaceKind::WallFace : FaceKind::Side;
  }
  if (std::holds_alternative<sim::InclinedRampSpec>(element.shape)) {
    return n.z() > kLevel ? FaceKind::RampDeck : FaceKind::Side;
  }
  if (std::holds_alternative<sim::FlatRampSpec>(element.shape)) {
    return n.z() > 1 - kLevel ? FaceKind::PlatformTop : FaceKind::Side;
  }
  return std::nullopt;
}

}  // namespace

std::string_view face_kind_name(FaceKind kind) {
  switch (kind) {
    case FaceKind::Floor: return "floor";
    case FaceKind::WallFace: return "wall_face";
    case FaceKind::RampDeck: return "ramp_deck";
    case FaceKind::PlatformTop: return "platform_top";
    case FaceKind::Side: return "side";
  }
  return "side";
}

bool TruthFace::contains(const Eigen::Vector3d& p, double margin) const {
  if (polygon.size() < 3) return false;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector3d& a = polygon[i];
    const Eigen::Vector3d edge = polygon[(i + 1) % polygon.size()] - a;
    // Counter-clockwise seen from the normal: n x edge points inwards.
    const Eigen::Vector3d inward = normal.cross(edge).normalized();
    if ((p - a).dot(inward) < -margin) return false;
  }
  return true;
}

std::vector<TruthFace> truth_faces(const sim::Arena& arena) {
  const std::vector<sim::ClassedMesh> meshes = sim::arena_meshes(arena);
  std::vector<TruthFace> faces;
  const std::size_t first_element = arena.floor ? 1 : 0;
  std::vector<std::optional<ConvexSolid>> solids;
  for (std::size_t e = 0; e < arena.elements.size(); ++e) {
    solids.push_back(element_solid(arena.elements[e], meshes[e + first_element]));
  }
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const bool is_floor = arena.floor && m == 0;
    const sim::ArenaElement* element = is_floor ? nullptr : &arena.elements[m - first_element];
    // The floor is one face: what stands on it hides parts of it, but those
    // never split what a map sees as the floor.
    std::vector<ConvexSolid> others;
    for (std::size_t e = 0; e < solids.size() && element; ++e) {
      if (e != m - first_element && solids[e]) others.push_back(*solids[e]);
    }
    for (const FaceBuilder& g : coplanar_groups(meshes[m])) {
      std::optional<FaceKind> kind = FaceKind::Floor;
      if (element) kind = face_kind(*element, g.normal);
      if (!kind) break;
      TruthFace f;
      f.mesh = m;
      if (element) f.element = m - first_element;
      f.name = meshes[m].name;
      f.kind = *kind;
      f.label = meshes[m].label;
      f.normal = g.normal;
      f.offset = g.offset;
      f.polygon = outline(g);
      f.center = g.weighted_center / g.area;
      f.area_m2 = g.area;
      f.slope_deg = std::acos(std::clamp(std::abs(g.normal.z()), 0.0, 1.0)) * 180.0 / std::numbers::pi;
      for (TruthFace& piece : open_pieces(f, others)) faces.push_back(std::move(piece));
    }
  }
  return faces;
}

double seen_fraction(const TruthFace& face, const sim::GroundTruthGrid& grid) {
  if (face.polygon.size() < 3 || !(grid.resolution > 0)) return 0;
  const double res = grid.resolution;
  const auto [au, av] = in_plane_axes(face.normal);
  const Eigen::Vector3d& origin = face.polygon.front();
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  for (const Eigen::Vector3d& p : face.polygon) {
    const double u = (p - origin).dot(au), v = (p - origin).dot(av);
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  // Far enough off the plane to leave a voxel face, never past the next one.
  const Eigen::Vector3d across = face.normal * (1e-3 * res);
  const auto observed = [&](const Eigen::Vector3d& p) {
    for (const Eigen::Vector3d& q : {Eigen::Vector3d(p + across), Eigen::Vector3d(p - across)}) {
      const auto it = grid.occupied.find(sim::voxel_key_of(q, res));
      if (it != grid.occupied.end() && it->second.observed) return true;
    }
    return false;
  };
  std::size_t samples = 0, seen = 0;
  for (double u = u0 + 0.5 * res; u < u1; u += res) {
    for (double v = v0 + 0.5 * res; v < v1; v += res) {
      const Eigen::Vector3d p = origin + u * au + v * av;
      if (!face.contains(p, 0)) continue;
      ++samples;
      seen += observed(p);
    }
  }
  if (samples == 0) return observed(face.center) ? 1.0 : 0.0;  // smaller than one sample
  return static_cast<double>(seen) / static_cast<double>(samples);
}

}  // namespace sarmap::eval
