// Reading and writing safetensors files (8-byte little-endian header length,
// a JSON header naming each tensor's dtype, shape and byte range, then raw
// little-endian data): the format sarmap's network weights come in. Every
// malformed file gets a sarmap::Error naming the file and the tensor.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sarmap {

struct SafetensorsTensor {
  std::string name;
  std::string dtype;               // "F32", "F64", "I64", ...
  std::vector<std::size_t> shape;  // empty for a scalar
  std::size_t begin = 0;           // byte range within the data section
  std::size_t end = 0;

  std::size_t element_count() const;
};

class SafetensorsFile {
 public:
  // Reads and validates the whole file. Throws sarmap::Error (Io, Parse).
  static SafetensorsFile read(const std::filesystem::path& path);
  // Validates bytes already in memory; `source` names them in messages.
  static SafetensorsFile parse(std::vector<std::uint8_t> bytes, std::string source);

  const std::string& source() const { return source_; }
  // The "__metadata__" entries (strings only, as the format allows).
  const std::map<std::string, std::string>& metadata() const { return metadata_; }
  // Tensors in the order of their data.
  const std::vector<SafetensorsTensor>& tensors() const { return tensors_; }
  // nullptr when absent.
  const SafetensorsTensor* find(std::string_view name) const;
  // The values of a float32 tensor; any other dtype is an error naming it.
  std::vector<float> floats(const SafetensorsTensor& tensor) const;

 private:
  std::string source_;
  std::vector<std::uint8_t> bytes_;
  std::size_t data_start_ = 0;
  std::map<std::string, std::string> metadata_;
  std::vector<SafetensorsTensor> tensors_;
};

// One float32 tensor to write.
struct SafetensorsFloatTensor {
  std::string name;
  std::vector<std::size_t> shape;
  std::span<const float> values;  // product(shape) values, row-major
};

// Writes float32 tensors and string metadata atomically.
void write_safetensors(const std::filesystem::path& path, std::span<const SafetensorsFloatTensor> tensors,
                       const std::map<std::string, std::string>& metadata = {});

}  // namespace sarmap
