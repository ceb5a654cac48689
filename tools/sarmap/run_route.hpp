// A route planned on what a run folder holds (graph.json on segments.json and
// map.sarmap): `sarmap plan`'s work, and the path `sarmap demo` draws in its
// picture.
#pragma once

#include <filesystem>

#include <Eigen/Core>

#include "engine/topo/route_planner.hpp"

namespace sarmap::cli {

// Checks the folder against its manifest first. Throws sarmap::Error naming
// the folder or file when it is not a finished run or lacks a file routes need.
topo::Route plan_on_run(const std::filesystem::path& run, const Eigen::Vector3d& from,
                        const Eigen::Vector3d& to, topo::RouteGraph graph, topo::RouteSearch search);

}  // namespace sarmap::cli
