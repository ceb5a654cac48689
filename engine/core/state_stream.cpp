#include "engine/core/state_stream.hpp"

#include "engine/core/error.hpp"

namespace sarmap {

void StateWriter::tag(std::string_view four_letters) { bytes_.append(four_letters.substr(0, 4)); }

void StateWriter::put_string(std::string_view text) {
  put<std::uint64_t>(text.size());
  bytes_.append(text);
}

StateReader::StateReader(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

void StateReader::expect_tag(std::string_view four_letters) {
  const std::size_t at = offset_;
  const std::string_view found(take(4, "section tag"), 4);
  if (found != four_letters.substr(0, 4)) {
    offset_ = at;
    fail("expected section " + std::string(four_letters) + ", found other bytes (written by another sarmap version?)");
  }
}

std::string StateReader::get_string() {
  const std::size_t n = get_count(1);
  return std::string(take(n, "string"), n);
}

std::size_t StateReader::get_count(std::size_t min_bytes_each) {
  const auto n = get<std::uint64_t>();
  const std::size_t left = bytes_.size() - offset_;
  if (min_bytes_each > 0 && n > left / min_bytes_each) {
    offset_ -= sizeof(std::uint64_t);
    fail("a count of " + std::to_string(n) + " does not fit in the " + std::to_string(left) + " bytes left");
  }
  return static_cast<std::size_t>(n);
}

void StateReader::expect_end() const {
  if (offset_ != bytes_.size()) {
    fail(std::to_string(bytes_.size() - offset_) + " bytes follow the last section");
  }
}

void StateReader::fail(const std::string& what) const {
  throw Error(ErrorCode::Parse, name_ + " (byte offset " + std::to_string(offset_) + "): " + what);
}

const char* StateReader::take(std::size_t size, const char* what) {
  if (size > bytes_.size() - offset_) fail(std::string("ends inside a ") + what + " (truncated?)");
  const char* at = bytes_.data() + offset_;
  offset_ += size;
  return at;
}

}  // namespace sarmap
