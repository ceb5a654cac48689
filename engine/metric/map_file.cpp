#include "engine/metric/map_file.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <zlib.h>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/metric/semantic_block.hpp"

namespace sarmap::metric {

namespace {

constexpr char kMagic[8] = {'S', 'A', 'R', 'M', 'A', 'P', 'V', 'X'};
// Version 1 stores every voxel (dense) as i16 log_odds + i16 evidence[6]
// (layout 1), version 2 the same values compactly (layout 2), both in the
// units of their day (log-odds 1/1024 nat, Bayesian evidence 1/256 nat);
// version 3 stores today's values compactly, a byte each (layout 3).
constexpr std::uint8_t kDenseLayout = 1;
constexpr std::uint8_t kWideCompactLayout = 2;
constexpr std::uint8_t kCompactLayout = 3;
constexpr std::uint16_t kWidePayloadBytes = 14;
constexpr std::uint16_t kPayloadBytes = 7;
constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 1 + 1 + 2 + 8 * 8 + 8;
constexpr std::size_t kDenseBlockBytes = 12 + kBlockVoxels * kWidePayloadBytes;
constexpr std::size_t kMaskWords = kBlockVoxels / 64;
// Bytes of one log-odds value and of one evidence row, by version.
std::size_t value_bytes(std::uint32_t version) { return version >= 3 ? 1 : 2; }
std::size_t row_bytes(std::uint32_t version) { return kClassCount * value_bytes(version); }

// Versions 1 and 2 in today's units: log-odds from 1/1024 to 1/32 nat,
// Bayesian evidence from 1/256 to 1/6 nat, histogram counts halved (every
// class, keeping their ratios) until they fit a byte; clamped as updates are.
std::int16_t log_odds_from_wide(std::int16_t wide, const OccupancyModel& occ) {
  if (wide == kUnknownLogOdds) return wide;
  const long v = std::lround(wide * kLogOddsScale / 1024.0);
  return static_cast<std::int16_t>(std::clamp<long>(v, occ.min(), occ.max()));
}
ClassEvidence evidence_from_wide(const ClassEvidence& wide, const LabelFusion& fusion) {
  ClassEvidence out{};
  if (fusion.settings().fusion == ClassFusion::Bayesian) {
    const long clamp = fusion.evidence_clamp_units();
    for (std::size_t c = 0; c < kClassCount; ++c) {
      out[c] = static_cast<std::int16_t>(std::clamp<long>(std::lround(wide[c] * kEvidenceScale / 256.0), -clamp, clamp));
    }
    return out;
  }
  std::array<int, kClassCount> counts{};
  for (std::size_t c = 0; c < kClassCount; ++c) counts[c] = std::max(0, int{wide[c]});
  saturate_counts(counts);
  for (std::size_t c = 0; c < kClassCount; ++c) out[c] = static_cast<std::int16_t>(counts[c]);
  return out;
}
// A compact block: key, occupancy kind, then one log-odds or 512.
constexpr std::uint8_t kUniformOccupancy = 0;
constexpr std::uint8_t kPerVoxelOccupancy = 1;
constexpr std::size_t kCompactBlockMinBytes = 12 + 1 + 2 + kMaskWords * 8;

// Little-endian encoding, independent of the host's byte order.
class Encoder {
 public:
  void u8(std::uint8_t v) { bytes.push_back(static_cast<char>(v)); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void u64(std::uint64_t v) { le(v, 8); }
  void i8(std::int8_t v) { u8(static_cast<std::uint8_t>(v)); }
  void i16(std::int16_t v) { u16(static_cast<std::uint16_t>(v)); }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  std::string bytes;

 private:
  void le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
};

class Decoder {
 public:
  Decoder(const std::string& data, std::size_t at) : data_(data), at_(at) {}
  std::size_t offset() const { return at_; }
  std::uint64_t le(int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{static_cast<unsigned char>(data_[at_ + i])} << (8 * i);
    at_ += n;
    return v;
  }
  std::uint8_t u8() { return static_cast<std::uint8_t>(le(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(le(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(le(4)); }
  std::uint64_t u64() { return le(8); }
  std::int8_t i8() { return static_cast<std::int8_t>(u8()); }
  std::int16_t i16() { return static_cast<std::int16_t>(u16()); }
  // One log-odds value as `version` stores it (1 byte from version 3, else 2).
  std::int16_t log_odds(std::uint32_t version) { return version >= 3 ? log_odds_of(i8()) : i16(); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  double f64() {
    const std::uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }

 private:
  const std::string& data_;
  std::size_t at_;
};

std::uint32_t crc_of(const char* data, std::size_t size, std::uint32_t crc = 0) {
  // zlib's crc32 takes a uInt length; feed large buffers in pieces.
  while (size > 0) {
    const std::size_t n = std::min<std::size_t>(size, 1u << 30);
    crc = static_cast<std::uint32_t>(crc32(crc, reinterpret_cast<const Bytef*>(data), static_cast<uInt>(n)));
    data += n;
    size -= n;
  }
  return crc;
}


// The block as version 3 stores it. Uniformity and which voxels hold a row
// are read from the values, not from how the block happens to be stored.
void encode_compact_block(Encoder& out, const BlockKey& key, const SemanticBlock& block) {
  out.i32(key.x);
  out.i32(key.y);
  out.i32(key.z);
  if (SemanticBlocks::uniform_slab(block)) {
    out.u8(kUniformOccupancy);
    out.i8(stored_log_odds(block.log_odds(0)));
  } else {
    out.u8(kPerVoxelOccupancy);
    for (int l = 0; l < kBlockVoxels; ++l) out.i8(stored_log_odds(block.log_odds(l)));
  }
  const DenseVoxels voxels = block.dense();
  std::array<std::uint64_t, kMaskWords> mask{};
  for (int l = 0; l < kBlockVoxels; ++l) {
    if (!no_evidence(voxels[l].evidence)) mask[l >> 6] |= std::uint64_t{1} << (l & 63);
  }
  for (std::uint64_t word : mask) out.u64(word);
  for (int l = 0; l < kBlockVoxels; ++l) {
    if ((mask[l >> 6] >> (l & 63)) & 1u) {
      for (std::int16_t e : voxels[l].evidence) out.i8(static_cast<std::int8_t>(e));
    }
  }
}

// Walks `count` compact blocks from `at` by their sizes alone, without
// reading values: where they end, or where the bytes before `end` run out,
// or where a block names an occupancy kind that does not exist (whose
// size is then unknown).
struct CompactWalk {
  enum class Outcome { Ends, RunsOut, UnknownOccupancy } outcome;
  std::size_t at;  // the end, or the block (RunsOut) or byte (UnknownOccupancy) where it stopped
};
CompactWalk walk_compact_blocks(const std::string& data, std::size_t at, std::size_t end, std::uint64_t count,
                                std::uint32_t version) {
  for (std::uint64_t b = 0; b < count; ++b) {
    const std::size_t block_at = at;
    if (end - at < 13) return {CompactWalk::Outcome::RunsOut, block_at};
    const auto kind = static_cast<std::uint8_t>(data[at + 12]);
    if (kind != kUniformOccupancy && kind != kPerVoxelOccupancy) {
      return {CompactWalk::Outcome::UnknownOccupancy, at + 12};
    }
    at += 13;
    const std::size_t occupancy_bytes = (kind == kUniformOccupancy ? 1 : kBlockVoxels) * value_bytes(version);
    if (end - at < occupancy_bytes + kMaskWords * 8) return {CompactWalk::Outcome::RunsOut, block_at};
    at += occupancy_bytes;
    Decoder mask(data, at);
    std::size_t rows = 0;
    for (std::size_t w = 0; w < kMaskWords; ++w) rows += static_cast<std::size_t>(std::popcount(mask.u64()));
    at += kMaskWords * 8;
    if (end - at < rows * row_bytes(version)) return {CompactWalk::Outcome::RunsOut, block_at};
    at += rows * row_bytes(version);
  }
  return {CompactWalk::Outcome::Ends, at};
}

}  // namespace

bool is_map_file_path(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".sarmap";
}

void save_map(const MetricMap& map, const std::filesystem::path& path) {
  const MetricMapSettings& s = map.settings();
  const auto keys = map.blocks().sorted_block_keys();
  Encoder header;
  header.bytes.append(kMagic, 8);
  header.u32(kMapFileVersion);
  header.f64(s.resolution);
  header.u8(static_cast<std::uint8_t>(s.fusion.fusion));
  header.u8(kCompactLayout);
  header.u16(kPayloadBytes);
  for (double v : {s.occupancy.prob_hit, s.occupancy.prob_miss, s.occupancy.clamp_min, s.occupancy.clamp_max,
                   s.occupancy.occupied_threshold, s.fusion.label_confidence, s.fusion.evidence_clamp,
                   s.fusion.free_evidence_keep}) {
    header.f64(v);
  }
  header.u64(keys.size());
  AtomicFileWriter out(path);
  out.write(header.bytes);
  std::uint32_t crc = crc_of(header.bytes.data(), header.bytes.size());
  Encoder block;
  for (const BlockKey& k : keys) {
    block.bytes.clear();
    encode_compact_block(block, k, *map.blocks().find(k));
    crc = crc_of(block.bytes.data(), block.bytes.size(), crc);
    out.write(block.bytes);
  }
  Encoder tail;
  tail.u32(crc);
  out.write(tail.bytes);
  out.commit();
}

MetricMap load_map(const std::filesystem::path& path) { return read_map_file(path).map; }

MapFile read_map_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec;
    throw Error(ErrorCode::Io, "cannot open metric map file " + name +
                                   (std::filesystem::exists(path, ec) ? "" : ": no such file"));
  }
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(ErrorCode::Io, "cannot read metric map file " + name);
  const auto fail = [&](std::size_t offset, const std::string& what) -> Error {
    return Error(ErrorCode::Parse, at_offset(name, offset, what));
  };
  if (data.size() < kHeaderBytes + 4) {
    throw fail(data.size(), "truncated: a metric map file has at least " + std::to_string(kHeaderBytes + 4) +
                                " bytes, this one has " + std::to_string(data.size()));
  }
  if (std::memcmp(data.data(), kMagic, 8) != 0) throw fail(0, "not a sarmap metric map (magic \"SARMAPVX\" missing)");
  Decoder d(data, 8);
  const std::uint32_t version = d.u32();
  if (version < 1 || version > kMapFileVersion) {
    throw fail(8, "unsupported version " + std::to_string(version) + " (this build reads versions 1 to " +
                      std::to_string(kMapFileVersion) + ")");
  }
  const std::uint8_t expected_layout = version == 1 ? kDenseLayout : version == 2 ? kWideCompactLayout : kCompactLayout;
  const std::uint16_t expected_payload = version >= 3 ? kPayloadBytes : kWidePayloadBytes;
  MetricMapSettings s;
  s.resolution = d.f64();
  const std::size_t fusion_at = d.offset();
  const std::uint8_t fusion = d.u8();
  if (fusion > 1) throw fail(fusion_at, "unknown class fusion " + std::to_string(fusion) + " (expected 0 or 1)");
  s.fusion.fusion = static_cast<ClassFusion>(fusion);
  const std::size_t layout_at = d.offset();
  const std::uint8_t layout = d.u8();
  const std::uint16_t payload = d.u16();
  if (layout != expected_layout || payload != expected_payload) {
    throw fail(layout_at, "unsupported voxel payload layout " + std::to_string(layout) + " of " +
                              std::to_string(payload) + " bytes (version " + std::to_string(version) +
                              " expects layout " + std::to_string(expected_layout) + " of " +
                              std::to_string(expected_payload) + " bytes)");
  }
  s.occupancy.prob_hit = d.f64();
  s.occupancy.prob_miss = d.f64();
  s.occupancy.clamp_min = d.f64();
  s.occupancy.clamp_max = d.f64();
  s.occupancy.occupied_threshold = d.f64();
  s.fusion.label_confidence = d.f64();
  s.fusion.evidence_clamp = d.f64();
  s.fusion.free_evidence_keep = d.f64();
  // Before version 3 the clamp could reach 120 nats; today's byte holds 21.
  if (version < 3 && s.fusion.evidence_clamp > kMaxEvidenceClamp) s.fusion.evidence_clamp = kMaxEvidenceClamp;
  const std::size_t count_at = d.offset();
  const std::uint64_t count = d.u64();
  const std::size_t blocks_end = data.size() - 4;
  Decoder crc_reader(data, blocks_end);
  const bool checksum_ok = crc_of(data.data(), blocks_end) == crc_reader.u32();
  // The blocks' sizes first, so that a short file is called truncated, not corrupt.
  if (version == 1) {
    const std::uint64_t max_blocks = (blocks_end - kHeaderBytes) / kDenseBlockBytes;
    if (count > max_blocks || kHeaderBytes + count * kDenseBlockBytes != blocks_end) {
      const unsigned long long expected = count <= (1ull << 40) ? kHeaderBytes + count * kDenseBlockBytes + 4 : 0;
      throw fail(count_at, "header declares " + std::to_string(count) + " blocks, which take " +
                               (expected ? std::to_string(expected) : std::string("more than 2^40")) +
                               " bytes, but the file has " + std::to_string(data.size()) +
                               (data.size() < expected ? " (truncated)" : " (trailing bytes)"));
    }
  } else {
    const std::uint64_t max_blocks = (blocks_end - kHeaderBytes) / kCompactBlockMinBytes;
    if (count > max_blocks) {
      throw fail(count_at, "header declares " + std::to_string(count) + " blocks, but the file's " +
                               std::to_string(data.size()) + " bytes hold at most " + std::to_string(max_blocks) +
                               " (truncated)");
    }
    const CompactWalk walk = walk_compact_blocks(data, kHeaderBytes, blocks_end, count, version);
    if (walk.outcome == CompactWalk::Outcome::RunsOut) {
      throw fail(walk.at, "truncated: the file ends inside one of the " + std::to_string(count) +
                              " blocks its header declares");
    }
    if (checksum_ok && walk.outcome == CompactWalk::Outcome::UnknownOccupancy) {
      throw fail(walk.at, "unknown block occupancy kind " + std::to_string(static_cast<unsigned char>(data[walk.at])) +
                              " (expected 0, one value, or 1, one per voxel)");
    }
    if (walk.outcome == CompactWalk::Outcome::Ends && walk.at != blocks_end) {
      throw fail(walk.at, "trailing bytes: the header's " + std::to_string(count) + " blocks end at byte " +
                              std::to_string(walk.at) + " of " + std::to_string(blocks_end));
    }
  }
  if (!checksum_ok) throw fail(blocks_end, "checksum mismatch: the file is corrupt");
  MetricMap map = [&] {
    try {
      return MetricMap(s);
    } catch (const Error& e) {
      throw fail(8 + 4, std::string("invalid settings in header: ") + e.what());
    }
  }();
  const OccupancyModel& occ = map.occupancy();
  // Versions 1 and 2 hold log-odds in 1/1024 nat: their clamp range then.
  const auto wide = [&](double p) { return std::lround(std::log(p / (1 - p)) * 1024.0); };
  const long min = version >= 3 ? occ.min() : wide(s.occupancy.clamp_min);
  const long max = version >= 3 ? occ.max() : wide(s.occupancy.clamp_max);
  const auto check_log_odds = [&](std::int16_t v, std::size_t at) {
    if (v != kUnknownLogOdds && (v < min || v > max)) {
      throw fail(at, "voxel log-odds " + std::to_string(v) + " outside the clamp range [" + std::to_string(min) +
                         ", " + std::to_string(max) + "]");
    }
  };
  const auto check_evidence = [&](const ClassEvidence& e, std::size_t at) {
    if (version >= 3 && !storable_evidence(e)) {
      throw fail(at, "class evidence -128 is outside +-" + std::to_string(kMaxEvidence));
    }
  };
  const std::int32_t max_block = static_cast<std::int32_t>((kMaxCoordinate / s.resolution) / kBlockEdge) + 1;
  for (std::uint64_t b = 0; b < count; ++b) {
    const std::size_t at = d.offset();
    const BlockKey key{d.i32(), d.i32(), d.i32()};
    // In 64 bits: std::abs of INT32_MIN overflows (undefined behaviour).
    const auto beyond = [max_block](std::int32_t v) { return std::abs(std::int64_t{v}) > max_block; };
    if (beyond(key.x) || beyond(key.y) || beyond(key.z)) {
      throw fail(at, "block (" + std::to_string(key.x) + ", " + std::to_string(key.y) + ", " +
                         std::to_string(key.z) + ") lies beyond the map limits of +-10 km");
    }
    if (map.blocks().find(key)) throw fail(at, "block stored twice");
    DenseVoxels voxels;
    if (version == 1) {
      for (SemanticVoxel& v : voxels) {
        const std::size_t voxel_at = d.offset();
        v.log_odds = d.i16();
        for (auto& e : v.evidence) e = d.i16();
        check_log_odds(v.log_odds, voxel_at);
      }
    } else {
      const std::size_t stored = d.u8() == kUniformOccupancy ? 1 : kBlockVoxels;
      for (std::size_t l = 0; l < stored; ++l) {
        const std::size_t voxel_at = d.offset();
        voxels[l].log_odds = d.log_odds(version);
        check_log_odds(voxels[l].log_odds, voxel_at);
      }
      if (stored == 1) {
        for (SemanticVoxel& v : voxels) v.log_odds = voxels[0].log_odds;
      }
      std::array<std::uint64_t, kMaskWords> mask;
      for (std::uint64_t& word : mask) word = d.u64();
      for (int l = 0; l < kBlockVoxels; ++l) {
        if (!((mask[l >> 6] >> (l & 63)) & 1u)) continue;
        const std::size_t row_at = d.offset();
        for (auto& e : voxels[l].evidence) e = version >= 3 ? d.i8() : d.i16();
        check_evidence(voxels[l].evidence, row_at);
        if (no_evidence(voxels[l].evidence)) {
          throw fail(row_at, "voxel " + std::to_string(l) + " of block (" + std::to_string(key.x) + ", " +
                                 std::to_string(key.y) + ", " + std::to_string(key.z) +
                                 ") has an all-zero evidence row (a voxel without evidence holds none)");
        }
      }
    }
    if (version < 3) {
      for (SemanticVoxel& v : voxels) {
        v.log_odds = log_odds_from_wide(v.log_odds, occ);
        v.evidence = evidence_from_wide(v.evidence, map.fusion());
      }
    }
    map.blocks().assign(key, voxels);
  }
  return {std::move(map), version};
}

}  // namespace sarmap::metric
