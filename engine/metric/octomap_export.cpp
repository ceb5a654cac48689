#include "engine/metric/octomap_export.hpp"

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "engine/io/atomic_file.hpp"
#include "engine/metric/octomap_keys.hpp"

namespace sarmap::metric {

namespace {

using octomap_keys::kTreeDepth;

// Entries are (morton << 1) | occupied, sorted, so every subtree is a range.
class TreeWriter {
 public:
  explicit TreeWriter(const std::vector<std::uint64_t>& leaves) : leaves_(leaves) {}

  std::string data;
  std::size_t nodes = 1;  // the root

  // Writes the node covering leaves_[begin, end) whose children split on key bit `bit`.
  void write_inner(std::size_t begin, std::size_t end, int bit) {
    std::size_t child_begin[8], child_end[8];
    std::uint8_t code[8];  // 0 none, 1 free leaf, 2 occupied leaf, 3 inner
    std::size_t at = begin;
    for (std::uint32_t c = 0; c < 8; ++c) {
      child_begin[c] = at;
      while (at < end && ((leaves_[at] >> (1 + 3 * bit)) & 7u) == c) ++at;
      child_end[c] = at;
      code[c] = child_code(child_begin[c], child_end[c], bit);
      if (code[c] != 0) ++nodes;
    }
    std::uint8_t bytes[2] = {0, 0};
    for (int c = 0; c < 8; ++c) {
      // Per child, 2 bits: 10 free leaf, 01 occupied leaf, 11 has children (bitset bit 2i, 2i+1).
      const int i = c & 3;
      std::uint8_t& byte = bytes[c >> 2];
      if (code[c] == 1 || code[c] == 3) byte |= static_cast<std::uint8_t>(1u << (2 * i));
      if (code[c] == 2 || code[c] == 3) byte |= static_cast<std::uint8_t>(1u << (2 * i + 1));
    }
    data.push_back(static_cast<char>(bytes[0]));
    data.push_back(static_cast<char>(bytes[1]));
    for (int c = 0; c < 8; ++c) {
      if (code[c] == 3) write_inner(child_begin[c], child_end[c], bit - 1);
    }
  }

 private:
  std::uint8_t child_code(std::size_t begin, std::size_t end, int bit) const {
    if (begin == end) return 0;
    const std::uint64_t full = std::uint64_t{1} << (3 * bit);  // voxels under the child
    if (end - begin == full) {
      const std::uint64_t state = leaves_[begin] & 1u;
      bool uniform = true;
      for (std::size_t i = begin + 1; i < end && uniform; ++i) uniform = (leaves_[i] & 1u) == state;
      if (uniform) return state ? 2 : 1;
    }
    return 3;
  }
  const std::vector<std::uint64_t>& leaves_;
};

}  // namespace

std::string octomap_binary(const MetricMap& map, std::size_t* node_count) {
  std::vector<std::uint64_t> leaves;
  const OccupancyModel& occ = map.occupancy();
  map.blocks().for_each_block([&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
    for (int l = 0; l < kBlockVoxels; ++l) {
      const SemanticVoxel v = block.voxel(l);
      if (!v.known()) continue;
      const std::uint64_t code = octomap_keys::morton_of(voxel_of(bk, l), map.resolution(), ".bt");
      const bool occupied = occ.state(v.log_odds) == VoxelState::Occupied;
      leaves.push_back(code << 1 | (occupied ? 1u : 0u));
    }
  });
  std::sort(leaves.begin(), leaves.end());
  TreeWriter tree(leaves);
  if (!leaves.empty()) tree.write_inner(0, leaves.size(), kTreeDepth - 1);
  const std::size_t nodes = leaves.empty() ? 0 : tree.nodes;
  if (node_count) *node_count = nodes;
  std::ostringstream header;
  header.precision(17);  // the resolution must read back as the same double
  header << "# Octomap OcTree binary file\n"
         << "# (feel free to add / change comments, but leave the first line as it is!)\n"
         << "#\n"
         << "# written by sarmap\n"
         << "id OcTree\n"
         << "size " << nodes << "\n"
         << "res " << map.resolution() << "\n"
         << "data\n";
  return header.str() + tree.data;
}

void write_octomap_bt(const MetricMap& map, const std::filesystem::path& path) {
  const std::string bytes = octomap_binary(map);
  AtomicFileWriter out(path);
  out.write(bytes);
  out.commit();
}

}  // namespace sarmap::metric

