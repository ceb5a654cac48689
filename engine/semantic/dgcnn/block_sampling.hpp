// Draws exactly the DGCNN's points_per_block samples from one block, seeded
// per block so the result does not depend on thread count or block order of work.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sarmap {

// Positions into a block of `count` points, `target` of them: distinct positions
// chosen at random when count >= target, otherwise every position once followed
// by random repeats. Deterministic in (seed, block_index). Throws on count == 0.
std::vector<std::uint32_t> sample_block(std::size_t count, std::size_t target, std::uint64_t seed,
                                        std::uint64_t block_index);

}  // namespace sarmap
