// The byte stream a checkpoint is made of: each stateful part of the pipeline
// (maps, classifier memory, segments, topological map, profile) appends its
// state to a StateWriter and reads it back from a StateReader, field by field
// in native byte order (a checkpoint resumes on the machine that wrote it; it
// is no interchange format). Sections start with a four-letter tag so that a
// reader out of step with the writer fails at the section, not later.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace sarmap {

class StateWriter {
 public:
  void tag(std::string_view four_letters);

  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(values.size());
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void put_string(std::string_view text);

  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  // `name` (the checkpoint's path) starts every error message.
  StateReader(std::string_view bytes, std::string name);

  // Throws sarmap::Error (Parse) naming the offset when the next tag differs.
  void expect_tag(std::string_view four_letters);

  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T), "value"), sizeof(T));
    return value;
  }
  // A count is checked against the bytes left before anything is allocated.
  template <class T>
  std::vector<T> get_vector() {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t n = get_count(sizeof(T));
    std::vector<T> values(n);
    if (n > 0) std::memcpy(values.data(), take(n * sizeof(T), "array"), n * sizeof(T));
    return values;
  }
  std::string get_string();
  // An element count for records of at least `min_bytes_each`, refused when
  // the rest of the stream could not hold that many.
  std::size_t get_count(std::size_t min_bytes_each);
  // Throws unless every byte was read.
  void expect_end() const;
  // Throws sarmap::Error (Parse) naming the checkpoint and the offset.
  [[noreturn]] void fail(const std::string& what) const;

 private:
  const char* take(std::size_t size, const char* what);

  std::string_view bytes_;
  std::size_t offset_ = 0;
  std::string name_;
};

}  // namespace sarmap
