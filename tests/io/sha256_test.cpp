// SHA-256 against the FIPS 180-4 / NIST example vectors, split into pieces at
// every offset (the buffering), and of files.
#include "engine/io/sha256.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "engine/core/error.hpp"
#include "tests/io/scratch_folder.hpp"

namespace sarmap {
namespace {

TEST(Sha256, MatchesTheStandardVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1'000'000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// 55, 56 and 64 bytes are where the padding needs one block or two.
TEST(Sha256, PiecesGiveTheDigestOfTheWhole) {
  for (const std::size_t length : {55u, 56u, 63u, 64u, 65u, 200u}) {
    std::string text;
    for (std::size_t i = 0; i < length; ++i) text += static_cast<char>('a' + (i * 7) % 26);
    const std::string whole = sha256_hex(text);
    for (std::size_t cut = 0; cut <= length; ++cut) {
      Sha256 hasher;
      hasher.update(text.substr(0, cut));
      hasher.update(text.substr(cut));
      ASSERT_EQ(hasher.hex_digest(), whole) << "length " << length << " cut " << cut;
    }
  }
}

TEST(Sha256, DigestsFilesAndNamesOnesItCannotRead) {
  test::ScratchFolder scratch;
  const std::string text(200'000, 'x');
  const auto file = scratch.write("big.bin", text);
  const FileDigest d = digest_file(file);
  EXPECT_EQ(d.bytes, text.size());
  EXPECT_EQ(d.sha256, sha256_hex(text));
  try {
    digest_file(scratch / "missing.bin");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.bin"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarmap
