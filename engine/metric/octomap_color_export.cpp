#include "engine/metric/octomap_color_export.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <vector>

#include "engine/io/atomic_file.hpp"
#include "engine/metric/octomap_keys.hpp"

namespace sarmap::metric {

namespace {

// OctoMap's ColorOcTreeNode counts a colour as unset while it is white.
constexpr Rgb kNoColor{255, 255, 255};

bool same(const Rgb& a, const Rgb& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

struct Leaf {
  std::uint64_t code;  // Morton order of the OctoMap key
  std::int16_t log_odds;
  Rgb color;
};

struct NodeValue {
  float log_odds;
  Rgb color;
};

// A node is written as its float log-odds and r, g, b (ColorOcTreeNode's
// data), then one byte whose bit i says child i follows; children follow
// depth first. An inner node holds what OctoMap's updateInnerOccupancy would
// give it (the children's largest log-odds, the mean of their set colours),
// so a reader that never recomputes inner nodes still sees a consistent tree.
class ColorTreeWriter {
 public:
  // Nodes are appended to `data`.
  ColorTreeWriter(const std::vector<Leaf>& leaves, std::string& data) : data(data), leaves_(leaves) {}

  std::string& data;

  // The nodes write_node(begin, end, bit) writes, written nowhere: so that
  // the file's bytes can be reserved whole (a string grown by doubling held
  // up to three times the tree at the end of a building-sized run).
  std::size_t count_nodes(std::size_t begin, std::size_t end, int bit) const {
    if (bit < 0 || uniform_and_full(begin, end, bit)) return 1;
    std::size_t count = 1;
    for_each_child(begin, end, bit, [&](std::uint32_t, std::size_t child_begin, std::size_t child_end) {
      count += count_nodes(child_begin, child_end, bit - 1);
    });
    return count;
  }

  // Writes the node covering leaves_[begin, end), whose children split on key
  // bit `bit` (-1: a single voxel).
  NodeValue write_node(std::size_t begin, std::size_t end, int bit) {
    const std::size_t at = data.size();
    data.resize(at + 8);
    if (bit < 0 || uniform_and_full(begin, end, bit)) {
      // A pruned leaf stands for every voxel under it, all with one value.
      const NodeValue value{to_float(leaves_[begin].log_odds), leaves_[begin].color};
      put(at, value, 0);
      return value;
    }
    float max_log_odds = -std::numeric_limits<float>::infinity();
    int sum[3] = {0, 0, 0}, colored = 0;
    std::uint8_t children = 0;
    for_each_child(begin, end, bit, [&](std::uint32_t c, std::size_t child_begin, std::size_t child_end) {
      children |= static_cast<std::uint8_t>(1u << c);
      const NodeValue child = write_node(child_begin, child_end, bit - 1);
      max_log_odds = std::max(max_log_odds, child.log_odds);
      if (!same(child.color, kNoColor)) {
        sum[0] += child.color.r;
        sum[1] += child.color.g;
        sum[2] += child.color.b;
        ++colored;
      }
    });
    NodeValue value{max_log_odds, kNoColor};
    if (colored > 0) {
      value.color = {static_cast<std::uint8_t>(sum[0] / colored), static_cast<std::uint8_t>(sum[1] / colored),
                     static_cast<std::uint8_t>(sum[2] / colored)};
    }
    put(at, value, children);
    return value;
  }

 private:
  // Calls visit(c, child_begin, child_end) for each child c of the node
  // covering leaves_[begin, end) that splits on key bit `bit` and holds
  // leaves, in child order (the leaves are sorted by their codes).
  template <class Visit>
  void for_each_child(std::size_t begin, std::size_t end, int bit, Visit&& visit) const {
    for (std::size_t child_begin = begin; child_begin < end;) {
      const auto c = static_cast<std::uint32_t>((leaves_[child_begin].code >> (3 * bit)) & 7u);
      std::size_t child_end = child_begin + 1;
      while (child_end < end && ((leaves_[child_end].code >> (3 * bit)) & 7u) == c) ++child_end;
      visit(c, child_begin, child_end);
      child_begin = child_end;
    }
  }

  static float to_float(std::int16_t log_odds) { return static_cast<float>(log_odds / kLogOddsScale); }

  // True when the node splitting on `bit` has all 8^(bit + 1) voxels under it,
  // with one log-odds and one colour: then it is one leaf, losing nothing.
  bool uniform_and_full(std::size_t begin, std::size_t end, int bit) const {
    if (end - begin != std::uint64_t{1} << (3 * (bit + 1))) return false;
    const Leaf& first = leaves_[begin];
    for (std::size_t i = begin + 1; i < end; ++i) {
      if (leaves_[i].log_odds != first.log_odds || !same(leaves_[i].color, first.color)) return false;
    }
    return true;
  }

  // Little-endian, as OctoMap writes on every platform it runs on.
  void put(std::size_t at, const NodeValue& value, std::uint8_t children) {
    std::uint32_t bits;
    std::memcpy(&bits, &value.log_odds, sizeof bits);
    for (int i = 0; i < 4; ++i) data[at + i] = static_cast<char>((bits >> (8 * i)) & 0xFFu);
    data[at + 4] = static_cast<char>(value.color.r);
    data[at + 5] = static_cast<char>(value.color.g);
    data[at + 6] = static_cast<char>(value.color.b);
    data[at + 7] = static_cast<char>(children);
  }

  const std::vector<Leaf>& leaves_;
};

}  // namespace

std::string octomap_color_tree(const MetricMap& map, std::size_t* node_count) {
  std::vector<Leaf> leaves;
  leaves.reserve(map.counts().known);
  const OccupancyModel& occ = map.occupancy();
  map.blocks().for_each_block([&](const BlockKey& bk, const MetricMap::Blocks::Block& block) {
    for (int l = 0; l < kBlockVoxels; ++l) {
      const SemanticVoxel v = block.voxel(l);
      if (!v.known()) continue;
      const std::uint64_t code = octomap_keys::morton_of(voxel_of(bk, l), map.resolution(), ".ot");
      const Rgb color = occ.state(v.log_odds) == VoxelState::Occupied
                            ? class_info(LabelFusion::dominant(v.evidence)).color
                            : kNoColor;
      leaves.push_back({code, v.log_odds, color});
    }
  });
  std::sort(leaves.begin(), leaves.end(), [](const Leaf& a, const Leaf& b) { return a.code < b.code; });
  std::string bytes;
  ColorTreeWriter tree(leaves, bytes);
  const int top_bit = octomap_keys::kTreeDepth - 1;
  const std::size_t nodes = leaves.empty() ? 0 : tree.count_nodes(0, leaves.size(), top_bit);
  std::ostringstream header;
  header.precision(17);  // the resolution must read back as the same double
  header << "# Octomap OcTree file\n"
         << "# (feel free to add / change comments, but leave the first line as it is!)\n"
         << "#\n"
         << "# written by sarmap: occupied voxels in their class colour, free ones white (no colour)\n"
         << "id ColorOcTree\n"
         << "size " << nodes << "\n"
         << "res " << map.resolution() << "\n"
         << "data\n";
  const std::string head = header.str();
  bytes.reserve(head.size() + 8 * nodes);
  bytes.append(head);
  if (!leaves.empty()) tree.write_node(0, leaves.size(), top_bit);
  if (node_count) *node_count = nodes;
  return bytes;
}

void write_octomap_ot(const MetricMap& map, const std::filesystem::path& path) {
  const std::string bytes = octomap_color_tree(map);
  AtomicFileWriter out(path);
  out.write(bytes);
  out.commit();
}

}  // namespace sarmap::metric
