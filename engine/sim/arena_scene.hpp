// The arena's triangles in an Embree scene, one geometry per element with the
// element's class, answering first-hit ray queries for the simulated sensors,
// the trajectory's ground height and the ground-truth visibility.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "engine/core/classes.hpp"
#include "engine/sim/arena_mesh.hpp"

namespace sarmap::sim {

// How a batch of rays is handed to Embree; both give the same hits (tested),
// the benchmark says which is faster.
enum class RayBatchMode { Single, Packet16 };

class ArenaScene {
 public:
  // Builds the scene (one Embree geometry per mesh). Throws sarmap::Error if
  // Embree fails or a mesh has an index outside its vertices.
  explicit ArenaScene(const std::vector<ClassedMesh>& meshes);
  ~ArenaScene();
  ArenaScene(const ArenaScene&) = delete;
  ArenaScene& operator=(const ArenaScene&) = delete;

  struct Hit {
    float t = 0;  // in units of the direction's length
    ClassId label = ClassId::Unknown;
    bool hit = false;
  };

  // First surface along origin + t * direction with t in [t_near, t_far].
  Hit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near, float t_far) const;

  // A batch of rays from one origin: t_out[i] is the hit distance (infinity on
  // a miss), label_out[i] its class. Thread-safe; allocates nothing.
  void intersect_batch(const Eigen::Vector3f& origin, std::span<const Eigen::Vector3f> directions, float t_near,
                       float t_far, std::span<float> t_out, std::span<std::uint8_t> label_out,
                       RayBatchMode mode = RayBatchMode::Single) const;

  // Height of the highest terrain or ramp surface under (x, y) below z_top,
  // looking through walls and obstacles; 0 when there is none.
  double ground_height(double x, double y, double z_top) const;

  ClassId geometry_label(std::uint32_t geometry) const { return labels_[geometry]; }
  std::size_t geometry_count() const { return labels_.size(); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<ClassId> labels_;
};

}  // namespace sarmap::sim
