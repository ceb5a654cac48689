#include "engine/core/error.hpp"

#include <gtest/gtest.h>

namespace sarmap {
namespace {

TEST(Error, MessagesNameTheLocation) {
  EXPECT_EQ(at_line("a.ply", 7, "bad"), "a.ply:7: bad");
  EXPECT_EQ(at_line("a.ply", 0, "bad"), "a.ply: bad");
  EXPECT_EQ(at_offset("a.pcd", 12, "short"), "a.pcd (byte offset 12): short");
  const Error e(ErrorCode::Parse, "x");
  EXPECT_EQ(e.code(), ErrorCode::Parse);
  EXPECT_EQ(to_string(ErrorCode::Io), "I/O error");
}

}  // namespace
}  // namespace sarmap
