#include "engine/io/text_parse.hpp"

#include <charconv>
#include <cstring>
#include <system_error>

namespace sarmap {

bool LineReader::next(std::string_view& line) {
  if (position_ >= text_.size()) return false;
  const char* begin = text_.data() + position_;
  const std::size_t remaining = text_.size() - position_;
  const void* newline = std::memchr(begin, '\n', remaining);
  std::size_t length = newline != nullptr ? static_cast<std::size_t>(static_cast<const char*>(newline) - begin)
                                          : remaining;
  position_ += length + (newline != nullptr ? 1 : 0);
  if (length > 0 && begin[length - 1] == '\r') --length;
  line = std::string_view(begin, length);
  ++line_number_;
  return true;
}

std::string_view next_token(std::string_view& rest) {
  std::size_t start = 0;
  while (start < rest.size() && (rest[start] == ' ' || rest[start] == '\t')) ++start;
  std::size_t end = start;
  while (end < rest.size() && rest[end] != ' ' && rest[end] != '\t') ++end;
  const std::string_view token = rest.substr(start, end - start);
  rest.remove_prefix(end);
  return token;
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

bool is_blank(std::string_view text) {
  for (const char c : text) {
    if (c != ' ' && c != '\t') return false;
  }
  return true;
}

namespace {

template <class T>
bool parse_whole(std::string_view token, T& out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  if (token.empty()) return false;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, out);
  return ec == std::errc() && ptr == end;
}

}  // namespace

bool parse_number(std::string_view token, float& out) { return parse_whole(token, out); }
bool parse_number(std::string_view token, double& out) { return parse_whole(token, out); }
bool parse_number(std::string_view token, std::int64_t& out) { return parse_whole(token, out); }
bool parse_number(std::string_view token, std::uint64_t& out) { return parse_whole(token, out); }

}  // namespace sarmap
