// Bounds of the kNN kernel's per-row state, which lives on the stack so the
// kernel never allocates: k neighbours of points of at most kKnnMaxDim floats.
#pragma once

#include <cstddef>

namespace sarmap::kernels {

inline constexpr std::size_t kKnnMaxK = 64;
inline constexpr std::size_t kKnnMaxDim = 256;
// Point indices travel through the kernel as float values, exact below 2^24.
inline constexpr std::size_t kKnnMaxCount = std::size_t{1} << 24;
// Candidates kept beyond k by the fast |b|^2 - 2a.b ranking, whose float
// rounding (about 1e-7 of |a|^2) can swap near-equal neighbours; the final k
// are chosen among them by exact differences in double. A row is redone
// exactly when the last candidate is not provably farther than the k-th
// (near or exact ties, e.g. a sparse block's repeated points). Eight keep
// such rows rare on real blocks, where four redid several times as many
// (docs/perf-history.md).
inline constexpr std::size_t kKnnExtra = 8;

// Up to this many dimensions, a tile of rows computes its box's distance to
// every panel at once, panels across the vector lanes (a few instructions per
// panel), instead of one panel at a time as it visits them; and only when the
// panels fit this many (a 4096-point block has 128 to 512).
inline constexpr std::size_t kKnnGapsUpFrontMaxDim = 4;
inline constexpr std::size_t kKnnGapsUpFrontMaxPanels = 1024;

// Above that many dimensions, a tile first tests a group of
// kKnnPanelsPerGroup consecutive panels by their common box, once, and skips
// the whole group when it is too far: most panels a tile tests are far (64-d
// on AVX2 above all, whose narrower panels make 256 of a 4096-point block).
// Only for clouds of at most
// kKnnMaxGroupedPanels panels (a tile keeps a bit per group on its stack).
inline constexpr std::size_t kKnnPanelsPerGroup = 8;
inline constexpr std::size_t kKnnMaxGroupedPanels = 16384;

// A row redone exactly ranks the points that could tie with its k-th
// neighbour; past this many (thousands of copies of one point) it ranks all.
inline constexpr std::size_t kKnnTieCandidates = 1024;

}  // namespace sarmap::kernels
