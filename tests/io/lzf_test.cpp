#include "engine/io/lzf.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "point_cloud_test_support.hpp"

namespace sarmap {
namespace {

using ::testing::HasSubstr;

std::vector<std::uint8_t> bytes_of(const std::string& text) { return {text.begin(), text.end()}; }

std::vector<std::uint8_t> round_trip(const std::vector<std::uint8_t>& data) {
  const std::vector<std::uint8_t> packed = lzf_compress(data);
  EXPECT_LE(data.size(), lzf_max_decompressed_size(packed.size()));
  std::vector<std::uint8_t> out(data.size());
  lzf_decompress(packed, out);
  return out;
}

TEST(Lzf, EmptyInputRoundTrips) {
  EXPECT_TRUE(lzf_compress({}).empty());
  std::vector<std::uint8_t> out;
  lzf_decompress({}, out);  // nothing in, nothing expected out
  EXPECT_TRUE(out.empty());
}

TEST(Lzf, TinyInputsRoundTrip) {
  for (std::size_t n = 1; n <= 70; ++n) {
    std::vector<std::uint8_t> data(n);
    for (std::size_t i = 0; i < n; ++i) data[i] = static_cast<std::uint8_t>(i % 3);
    EXPECT_EQ(round_trip(data), data) << n;
  }
}

TEST(Lzf, AllEqualBytesCompressHard) {
  const std::vector<std::uint8_t> data(100000, 0x5a);
  const auto packed = lzf_compress(data);
  // Each 3-byte back-reference covers 264 bytes.
  EXPECT_LT(packed.size(), data.size() / 80);
  EXPECT_EQ(round_trip(data), data);
}

TEST(Lzf, IncompressibleDataGrowsByAtMostOneBytePer32) {
  test::Random random(7);
  std::vector<std::uint8_t> data(65536);
  for (auto& b : data) b = random.byte();
  const auto packed = lzf_compress(data);
  EXPECT_LE(packed.size(), data.size() + data.size() / 32 + 1);
  EXPECT_EQ(round_trip(data), data);
}

TEST(Lzf, RandomMixturesOfRepeatsAndNoiseRoundTrip) {
  test::Random random(11);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<std::uint8_t> data;
    const std::size_t target = 1 + random.next() % 40000;
    while (data.size() < target) {
      const unsigned kind = random.next() % 3;
      const std::size_t length = 1 + random.next() % 600;
      if (kind == 0 || data.empty()) {
        for (std::size_t i = 0; i < length; ++i) data.push_back(random.byte() % 4);  // few symbols
      } else if (kind == 1) {
        // Copy from up to 10000 bytes back: some within LZF's 8 KiB window, some beyond.
        const std::size_t back = 1 + random.next() % std::min<std::size_t>(data.size(), 10000);
        const std::size_t from = data.size() - back;
        for (std::size_t i = 0; i < length; ++i) data.push_back(data[from + i]);
      } else {
        for (std::size_t i = 0; i < length; ++i) data.push_back(random.byte());
      }
    }
    ASSERT_EQ(round_trip(data), data) << "trial " << trial;
  }
}

TEST(Lzf, MatchesAtTheEdgeOfTheWindowRoundTrip) {
  test::Random random(3);
  std::vector<std::uint8_t> block(300);
  for (auto& b : block) b = random.byte();
  for (const std::size_t gap : {8190u, 8191u, 8192u, 8193u, 9000u}) {
    std::vector<std::uint8_t> data = block;
    for (std::size_t i = 0; i < gap - block.size(); ++i) data.push_back(random.byte());
    data.insert(data.end(), block.begin(), block.end());  // repeat exactly `gap` bytes later
    EXPECT_EQ(round_trip(data), data) << gap;
  }
}

TEST(Lzf, DecodesAHandWrittenStream) {
  // Literal "abc" (control 2), then a back-reference of 9 bytes at distance 3:
  // length code 7 needs an extra length byte 0, offset byte 2.
  const std::vector<std::uint8_t> stream = {2, 'a', 'b', 'c', 0xe0, 0, 2, 1, 'x', 'y'};
  std::vector<std::uint8_t> out(14);
  lzf_decompress(stream, out);
  EXPECT_EQ(std::string(out.begin(), out.end()), "abcabcabcabcxy");
}

std::string decompress_error(const std::vector<std::uint8_t>& stream, std::size_t out_size) {
  std::vector<std::uint8_t> out(out_size);
  return test::error_from([&] { lzf_decompress(stream, out); }).what();
}

TEST(Lzf, RejectsMalformedStreamsWithThePosition) {
  // Literal run announcing 4 bytes, 2 present.
  EXPECT_THAT(decompress_error({3, 'a', 'b'}, 4), HasSubstr("byte 0 of the compressed block"));
  EXPECT_THAT(decompress_error({3, 'a', 'b'}, 4), HasSubstr("cut off"));
  // Back-reference before the first byte.
  EXPECT_THAT(decompress_error({0, 'a', 0x20, 5}, 4), HasSubstr("byte 2 of the compressed block"));
  EXPECT_THAT(decompress_error({0, 'a', 0x20, 5}, 4), HasSubstr("reaches before the start"));
  // Long back-reference whose length byte is missing.
  EXPECT_THAT(decompress_error({0, 'a', 0xe0}, 40), HasSubstr("length byte is cut off"));
  // Offset byte missing.
  EXPECT_THAT(decompress_error({0, 'a', 0x20}, 4), HasSubstr("offset byte is cut off"));
  // More output than declared, and less.
  EXPECT_THAT(decompress_error({2, 'a', 'b', 'c'}, 2), HasSubstr("exceeds the declared 2 bytes"));
  EXPECT_THAT(decompress_error({2, 'a', 'b', 'c'}, 5), HasSubstr("decompresses to 3 bytes; expected 5"));
  EXPECT_EQ(test::error_from([] {
              std::vector<std::uint8_t> out(4);
              lzf_decompress(bytes_of("\x03" "ab"), out);
            }).code(),
            ErrorCode::Parse);
}

}  // namespace
}  // namespace sarmap
