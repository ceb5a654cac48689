#include "engine/render/voxel_scene.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>

#include "engine/core/error.hpp"
#include "engine/geometry/classed_mesh.hpp"
#include "engine/geometry/triangle_scene.hpp"

namespace sarmap::render {
namespace {

// Integer voxel coordinates packed 21 bits an axis: beyond +-10 km at 1 cm
// voxels, more than any map holds.
std::uint64_t pack(const Eigen::Vector3i& k) {
  constexpr std::uint64_t mask = (1u << 21) - 1;
  return (static_cast<std::uint64_t>(k.x()) & mask) | ((static_cast<std::uint64_t>(k.y()) & mask) << 21) |
         ((static_cast<std::uint64_t>(k.z()) & mask) << 42);
}

Eigen::Vector3i key_of(const Eigen::Vector3f& centre, float voxel) {
  return (centre / voxel).array().floor().cast<int>();
}

}  // namespace

Box3 voxel_bounds(const VoxelSet& voxels) {
  if (voxels.centres.empty()) return {Eigen::Vector3f::Zero(), Eigen::Vector3f::Ones()};
  Box3 box{voxels.centres[0], voxels.centres[0]};
  for (const Eigen::Vector3f& c : voxels.centres) {
    box.min = box.min.cwiseMin(c);
    box.max = box.max.cwiseMax(c);
  }
  const Eigen::Vector3f half = Eigen::Vector3f::Constant(0.5f * voxels.voxel);
  return {box.min - half, box.max + half};
}

VoxelScene::VoxelScene(const VoxelSet& voxels) {
  if (voxels.centres.size() != voxels.labels.size()) {
    throw Error(ErrorCode::InvalidArgument, "VoxelScene: " + std::to_string(voxels.centres.size()) +
                                                " voxel centres but " + std::to_string(voxels.labels.size()) +
                                                " labels");
  }
  if (!(voxels.voxel > 0) || !std::isfinite(voxels.voxel)) {
    throw Error(ErrorCode::InvalidArgument, "VoxelScene: the voxel edge must be positive");
  }
  std::unordered_set<std::uint64_t> occupied;
  occupied.reserve(voxels.centres.size());
  for (const Eigen::Vector3f& c : voxels.centres) occupied.insert(pack(key_of(c, voxels.voxel)));

  geometry::ClassedMesh mesh;
  mesh.name = "occupied voxels";
  const float h = 0.5f * voxels.voxel;
  for (std::size_t i = 0; i < voxels.centres.size(); ++i) {
    const Eigen::Vector3f& c = voxels.centres[i];
    const Eigen::Vector3i key = key_of(c, voxels.voxel);
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = -1; side <= 1; side += 2) {
        Eigen::Vector3i next = key;
        next[axis] += side;
        if (occupied.count(pack(next)) != 0) continue;
        // The face's two in-plane axes, and its four corners around the
        // point half a voxel out from the centre.
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
        for (const auto& [su, sv] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
          Eigen::Vector3f p = c;
          p[axis] += static_cast<float>(side) * h;
          p[u] += static_cast<float>(su) * h;
          p[v] += static_cast<float>(sv) * h;
          mesh.vertices.push_back(p);
        }
        geometry::add_quad(mesh, base, base + 1, base + 2, base + 3);
        face_voxel_.push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
  const std::vector<geometry::ClassedMesh> meshes{std::move(mesh)};
  scene_ = std::make_unique<geometry::TriangleScene>(meshes);
}

VoxelScene::~VoxelScene() = default;

VoxelScene::Hit VoxelScene::trace(const Camera::Ray& ray) const {
  const auto surface =
      scene_->closest_hit(ray.origin, ray.direction, 0.0f, std::numeric_limits<float>::infinity());
  Hit hit;
  if (!surface.hit) return hit;
  hit.hit = true;
  hit.t = surface.t;
  hit.voxel = face_voxel_[surface.triangle / 2];
  // Seen from outside a closed set of cubes, the face turned to the ray is
  // the outward one.
  hit.normal = surface.normal;
  return hit;
}

}  // namespace sarmap::render
