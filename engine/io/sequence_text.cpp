#include "engine/io/sequence_text.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/io/file_bytes.hpp"

namespace sarmap {

std::vector<TextRow> read_text_rows(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::Io, path.string() + ": cannot open: " + std::strerror(errno));
  }
  check_input_file_size(path);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  if (in.bad()) throw Error(ErrorCode::Io, path.string() + ": read failed");
  std::vector<TextRow> rows;
  std::size_t line = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line;
    const std::string_view content(text.data() + start, end - start);
    start = end + 1;
    if (content.find('\0') != std::string_view::npos) {
      throw Error(ErrorCode::Parse, at_line(path.string(), line, "binary data (NUL byte) in a text file"));
    }
    TextRow row;
    row.line = line;
    std::size_t i = 0;
    while (i < content.size()) {
      while (i < content.size() && std::isspace(static_cast<unsigned char>(content[i]))) ++i;
      std::size_t j = i;
      while (j < content.size() && !std::isspace(static_cast<unsigned char>(content[j]))) ++j;
      if (j > i) row.tokens.emplace_back(content.substr(i, j - i));
      i = j;
    }
    if (row.tokens.empty() || row.tokens.front().front() == '#') continue;
    rows.push_back(std::move(row));
  }
  return rows;
}

double parse_number(std::string_view token, std::string_view file, std::size_t line, std::string_view field) {
  // from_chars rejects a leading '+', which some writers emit.
  std::string_view digits = token;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    throw Error(ErrorCode::InvalidData, at_line(file, line,
                                                std::string(field) + ": '" + std::string(token) +
                                                    "' is out of the range of a double"));
  }
  if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
    throw Error(
        ErrorCode::Parse,
        at_line(file, line, std::string(field) + ": expected a number, got '" + std::string(token) + "'"));
  }
  if (!std::isfinite(value)) {
    throw Error(ErrorCode::InvalidData,
                at_line(file, line,
                        std::string(field) + ": expected a finite number, got '" + std::string(token) + "'"));
  }
  return value;
}

void expect_token_count(const TextRow& row, std::size_t count, std::string_view file,
                        std::string_view layout) {
  if (row.tokens.size() == count) return;
  std::ostringstream msg;
  msg << "expected " << count << " values (" << layout << "), got " << row.tokens.size();
  throw Error(ErrorCode::Parse, at_line(file, row.line, msg.str()));
}

}  // namespace sarmap
