// A self-contained SplitMix64 generator, so samples are identical across
// standard libraries (std::shuffle and distributions are not specified bit-exactly).
#include "engine/semantic/dgcnn/block_sampling.hpp"

#include <cstddef>
#include <numeric>
#include <utility>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, bound) by the multiply-high method; its bias (< bound / 2^64) is negligible.
  std::uint64_t below(std::uint64_t bound) {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(next()) * bound) >> 64);
  }
};

}  // namespace

std::vector<std::uint32_t> sample_block(std::size_t count, std::size_t target, std::uint64_t seed,
                                        std::uint64_t block_index) {
  if (count == 0) throw Error(ErrorCode::InvalidArgument, "sample_block: a block with no points");
  SplitMix64 rng{seed ^ (block_index * 0xD1B54A32D192ED03ULL + 0x8CB92BA72F3D8DD7ULL)};
  rng.next();
  if (count >= target) {
    // Partial Fisher-Yates: the first `target` slots become a uniform draw without replacement.
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    for (std::size_t i = 0; i < target; ++i) {
      const std::size_t j = i + static_cast<std::size_t>(rng.below(count - i));
      std::swap(order[i], order[j]);
    }
    order.resize(target);
    return order;
  }
  std::vector<std::uint32_t> out(target);
  std::iota(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(count), 0u);
  for (std::size_t i = count; i < target; ++i) out[i] = static_cast<std::uint32_t>(rng.below(count));
  return out;
}

}  // namespace sarmap
