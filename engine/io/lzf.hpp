// LZF, the small LZ77 variant PCD's binary_compressed encoding uses (as in
// Marc Lehmann's liblzf): written here so sarmap needs no extra library.
// The format: a control byte c < 32 starts a run of c + 1 literal bytes; any
// other control byte is a back-reference of length (c >> 5) + 2 (an extra
// length byte follows when c >> 5 == 7) at distance ((c & 31) << 8 | next) + 1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sarmap {

// Compresses data; never fails. Incompressible input grows by one byte per 32.
std::vector<std::uint8_t> lzf_compress(std::span<const std::uint8_t> data);

// Decompresses into out, which must be exactly the uncompressed size. Throws
// sarmap::Error (Parse) with a position inside the compressed stream when it
// is malformed: truncated, a back-reference before the start, or output that
// does not fill out exactly.
void lzf_decompress(std::span<const std::uint8_t> compressed, std::span<std::uint8_t> out);

// The most bytes `compressed_size` bytes of LZF can expand to: readers check a
// declared uncompressed size against it before allocating.
std::uint64_t lzf_max_decompressed_size(std::uint64_t compressed_size);

}  // namespace sarmap
