#include "engine/topo/topo_settings.hpp"

#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap::topo {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw Error(ErrorCode::InvalidArgument, std::string("topo settings: ") + what);
}

bool positive(double v) { return v > 0 && std::isfinite(v); }

}  // namespace

void validate(const TopoSettings& s) {
  require(s.robot_radius >= 0 && std::isfinite(s.robot_radius), "robot_radius must be >= 0");
  require(positive(s.robot_height), "robot_height must be > 0");
  require(!s.body_heights.empty(), "body_heights must name at least one height");
  for (double h : s.body_heights) {
    require(h >= 0 && std::isfinite(h), "body_heights must be >= 0");
  }
  require(s.max_slope_deg > 0 && s.max_slope_deg < 90, "max_slope_deg must be in (0, 90)");
  require(s.max_step >= 0 && std::isfinite(s.max_step), "max_step must be >= 0");
  require(positive(s.node_spacing) && s.node_spacing >= 0.05, "node_spacing must be at least 0.05 m");
  require(positive(s.edge_radius), "edge_radius must be > 0");
  require(s.edge_radius <= 100 * s.node_spacing, "edge_radius must be at most 100 node spacings");
}

}  // namespace sarmap::topo
