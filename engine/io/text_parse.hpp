// Line and token scanning over an in-memory text, and numbers parsed with
// std::from_chars (no locale, no streams), for the ASCII PLY and PCD readers
// and their headers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace sarmap {

// Walks a text line by line, counting lines from 1, so errors can name them.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}

  // The next line without its "\n" or "\r\n"; false when the text is exhausted.
  bool next(std::string_view& line);
  // 1-based number of the line last returned by next() (0 before the first).
  std::size_t line_number() const { return line_number_; }
  // Byte offset of the first character not yet returned.
  std::size_t offset() const { return position_; }
  bool at_end() const { return position_ >= text_.size(); }

 private:
  std::string_view text_;
  std::size_t position_ = 0;
  std::size_t line_number_ = 0;
};

// Splits the next token (separated by spaces or tabs) off the front of rest;
// returns an empty view when none is left.
std::string_view next_token(std::string_view& rest);
// text without leading and trailing spaces and tabs.
std::string_view trim(std::string_view text);
// True when only spaces and tabs remain.
bool is_blank(std::string_view text);

// Each parser accepts the whole token or nothing: "1.5x" fails. A leading '+'
// is accepted, as are "nan" and "inf" for the floating-point ones.
bool parse_number(std::string_view token, float& out);
bool parse_number(std::string_view token, double& out);
bool parse_number(std::string_view token, std::int64_t& out);
bool parse_number(std::string_view token, std::uint64_t& out);

}  // namespace sarmap
