#include "engine/geometry/classed_mesh.hpp"

#include <cmath>

#include "engine/core/error.hpp"
#include "engine/geometry/float_limits.hpp"

namespace sarmap::geometry {

void validate_mesh(const ClassedMesh& m) {
  if (m.indices.size() % 3 != 0)
    throw Error(ErrorCode::InvalidData, m.name + ": index count is not a multiple of 3");
  for (std::uint32_t i : m.indices) {
    if (i >= m.vertices.size()) throw Error(ErrorCode::InvalidData, m.name + ": triangle index out of range");
  }
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const Eigen::Vector3f& v = m.vertices[i];
    if (!v.allFinite()) {
      throw Error(ErrorCode::InvalidData, m.name + ": vertex " + std::to_string(i) + " is not finite");
    }
    if (v.cwiseAbs().maxCoeff() > kMaxSceneCoordinate) {
      throw Error(ErrorCode::InvalidData, m.name + ": vertex " + std::to_string(i) + " lies beyond " +
                                              std::to_string(static_cast<int>(kMaxSceneCoordinate)) + " m");
    }
  }
}

}  // namespace sarmap::geometry
