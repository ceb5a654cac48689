#include "engine/sim/arena_mesh.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "engine/core/degrees.hpp"
#include "engine/geometry/oriented_box.hpp"

namespace sarmap::sim {
namespace {

Eigen::Matrix3d yaw_rotation(double yaw_deg) {
  return Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

using geometry::add_quad;
using geometry::BoxFaces;

// A box of the given size around `center`, turned by yaw about z.
ClassedMesh box_mesh(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw_deg, BoxFaces faces) {
  return geometry::box_mesh(geometry::yawed_box(center, size, yaw_deg * kDeg), faces);
}

// The wedge: footprint length x width centred at the origin, slope rising to +x.
ClassedMesh wedge_mesh(const InclinedRampSpec& s) {
  ClassedMesh m;
  const Eigen::Matrix3d r = yaw_rotation(s.yaw_deg);
  const double hx = s.length / 2, hy = s.width / 2;
  const double top = s.length * std::tan(s.angle_deg * kDeg);
  const Eigen::Vector3d local[6] = {
      {-hx, -hy, 0}, {-hx, hy, 0},     // low edge, on the floor
      {hx, -hy, 0},  {hx, hy, 0},      // back edge, on the floor
      {hx, -hy, top}, {hx, hy, top},   // high edge
  };
  const Eigen::Vector3d c(s.center.x(), s.center.y(), 0);
  for (const auto& p : local) m.vertices.push_back((c + r * p).cast<float>());
  add_quad(m, 0, 4, 5, 1);                      // slope
  add_quad(m, 2, 3, 5, 4);                      // vertical back face
  m.indices.insert(m.indices.end(), {0, 2, 4});  // side at -y
  m.indices.insert(m.indices.end(), {1, 5, 3});  // side at +y
  return m;
}

ClassedMesh transformed_mesh(const MeshSpec& s) {
  ClassedMesh m;
  const Eigen::Matrix3d r = rotation_from_rpy_deg(s.rpy_deg);
  m.vertices.reserve(s.vertices.size());
  for (const Eigen::Vector3f& v : s.vertices) {
    const Eigen::Vector3d scaled = v.cast<double>().cwiseProduct(s.scale);
    m.vertices.push_back((r * scaled + s.position).cast<float>());
  }
  m.indices = s.indices;
  return m;
}

}  // namespace

Eigen::Matrix3d rotation_from_rpy_deg(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z() * kDeg, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y() * kDeg, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x() * kDeg, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

ClassedMesh element_mesh(const ArenaElement& element) {
  ClassedMesh m;
  if (const auto* w = std::get_if<WallSpec>(&element.shape)) {
    const Eigen::Vector2d d = w->to - w->from;
    const Eigen::Vector2d mid = (w->from + w->to) / 2;
    const double yaw = std::atan2(d.y(), d.x()) / kDeg;
    m = box_mesh({mid.x(), mid.y(), w->height / 2}, {d.norm() + w->thickness, w->thickness, w->height}, yaw,
                 BoxFaces::NoBottom);
  } else if (const auto* r = std::get_if<InclinedRampSpec>(&element.shape)) {
    m = wedge_mesh(*r);
  } else if (const auto* f = std::get_if<FlatRampSpec>(&element.shape)) {
    m = box_mesh({f->center.x(), f->center.y(), f->height / 2}, {f->size.x(), f->size.y(), f->height}, f->yaw_deg,
                 BoxFaces::NoBottom);
  } else if (const auto* b = std::get_if<BoxSpec>(&element.shape)) {
    m = box_mesh(b->center, b->size, b->yaw_deg, BoxFaces::All);
  } else {
    m = transformed_mesh(std::get<MeshSpec>(element.shape));
  }
  m.label = element.label;
  return m;
}

std::vector<ClassedMesh> arena_meshes(const Arena& arena) {
  std::vector<ClassedMesh> meshes;
  if (arena.floor) {
    ClassedMesh f;
    const Eigen::Vector3d& lo = arena.bounds_min;
    const Eigen::Vector3d& hi = arena.bounds_max;
    f.vertices = {Eigen::Vector3f(lo.x(), lo.y(), 0), Eigen::Vector3f(hi.x(), lo.y(), 0),
                  Eigen::Vector3f(hi.x(), hi.y(), 0), Eigen::Vector3f(lo.x(), hi.y(), 0)};
    add_quad(f, 0, 1, 2, 3);
    f.label = ClassId::Terrain;
    f.name = "floor";
    meshes.push_back(std::move(f));
  }
  for (std::size_t i = 0; i < arena.elements.size(); ++i) {
    ClassedMesh m = element_mesh(arena.elements[i]);
    m.name = "elements[" + std::to_string(i) + "] (" + std::string(element_type_name(arena.elements[i])) + ")";
    meshes.push_back(std::move(m));
  }
  return meshes;
}

}  // namespace sarmap::sim
