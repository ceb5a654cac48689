#include "engine/io/lzf.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "engine/core/error.hpp"

namespace sarmap {
namespace {

constexpr std::size_t kMaxLiteral = 32;                // control bytes 0..31
constexpr std::size_t kMaxOffset = 1 << 13;            // 13 bits of distance
constexpr std::size_t kMaxMatch = (7 + 255) + 2;       // longest back-reference
constexpr unsigned kHashBits = 14;

unsigned hash3(const std::uint8_t* p) {
  const std::uint32_t v = (std::uint32_t{p[0]} << 16) | (std::uint32_t{p[1]} << 8) | p[2];
  return (v * 2654435761u) >> (32 - kHashBits);
}

[[noreturn]] void malformed(std::size_t position, const std::string& what) {
  throw Error(ErrorCode::Parse, "LZF data (byte " + std::to_string(position) + " of the compressed block): " + what);
}

}  // namespace

std::vector<std::uint8_t> lzf_compress(std::span<const std::uint8_t> data) {
  const std::size_t n = data.size();
  std::vector<std::uint8_t> out;
  out.reserve(n + n / kMaxLiteral + 2);
  if (n == 0) return out;
  const std::uint8_t* in = data.data();
  // Last position + 1 where each 3-byte hash was seen; 0 means never.
  std::vector<std::size_t> seen(std::size_t{1} << kHashBits, 0);

  std::size_t control = out.size();  // index of the pending literal run's control byte
  out.push_back(0);
  std::size_t literals = 0;
  auto emit_literal = [&](std::uint8_t byte) {
    out.push_back(byte);
    if (++literals == kMaxLiteral) {
      out[control] = static_cast<std::uint8_t>(literals - 1);
      literals = 0;
      control = out.size();
      out.push_back(0);
    }
  };

  std::size_t ip = 0;
  while (ip + 2 < n) {
    const unsigned h = hash3(in + ip);
    const std::size_t candidate = seen[h];
    seen[h] = ip + 1;
    if (candidate != 0) {
      const std::size_t ref = candidate - 1;
      const std::size_t distance = ip - ref;  // >= 1
      if (distance <= kMaxOffset && std::memcmp(in + ref, in + ip, 3) == 0) {
        const std::size_t limit = std::min(kMaxMatch, n - ip);
        std::size_t length = 3;
        while (length < limit && in[ref + length] == in[ip + length]) ++length;
        // Close the literal run (or take back its unused control byte).
        if (literals > 0) {
          out[control] = static_cast<std::uint8_t>(literals - 1);
        } else {
          out.pop_back();
        }
        const std::size_t code = length - 2;
        const std::size_t offset = distance - 1;
        if (code < 7) {
          out.push_back(static_cast<std::uint8_t>((code << 5) | (offset >> 8)));
        } else {
          out.push_back(static_cast<std::uint8_t>((7 << 5) | (offset >> 8)));
          out.push_back(static_cast<std::uint8_t>(code - 7));
        }
        out.push_back(static_cast<std::uint8_t>(offset & 0xff));
        // Remember the positions inside the match too, which finds the next
        // match in repetitive data (long runs of equal floats) sooner.
        const std::size_t end = ip + length;
        for (std::size_t p = ip + 1; p + 2 < n && p < end; ++p) seen[hash3(in + p)] = p + 1;
        ip = end;
        literals = 0;
        control = out.size();
        out.push_back(0);
        continue;
      }
    }
    emit_literal(in[ip++]);
  }
  while (ip < n) emit_literal(in[ip++]);
  if (literals > 0) {
    out[control] = static_cast<std::uint8_t>(literals - 1);
  } else {
    out.pop_back();
  }
  return out;
}

void lzf_decompress(std::span<const std::uint8_t> compressed, std::span<std::uint8_t> out) {
  const std::uint8_t* in = compressed.data();
  const std::size_t in_size = compressed.size();
  const std::size_t out_size = out.size();
  std::uint8_t* dst = out.data();
  std::size_t ip = 0;
  std::size_t op = 0;
  while (ip < in_size) {
    const std::size_t at = ip;
    const unsigned control = in[ip++];
    if (control < kMaxLiteral) {
      const std::size_t length = control + 1;
      if (length > in_size - ip) malformed(at, "literal run of " + std::to_string(length) + " bytes is cut off");
      if (length > out_size - op) malformed(at, "output exceeds the declared " + std::to_string(out_size) + " bytes");
      std::memcpy(dst + op, in + ip, length);
      ip += length;
      op += length;
      continue;
    }
    std::size_t length = control >> 5;
    if (length == 7) {
      if (ip >= in_size) malformed(at, "back-reference length byte is cut off");
      length += in[ip++];
    }
    if (ip >= in_size) malformed(at, "back-reference offset byte is cut off");
    const std::size_t distance = ((std::size_t{control} & 31) << 8) + in[ip++] + 1;
    length += 2;
    if (distance > op) {
      malformed(at, "back-reference " + std::to_string(distance) + " bytes back reaches before the start");
    }
    if (length > out_size - op) malformed(at, "output exceeds the declared " + std::to_string(out_size) + " bytes");
    // Byte by byte: source and destination overlap when distance < length.
    const std::uint8_t* ref = dst + op - distance;
    for (std::size_t i = 0; i < length; ++i) dst[op + i] = ref[i];
    op += length;
  }
  if (op != out_size) {
    malformed(in_size, "decompresses to " + std::to_string(op) + " bytes; expected " + std::to_string(out_size));
  }
}

std::uint64_t lzf_max_decompressed_size(std::uint64_t compressed_size) {
  // The densest code is a 3-byte back-reference yielding kMaxMatch bytes.
  return compressed_size / 3 * kMaxMatch + 2 * kMaxMatch;
}

}  // namespace sarmap
