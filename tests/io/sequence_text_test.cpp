#include "engine/io/sequence_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "error_message.hpp"
#include "scratch_folder.hpp"

namespace sarmap {
namespace {

using test::error_message;
using ::testing::HasSubstr;

TEST(SequenceText, SkipsCommentsAndBlankLinesKeepingLineNumbers) {
  test::ScratchFolder dir;
  const auto file = dir.write("list.txt", "# header\n\n  1.5 a.png  \r\n#x\n2\tb.png\n3 c.png");
  const auto rows = read_text_rows(file);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].line, 3u);
  EXPECT_EQ(rows[0].tokens, (std::vector<std::string>{"1.5", "a.png"}));
  EXPECT_EQ(rows[1].line, 5u);
  EXPECT_EQ(rows[1].tokens, (std::vector<std::string>{"2", "b.png"}));
  EXPECT_EQ(rows[2].line, 6u);  // last line without a newline
}

TEST(SequenceText, ParsesNumbersStrictly) {
  EXPECT_EQ(parse_number("1.25", "f", 1, "x"), 1.25);
  EXPECT_EQ(parse_number("+2e3", "f", 1, "x"), 2000.0);
  EXPECT_EQ(parse_number("-0.5", "f", 1, "x"), -0.5);
  EXPECT_THAT(error_message([] { parse_number("1.5x", "f.txt", 7, "tx"); }),
              HasSubstr("f.txt:7: tx: expected a number, got '1.5x'"));
  EXPECT_THAT(error_message([] { parse_number("", "f", 1, "x"); }), HasSubstr("expected a number"));
  EXPECT_THAT(error_message([] { parse_number("inf", "f", 1, "x"); }), HasSubstr("finite"));
  EXPECT_THAT(error_message([] { parse_number("NaN", "f", 1, "x"); }), HasSubstr("finite"));
  EXPECT_THAT(error_message([] { parse_number("1e999", "f", 1, "x"); }), HasSubstr("out of the range"));
}

TEST(SequenceText, BinaryDataAndMissingFilesAreErrors) {
  test::ScratchFolder dir;
  const auto file = dir.write("bin.txt", std::string("1 2\n3\0 4\n", 9));
  EXPECT_THAT(error_message([&] { read_text_rows(file); }), HasSubstr("bin.txt:2: binary data"));
  EXPECT_THAT(error_message([&] { read_text_rows(dir / "none.txt"); }), HasSubstr("cannot open"));
}

}  // namespace
}  // namespace sarmap
