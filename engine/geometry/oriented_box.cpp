#include "engine/geometry/oriented_box.hpp"

#include <Eigen/Geometry>

#include "engine/core/error.hpp"

namespace sarmap::geometry {

OrientedBox yawed_box(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw) {
  return {center, Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(), size / 2};
}

void append_box(ClassedMesh& m, const OrientedBox& box, BoxFaces faces) {
  if (!box.center.allFinite() || !box.axes.allFinite() || !box.half_extents.allFinite() ||
      (box.half_extents.array() < 0).any()) {
    throw Error(ErrorCode::InvalidArgument,
                "box_mesh: the box has a non-finite value or a negative half extent");
  }
  const auto first = static_cast<std::uint32_t>(m.vertices.size());
  const Eigen::Vector3d& h = box.half_extents;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d local((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
    m.vertices.push_back((box.center + box.axes * local).cast<float>());
  }
  const auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    add_quad(m, first + a, first + b, first + c, first + d);
  };
  quad(4, 5, 7, 6);  // +z
  if (faces == BoxFaces::All) quad(0, 2, 3, 1);
  quad(0, 1, 5, 4);  // -y
  quad(2, 6, 7, 3);  // +y
  quad(0, 4, 6, 2);  // -x
  quad(1, 3, 7, 5);  // +x
}

ClassedMesh box_mesh(const OrientedBox& box, BoxFaces faces) {
  ClassedMesh m;
  m.vertices.reserve(8);
  m.indices.reserve(36);
  append_box(m, box, faces);
  return m;
}

}  // namespace sarmap::geometry
