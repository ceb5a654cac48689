#include "engine/metric/map_file.hpp"

#include <cctype>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <zlib.h>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"

namespace sarmap::metric {

namespace {

constexpr char kMagic[8] = {'S', 'A', 'R', 'M', 'A', 'P', 'V', 'X'};
constexpr std::uint8_t kPayloadLayout = 1;  // i16 log_odds + i16 evidence[6]
constexpr std::uint16_t kPayloadBytes = 14;
constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 1 + 1 + 2 + 8 * 8 + 8;
constexpr std::size_t kBlockBytes = 12 + kBlockVoxels * kPayloadBytes;

// Little-endian encoding, independent of the host's byte order.
class Encoder {
 public:
  void u8(std::uint8_t v) { bytes.push_back(static_cast<char>(v)); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void u64(std::uint64_t v) { le(v, 8); }
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
  std::int16_t i16() { return static_cast<std::int16_t>(u16()); }
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
  header.u8(kPayloadLayout);
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
    block.i32(k.x);
    block.i32(k.y);
    block.i32(k.z);
    for (const SemanticVoxel& v : map.blocks().find(k)->dense()) {
      block.i16(v.log_odds);
      for (std::int16_t e : v.evidence) block.i16(e);
    }
    crc = crc_of(block.bytes.data(), block.bytes.size(), crc);
    out.write(block.bytes);
  }
  Encoder tail;
  tail.u32(crc);
  out.write(tail.bytes);
  out.commit();
}

MetricMap load_map(const std::filesystem::path& path) {
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
  if (version != kMapFileVersion) {
    throw fail(8, "unsupported version " + std::to_string(version) + " (this build reads version " +
                      std::to_string(kMapFileVersion) + ")");
  }
  MetricMapSettings s;
  s.resolution = d.f64();
  const std::size_t fusion_at = d.offset();
  const std::uint8_t fusion = d.u8();
  if (fusion > 1) throw fail(fusion_at, "unknown class fusion " + std::to_string(fusion) + " (expected 0 or 1)");
  s.fusion.fusion = static_cast<ClassFusion>(fusion);
  const std::size_t layout_at = d.offset();
  const std::uint8_t layout = d.u8();
  const std::uint16_t payload = d.u16();
  if (layout != kPayloadLayout || payload != kPayloadBytes) {
    throw fail(layout_at, "unsupported voxel payload layout " + std::to_string(layout) + " of " +
                              std::to_string(payload) + " bytes (expected layout 1 of 14 bytes)");
  }
  s.occupancy.prob_hit = d.f64();
  s.occupancy.prob_miss = d.f64();
  s.occupancy.clamp_min = d.f64();
  s.occupancy.clamp_max = d.f64();
  s.occupancy.occupied_threshold = d.f64();
  s.fusion.label_confidence = d.f64();
  s.fusion.evidence_clamp = d.f64();
  s.fusion.free_evidence_keep = d.f64();
  const std::size_t count_at = d.offset();
  const std::uint64_t count = d.u64();
  const std::uint64_t max_blocks = (data.size() - kHeaderBytes - 4) / kBlockBytes;
  if (count > max_blocks || kHeaderBytes + count * kBlockBytes + 4 != data.size()) {
    const unsigned long long expected = count <= (1ull << 40) ? kHeaderBytes + count * kBlockBytes + 4 : 0;
    throw fail(count_at, "header declares " + std::to_string(count) + " blocks, which take " +
                             (expected ? std::to_string(expected) : std::string("more than 2^40")) +
                             " bytes, but the file has " + std::to_string(data.size()) +
                             (data.size() < expected ? " (truncated)" : " (trailing bytes)"));
  }
  Decoder crc_reader(data, data.size() - 4);
  const std::uint32_t stored_crc = crc_reader.u32();
  if (crc_of(data.data(), data.size() - 4) != stored_crc) {
    throw fail(data.size() - 4, "checksum mismatch: the file is corrupt");
  }
  MetricMap map = [&] {
    try {
      return MetricMap(s);
    } catch (const Error& e) {
      throw fail(8 + 4, std::string("invalid settings in header: ") + e.what());
    }
  }();
  const OccupancyModel& occ = map.occupancy();
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
    for (SemanticVoxel& v : voxels) {
      const std::size_t voxel_at = d.offset();
      v.log_odds = d.i16();
      for (auto& e : v.evidence) e = d.i16();
      if (v.log_odds != kUnknownLogOdds && (v.log_odds < occ.min() || v.log_odds > occ.max())) {
        throw fail(voxel_at, "voxel log-odds " + std::to_string(v.log_odds) + " outside the clamp range [" +
                                 std::to_string(occ.min()) + ", " + std::to_string(occ.max()) + "]");
      }
    }
    map.blocks().assign(key, voxels);
  }
  return map;
}

}  // namespace sarmap::metric
