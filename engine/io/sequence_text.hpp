// Reading the small whitespace-separated text files of scan-sequence layouts
// (TUM lists, 7-Scenes poses, intrinsics matrices) with errors that name the
// file, the line and the field, so a broken dataset can be fixed by hand.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace sarmap {

struct TextRow {
  std::size_t line = 0;  // 1-based line number in the file
  std::vector<std::string> tokens;
};

// Every non-blank line that does not start with '#', split on whitespace.
// Throws sarmap::Error (Io) when the file cannot be read, (Parse) for a NUL byte.
std::vector<TextRow> read_text_rows(const std::filesystem::path& path);

// The token as a finite double; otherwise a Parse / InvalidData error
// "file:line: <field>: expected a number, got 'abc'".
double parse_number(std::string_view token, std::string_view file, std::size_t line, std::string_view field);

// Throws a Parse error unless the row has exactly `count` tokens; `layout`
// describes them ("timestamp tx ty tz qx qy qz qw").
void expect_token_count(const TextRow& row, std::size_t count, std::string_view file,
                        std::string_view layout);

}  // namespace sarmap
