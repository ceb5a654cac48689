// Occupied voxels as files other tools open: one point per voxel at its
// centre with its class (label), class colour and occupancy probability, for
// voxels.ply, `sarmap convert map.sarmap` and the viewer; or each voxel as a
// coloured cube mesh for viewers that know no voxels. Both files name the
// voxel size in their header ("voxel_size 0.05"; docs/formats.md).
#pragma once

#include <filesystem>
#include <string>

#include "engine/core/point_buffer.hpp"
#include "engine/metric/metric_map.hpp"

namespace sarmap::metric {

// One point per occupied voxel, in (z, y, x) block order: x y z at the voxel
// centre, labels = dominant class, colours from the class table, score
// channel "probability" = occupancy probability (PLY scalar_probability).
PointBuffer occupied_voxel_cloud(const MetricMap& map);

// The header comment that carries the voxel edge: "voxel_size 0.05" (the
// shortest decimal that reads back as the map's resolution).
std::string voxel_size_comment(const MetricMap& map);

// Writes occupied_voxel_cloud() as .ply or .pcd (by extension; binary or
// ASCII) with voxel_size_comment() in the header, atomically. Throws
// sarmap::Error for another extension or when the file cannot be written.
void write_voxel_cloud(const MetricMap& map, const std::filesystem::path& path, bool binary = true);

// Writes every occupied voxel as a cube: 8 vertices (in the class colour) and
// 6 outward-facing quads per voxel, in the order of occupied_voxel_cloud(),
// as a binary PLY mesh with voxel_size_comment() in the header, atomically.
// Throws sarmap::Error (InvalidArgument) for a path that is not .ply.
void write_voxel_cubes(const MetricMap& map, const std::filesystem::path& path);

}  // namespace sarmap::metric
