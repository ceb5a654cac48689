// .npy reading and writing for float32 arrays (see npy.hpp). The header is a
// Python dict literal; only the subset numpy writes is accepted.
#include "engine/io/npy.hpp"

#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/element_count.hpp"
#include "engine/io/file_bytes.hpp"

namespace sarmap {
namespace {

static_assert(std::endian::native == std::endian::little, "'<f4' data is read as native floats");

constexpr char kMagic[] = "\x93NUMPY";

// A parsed header value: a string, a bool or a tuple of integers.
struct Value {
  enum Kind { String, Bool, Tuple } kind = String;
  std::string text;
  bool flag = false;
  std::vector<std::size_t> tuple;
};

class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& source, std::size_t offset)
      : text_(text), source_(source), offset_(offset) {}

  std::map<std::string, Value> parse() {
    std::map<std::string, Value> out;
    expect('{');
    while (true) {
      skip_space();
      if (peek() == '}') break;
      const std::string key = quoted();
      expect(':');
      out[key] = value();
      skip_space();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      if (peek() != '}') fail("expected ',' or '}' in the header dict");
    }
    return out;
  }

 private:
  std::string_view text_;
  const std::string& source_;
  std::size_t offset_;
  std::size_t pos_ = 0;

  [[noreturn]] void fail(const std::string& message) const {
    throw Error(ErrorCode::Parse, at_offset(source_, offset_ + pos_, message));
  }
  char peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  void expect(char c) {
    skip_space();
    if (peek() != c) fail(std::string("expected '") + c + "' in the header");
    ++pos_;
  }
  std::string quoted() {
    skip_space();
    const char q = peek();
    if (q != '\'' && q != '"') fail("expected a quoted string in the header");
    const std::size_t close = text_.find(q, pos_ + 1);
    if (close == std::string_view::npos) fail("unterminated string in the header");
    std::string s(text_.substr(pos_ + 1, close - pos_ - 1));
    pos_ = close + 1;
    return s;
  }
  Value value() {
    skip_space();
    Value v;
    if (peek() == '\'' || peek() == '"') {
      v.text = quoted();
    } else if (text_.substr(pos_, 4) == "True" || text_.substr(pos_, 5) == "False") {
      v.kind = Value::Bool;
      v.flag = text_[pos_] == 'T';
      pos_ += v.flag ? 4 : 5;
    } else if (peek() == '(') {
      v.kind = Value::Tuple;
      ++pos_;
      while (true) {
        skip_space();
        if (peek() == ')') {
          ++pos_;
          break;
        }
        if (!std::isdigit(static_cast<unsigned char>(peek()))) fail("shape must be a tuple of non-negative integers");
        std::size_t n = 0;
        while (std::isdigit(static_cast<unsigned char>(peek()))) {
          n = n * 10 + static_cast<std::size_t>(peek() - '0');
          if (n > (std::size_t{1} << 40)) fail("shape dimension too large");
          ++pos_;
        }
        v.tuple.push_back(n);
        skip_space();
        if (peek() == ',') ++pos_;
      }
    } else {
      fail("unsupported value in the header");
    }
    return v;
  }
};

}  // namespace

NpyArray read_npy_f32(const std::filesystem::path& path) {
  const std::string src = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::Io, src + ": cannot open for reading");
  check_input_file_size(path);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 10 || std::memcmp(bytes.data(), kMagic, 6) != 0) {
    throw Error(ErrorCode::Parse, at_offset(src, 0, "not a .npy file (magic \\x93NUMPY missing)"));
  }
  const unsigned major = static_cast<unsigned char>(bytes[6]);
  std::size_t header_len = 0, header_start = 0;
  if (major == 1) {
    header_len = static_cast<unsigned char>(bytes[8]) | (static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw Error(ErrorCode::Parse, at_offset(src, 8, "truncated header length"));
    std::uint32_t len = 0;
    std::memcpy(&len, bytes.data() + 8, 4);
    header_len = len;
    header_start = 12;
  } else {
    throw Error(ErrorCode::Unsupported, at_offset(src, 6, "format version " + std::to_string(major) + " (1, 2 or 3 expected)"));
  }
  if (header_start + header_len > bytes.size()) {
    throw Error(ErrorCode::Parse, at_offset(src, header_start, "truncated: header of " + std::to_string(header_len) +
                                                                  " bytes declared, file ends first"));
  }
  const std::string_view header(bytes.data() + header_start, header_len);
  auto fields = HeaderParser(header, src, header_start).parse();
  const auto descr = fields.find("descr");
  if (descr == fields.end() || descr->second.kind != Value::String) {
    throw Error(ErrorCode::Parse, at_offset(src, header_start, "header has no 'descr'"));
  }
  if (descr->second.text != "<f4") {
    throw Error(ErrorCode::Unsupported, at_offset(src, header_start, "descr '" + descr->second.text +
                                                                         "': only little-endian float32 ('<f4') is read"));
  }
  const auto fortran = fields.find("fortran_order");
  if (fortran == fields.end() || fortran->second.kind != Value::Bool) {
    throw Error(ErrorCode::Parse, at_offset(src, header_start, "header has no 'fortran_order' True/False"));
  }
  if (fortran->second.flag) {
    throw Error(ErrorCode::Unsupported, at_offset(src, header_start, "fortran_order True: write the array C-ordered"));
  }
  const auto shape = fields.find("shape");
  if (shape == fields.end() || shape->second.kind != Value::Tuple) {
    throw Error(ErrorCode::Parse, at_offset(src, header_start, "header has no 'shape' tuple"));
  }
  NpyArray array;
  array.shape = shape->second.tuple;
  const std::size_t data_start = header_start + header_len;
  const std::size_t data_bytes = bytes.size() - data_start;
  const std::optional<std::size_t> checked_count = checked_element_count(array.shape, 4);
  if (!checked_count) {
    throw Error(ErrorCode::Parse, at_offset(src, header_start, "shape holds more elements than memory can address"));
  }
  const std::size_t count = *checked_count;
  if (data_bytes != count * 4) {
    throw Error(ErrorCode::Parse, at_offset(src, data_start, "shape needs " + std::to_string(count * 4) +
                                                                 " bytes of data, " +
                                                                 std::to_string(bytes.size() - data_start) + " present"));
  }
  array.values.resize(count);
  // memcpy to the null data() of an empty vector is undefined.
  if (count > 0) std::memcpy(array.values.data(), bytes.data() + data_start, count * 4);
  return array;
}

void write_npy_f32(const std::filesystem::path& path, std::span<const std::size_t> shape, std::span<const float> values) {
  std::size_t count = 1;
  std::string dims;
  for (std::size_t d : shape) {
    count *= d;
    dims += std::to_string(d) + ", ";
  }
  if (count != values.size()) {
    throw Error(ErrorCode::InvalidArgument, path.string() + ": " + std::to_string(values.size()) +
                                                " values do not fill the shape");
  }
  if (shape.size() > 1) dims.resize(dims.size() - 2);  // "(4, 6)"; a 1-D shape keeps "(4, )"
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + dims + "), }";
  // Magic + version + length + header + '\n' padded to a multiple of 64.
  const std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header.push_back('\n');
  const std::uint16_t len = static_cast<std::uint16_t>(header.size());
  AtomicFileWriter out(path);
  out.write(kMagic, 6);
  const char version[2] = {1, 0};
  out.write(version, 2);
  out.write(&len, 2);
  out.write(header);
  out.write(values.data(), values.size() * sizeof(float));
  out.commit();
}

}  // namespace sarmap
