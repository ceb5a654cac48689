// Bounds of the EdgeConv kernels' stack tiles, so they never allocate.
#pragma once

#include <cstddef>

namespace sarmap::kernels {

inline constexpr std::size_t kEdgeMaxHidden = 256;   // channels between the two convolutions
inline constexpr std::size_t kEdgeMaxOut = 256;      // output channels
inline constexpr std::size_t kEdgeMaxK = 64;         // neighbours per point
inline constexpr std::size_t kEdgeTileFloats = 8192; // edge rows x hidden per tile (32 KiB, L1)
inline constexpr std::size_t kEdgeMaxTilePoints = 32;

}  // namespace sarmap::kernels
