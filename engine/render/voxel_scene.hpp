// Occupied voxels as a ray-traceable scene: every voxel a cube, of which only
// the faces not shared with another occupied voxel become triangles in the
// shared Embree scene (geometry::TriangleScene). A ray's first hit names the
// voxel, so each picture colours the same hit in its own way.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/render/camera.hpp"

namespace sarmap::geometry {
class TriangleScene;
}

namespace sarmap::render {

// Equal cubes with a class each: the occupied voxels of a metric map.
struct VoxelSet {
  float voxel = 0.05f;  // edge, metres
  std::vector<Eigen::Vector3f> centres;
  std::vector<ClassId> labels;  // one per centre
};

// The box of the voxels' faces; a unit box at the origin when there are none.
Box3 voxel_bounds(const VoxelSet& voxels);

class VoxelScene {
 public:
  // Throws sarmap::Error (InvalidArgument) when the sizes of centres and
  // labels differ or the edge is not positive and finite.
  explicit VoxelScene(const VoxelSet& voxels);
  ~VoxelScene();
  VoxelScene(const VoxelScene&) = delete;
  VoxelScene& operator=(const VoxelScene&) = delete;

  struct Hit {
    bool hit = false;
    float t = 0;                                       // metres along the ray (its direction is unit)
    std::uint32_t voxel = 0;                           // index into the VoxelSet
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // the face's outward normal
  };
  // Thread-safe: one scene serves every row of a picture at once.
  Hit trace(const Camera::Ray& ray) const;

  std::size_t face_count() const { return face_voxel_.size(); }

 private:
  std::vector<std::uint32_t> face_voxel_;  // per exposed face (two triangles)
  std::unique_ptr<geometry::TriangleScene> scene_;
};

}  // namespace sarmap::render
