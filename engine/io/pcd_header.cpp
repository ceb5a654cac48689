#include "engine/io/pcd_header.hpp"

#include <optional>

#include "engine/core/error.hpp"
#include "engine/io/text_parse.hpp"

namespace sarmap {

std::size_t PcdHeader::point_size() const {
  std::size_t size = 0;
  for (const PcdField& f : fields) size += f.bytes();
  return size;
}

std::string_view to_string(PcdEncoding encoding) {
  switch (encoding) {
    case PcdEncoding::Ascii: return "ascii";
    case PcdEncoding::Binary: return "binary";
    case PcdEncoding::BinaryCompressed: return "binary_compressed";
  }
  return "?";
}

namespace {

std::vector<std::string_view> tokens_of(std::string_view rest) {
  std::vector<std::string_view> out;
  for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest)) out.push_back(t);
  return out;
}

}  // namespace

PcdHeader parse_pcd_header(std::string_view bytes, const std::string& file) {
  LineReader lines(bytes);
  std::string_view line;
  auto fail = [&](ErrorCode code, std::size_t at, const std::string& what) {
    return Error(code, at_line(file, at, what));
  };
  PcdHeader header;
  std::vector<std::string_view> sizes, types, counts;
  std::size_t size_line = 0, type_line = 0, count_line = 0, width_line = 0;
  bool have_width = false, have_points = false, have_height = false;

  auto parse_count = [&](std::string_view keyword, std::string_view rest, std::uint64_t& out) {
    const auto values = tokens_of(rest);
    if (values.size() != 1 || !parse_number(values[0], out)) {
      throw fail(ErrorCode::Parse, lines.line_number(),
                 std::string(keyword) + " '" + std::string(trim(rest)) + "'; expected one non-negative integer");
    }
  };

  while (true) {
    if (!lines.next(line)) {
      if (lines.line_number() == 0) throw fail(ErrorCode::Parse, 0, "empty file; expected a PCD header");
      throw fail(ErrorCode::Parse, lines.line_number(), "header ends without a DATA line (file truncated?)");
    }
    std::string_view rest = line;
    const std::string_view keyword = next_token(rest);
    if (!keyword.empty() && keyword.front() == '#') {
      const std::string_view text = trim(trim(line).substr(1));
      if (text.substr(0, 5) != ".PCD ") header.comments.emplace_back(text);
      continue;
    }
    if (keyword.empty()) continue;
    const std::size_t at = lines.line_number();
    if (keyword == "VERSION") {
      const auto values = tokens_of(rest);
      if (values.size() != 1 || (values[0] != "0.7" && values[0] != ".7")) {
        throw fail(ErrorCode::Unsupported, at, "VERSION '" + std::string(trim(rest)) + "'; expected 0.7");
      }
    } else if (keyword == "FIELDS") {
      for (const std::string_view name : tokens_of(rest)) header.fields.push_back({std::string(name)});
      if (header.fields.empty()) throw fail(ErrorCode::Parse, at, "FIELDS names no field");
      header.fields_line = at;
    } else if (keyword == "SIZE") {
      sizes = tokens_of(rest);
      size_line = at;
    } else if (keyword == "TYPE") {
      types = tokens_of(rest);
      type_line = at;
    } else if (keyword == "COUNT") {
      counts = tokens_of(rest);
      count_line = at;
    } else if (keyword == "WIDTH") {
      parse_count(keyword, rest, header.width);
      have_width = true;
      width_line = at;
    } else if (keyword == "HEIGHT") {
      parse_count(keyword, rest, header.height);
      have_height = true;
    } else if (keyword == "POINTS") {
      parse_count(keyword, rest, header.points);
      have_points = true;
      header.points_line = at;
    } else if (keyword == "VIEWPOINT") {
      const auto values = tokens_of(rest);
      double ignored = 0;
      bool ok = values.size() == 7;
      for (const auto v : values) ok = ok && parse_number(v, ignored);
      if (!ok) throw fail(ErrorCode::Parse, at, "VIEWPOINT '" + std::string(trim(rest)) + "'; expected 7 numbers");
    } else if (keyword == "DATA") {
      const auto values = tokens_of(rest);
      const std::string_view name = values.size() == 1 ? values[0] : std::string_view();
      if (name == "ascii") {
        header.encoding = PcdEncoding::Ascii;
      } else if (name == "binary") {
        header.encoding = PcdEncoding::Binary;
      } else if (name == "binary_compressed") {
        header.encoding = PcdEncoding::BinaryCompressed;
      } else {
        throw fail(ErrorCode::Parse, at,
                   "DATA '" + std::string(trim(rest)) + "'; expected ascii, binary or binary_compressed");
      }
      break;
    } else {
      throw fail(ErrorCode::Parse, at, "unknown header keyword '" + std::string(keyword) +
                                           "'; expected VERSION, FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, "
                                           "VIEWPOINT, POINTS or DATA");
    }
  }
  header.type_line = type_line;
  header.count_line = count_line;
  header.data_offset = lines.offset();
  header.header_lines = lines.line_number();
  const std::size_t data_line = header.header_lines;

  // Cross-checks between the lines.
  if (header.fields.empty()) throw fail(ErrorCode::Parse, data_line, "header has no FIELDS line");
  const std::size_t n = header.fields.size();
  if (sizes.size() != n) {
    throw fail(ErrorCode::Parse, size_line != 0 ? size_line : data_line,
               "SIZE has " + std::to_string(sizes.size()) + " entries; expected one per field (" + std::to_string(n) +
                   ")");
  }
  if (types.size() != n) {
    throw fail(ErrorCode::Parse, type_line != 0 ? type_line : data_line,
               "TYPE has " + std::to_string(types.size()) + " entries; expected one per field (" + std::to_string(n) +
                   ")");
  }
  if (count_line != 0 && counts.size() != n) {
    throw fail(ErrorCode::Parse, count_line,
               "COUNT has " + std::to_string(counts.size()) + " entries; expected one per field (" +
                   std::to_string(n) + ")");
  }
  for (std::size_t k = 0; k < n; ++k) {
    PcdField& field = header.fields[k];
    std::uint64_t size = 0;
    if (!parse_number(sizes[k], size)) {
      throw fail(ErrorCode::Parse, size_line, "SIZE of field '" + field.name + "' is '" + std::string(sizes[k]) +
                                                  "'; expected 1, 2, 4 or 8");
    }
    const auto type = types[k].size() == 1 ? scalar_type_from_pcd(types[k][0], size) : std::nullopt;
    if (!type) {
      throw fail(ErrorCode::Parse, type_line,
                 "field '" + field.name + "' has TYPE " + std::string(types[k]) + " with SIZE " +
                     std::string(sizes[k]) + "; expected I or U with SIZE 1, 2, 4 or 8, or F with SIZE 4 or 8");
    }
    field.type = *type;
    if (count_line != 0) {
      std::uint64_t count = 0;
      // A point's values must fit one line / record: a sane COUNT is small.
      if (!parse_number(counts[k], count) || count == 0 || count > (1u << 20)) {
        throw fail(ErrorCode::Parse, count_line, "COUNT of field '" + field.name + "' is '" +
                                                     std::string(counts[k]) + "'; expected a positive integer");
      }
      field.count = static_cast<std::size_t>(count);
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (header.fields[j].name == field.name && field.name != "_") {
        throw fail(ErrorCode::Parse, header.fields_line, "field '" + field.name + "' appears twice in FIELDS");
      }
    }
  }
  if (!have_width) throw fail(ErrorCode::Parse, data_line, "header has no WIDTH line");
  if (!have_height) header.height = 1;
  const bool product_overflows = header.height != 0 && header.width > UINT64_MAX / header.height;
  const std::uint64_t product = header.width * header.height;
  if (!have_points) {
    header.points = product;
    header.points_line = width_line;
  }
  if (product_overflows || product != header.points) {
    throw fail(ErrorCode::Parse, header.points_line,
               "WIDTH * HEIGHT (" + std::to_string(header.width) + " * " + std::to_string(header.height) +
                   ") does not equal POINTS (" + std::to_string(header.points) + ")");
  }
  return header;
}

}  // namespace sarmap
