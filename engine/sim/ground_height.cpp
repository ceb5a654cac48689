#include "engine/sim/ground_height.hpp"

#include <limits>

namespace sarmap::sim {

double ground_height(const geometry::TriangleScene& scene, double x, double y, double z_top) {
  const Eigen::Vector3f origin(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z_top));
  const Eigen::Vector3f down(0, 0, -1);
  float t_near = 0;
  // Steps past walls and obstacles until it meets terrain or a ramp.
  for (int step = 0; step < 64; ++step) {
    const geometry::TriangleScene::Hit h =
        scene.intersect(origin, down, t_near, std::numeric_limits<float>::infinity());
    if (!h.hit) return 0;
    if (h.label == ClassId::Terrain || h.label == ClassId::InclinedRamp || h.label == ClassId::FlatRamp) {
      return z_top - h.t;
    }
    t_near = h.t + 1e-4f;
  }
  return 0;
}

}  // namespace sarmap::sim
