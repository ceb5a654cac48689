#include "engine/eval/face_pieces.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include "engine/eval/truth_surfaces.hpp"

namespace sarmap::eval {
namespace {

// How far in front of a face a sample is tested: well clear of float
// rounding, well inside any solid (the thinnest are walls of centimetres).
constexpr double kInFront = 1e-3;

using Point2 = Eigen::Vector2d;

// Sutherland-Hodgman: the part of a convex polygon with coord[axis] on the
// kept side of `bound`.
std::vector<Point2> clip(const std::vector<Point2>& poly, int axis, double bound, bool keep_below) {
  std::vector<Point2> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Point2& a = poly[i];
    const Point2& b = poly[(i + 1) % poly.size()];
    const double da = keep_below ? bound - a[axis] : a[axis] - bound;
    const double db = keep_below ? bound - b[axis] : b[axis] - bound;
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + da / (da - db) * (b - a));
  }
  return out;
}

}  // namespace

bool ConvexSolid::contains(const Eigen::Vector3d& p) const {
  if (!box.contains(p)) return false;
  for (const auto& [n, d] : planes) {
    if (n.dot(p) + d > 0) return false;
  }
  return true;
}

std::optional<ConvexSolid> element_solid(const sim::ArenaElement& element, const sim::ClassedMesh& mesh) {
  if (std::holds_alternative<sim::MeshSpec>(element.shape) || mesh.vertices.empty()) return std::nullopt;
  ConvexSolid s;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const Eigen::Vector3d a = mesh.vertices[mesh.indices[t]].cast<double>();
    const Eigen::Vector3d cross =
        (mesh.vertices[mesh.indices[t + 1]].cast<double>() - a).cross(mesh.vertices[mesh.indices[t + 2]].cast<double>() - a);
    if (!(cross.norm() > 1e-12)) continue;
    const Eigen::Vector3d n = cross.normalized();
    // A plane twice (a quad's two triangles) is harmless.
    s.planes.emplace_back(n, -n.dot(a));
  }
  for (const Eigen::Vector3f& v : mesh.vertices) s.box.extend(v.cast<double>());
  if (!std::holds_alternative<sim::BoxSpec>(element.shape)) {
    s.planes.emplace_back(-Eigen::Vector3d::UnitZ(), s.box.min().z());  // the floor it stands on
  }
  return s;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> in_plane_axes(const Eigen::Vector3d& n) {
  Eigen::Vector3d u = Eigen::Vector3d::UnitZ().cross(n);
  if (u.norm() < 0.5) u = Eigen::Vector3d::UnitX() - n.x() * n;
  u.normalize();
  return {u, n.cross(u)};
}

std::vector<TruthFace> open_pieces(const TruthFace& face, std::span<const ConvexSolid> others, double step,
                                   double min_area) {
  Eigen::AlignedBox3d extent;
  for (const Eigen::Vector3d& p : face.polygon) extent.extend(p);
  extent.min().array() -= 2 * kInFront;
  extent.max().array() += 2 * kInFront;
  std::vector<const ConvexSolid*> near;
  for (const ConvexSolid& s : others) {
    if (s.box.intersects(extent)) near.push_back(&s);
  }
  if (near.empty() || face.polygon.size() < 3) return {face};

  const auto [u, v] = in_plane_axes(face.normal);
  const Eigen::Vector3d& origin = face.polygon.front();
  std::vector<Point2> outline;
  for (const Eigen::Vector3d& p : face.polygon) outline.emplace_back((p - origin).dot(u), (p - origin).dot(v));
  Point2 lo = outline.front(), hi = outline.front();
  for (const Point2& q : outline) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  const auto nu = static_cast<std::size_t>(std::ceil((hi.x() - lo.x()) / step));
  const auto nv = static_cast<std::size_t>(std::ceil((hi.y() - lo.y()) / step));
  const auto at = [&](std::size_t i, std::size_t k) {
    return Point2(lo.x() + (static_cast<double>(i) + 0.5) * step, lo.y() + (static_cast<double>(k) + 0.5) * step);
  };
  // 0 off the face, 1 open, 2 hidden.
  std::vector<std::uint8_t> state(nu * nv, 0);
  bool any_hidden = false;
  for (std::size_t k = 0; k < nv; ++k) {
    for (std::size_t i = 0; i < nu; ++i) {
      const Point2 q = at(i, k);
      const Eigen::Vector3d p = origin + q.x() * u + q.y() * v;
      if (!face.contains(p, 0)) continue;
      const Eigen::Vector3d front = p + kInFront * face.normal;
      const bool hidden = std::any_of(near.begin(), near.end(), [&](const ConvexSolid* s) { return s->contains(front); });
      state[k * nu + i] = hidden ? 2 : 1;
      any_hidden = any_hidden || hidden;
    }
  }
  if (!any_hidden) return {face};

  std::vector<TruthFace> pieces;
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < state.size(); ++seed) {
    if (state[seed] != 1) continue;
    // Flood the group, marking it 3.
    std::size_t count = 0;
    Point2 glo = at(seed % nu, seed / nu), ghi = glo, sum = Point2::Zero();
    state[seed] = 3;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      const std::size_t i = c % nu, k = c / nu;
      const Point2 q = at(i, k);
      glo = glo.cwiseMin(q), ghi = ghi.cwiseMax(q), sum += q;
      ++count;
      const auto visit = [&](std::size_t n) {
        if (state[n] == 1) state[n] = 3, stack.push_back(n);
      };
      if (i > 0) visit(c - 1);
      if (i + 1 < nu) visit(c + 1);
      if (k > 0) visit(c - nu);
      if (k + 1 < nv) visit(c + nu);
    }
    const double area = static_cast<double>(count) * step * step;
    if (area < min_area) continue;
    std::vector<Point2> poly = outline;
    poly = clip(poly, 0, glo.x() - 0.5 * step, false);
    poly = clip(poly, 0, ghi.x() + 0.5 * step, true);
    poly = clip(poly, 1, glo.y() - 0.5 * step, false);
    poly = clip(poly, 1, ghi.y() + 0.5 * step, true);
    if (poly.size() < 3) continue;
    TruthFace piece = face;
    piece.polygon.clear();
    for (const Point2& q : poly) piece.polygon.push_back(origin + q.x() * u + q.y() * v);
    const Point2 mean = sum / static_cast<double>(count);
    piece.center = origin + mean.x() * u + mean.y() * v;
    piece.area_m2 = area;
    pieces.push_back(std::move(piece));
  }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    pieces[i].piece = i;
    pieces[i].pieces = pieces.size();
  }
  return pieces;
}

}  // namespace sarmap::eval
