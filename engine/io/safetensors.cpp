// Safetensors parsing and writing (see safetensors.hpp).
#include "engine/io/safetensors.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/element_count.hpp"
#include "engine/io/file_bytes.hpp"

namespace sarmap {
namespace {

static_assert(std::endian::native == std::endian::little, "safetensors data is little-endian");

// Headers beyond this are refused rather than parsed (the format's own cap).
constexpr std::uint64_t kMaxHeaderBytes = 100u << 20;

std::optional<std::size_t> dtype_size(std::string_view dtype) {
  if (dtype == "F64" || dtype == "I64" || dtype == "U64") return 8;
  if (dtype == "F32" || dtype == "I32" || dtype == "U32") return 4;
  if (dtype == "F16" || dtype == "BF16" || dtype == "I16" || dtype == "U16") return 2;
  if (dtype == "I8" || dtype == "U8" || dtype == "BOOL" || dtype == "F8_E4M3" || dtype == "F8_E5M2") return 1;
  return std::nullopt;
}

[[noreturn]] void fail(ErrorCode code, const std::string& source, const std::string& message) {
  throw Error(code, source + ": " + message);
}

std::string shape_text(const std::vector<std::size_t>& shape) {
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + "]";
}

std::size_t as_size(const nlohmann::json& value, const std::string& source, const std::string& what) {
  if (!value.is_number_unsigned()) fail(ErrorCode::Parse, source, what + " must be a non-negative integer");
  return value.get<std::size_t>();
}

SafetensorsTensor parse_entry(const std::string& name, const nlohmann::json& entry, std::size_t data_size,
                              const std::string& source) {
  const std::string where = "tensor '" + name + "'";
  if (!entry.is_object()) fail(ErrorCode::Parse, source, where + ": entry is not a JSON object");
  SafetensorsTensor t;
  t.name = name;
  const auto dtype = entry.find("dtype");
  if (dtype == entry.end() || !dtype->is_string()) fail(ErrorCode::Parse, source, where + ": no \"dtype\" string");
  t.dtype = dtype->get<std::string>();
  const auto size = dtype_size(t.dtype);
  if (!size) fail(ErrorCode::Parse, source, where + ": unknown dtype \"" + t.dtype + "\"");
  const auto shape = entry.find("shape");
  if (shape == entry.end() || !shape->is_array()) fail(ErrorCode::Parse, source, where + ": no \"shape\" array");
  for (const auto& d : *shape) t.shape.push_back(as_size(d, source, where + ": a shape dimension"));
  const auto offsets = entry.find("data_offsets");
  if (offsets == entry.end() || !offsets->is_array() || offsets->size() != 2) {
    fail(ErrorCode::Parse, source, where + ": \"data_offsets\" must be [begin, end]");
  }
  t.begin = as_size((*offsets)[0], source, where + ": data_offsets begin");
  t.end = as_size((*offsets)[1], source, where + ": data_offsets end");
  if (t.begin > t.end) fail(ErrorCode::Parse, source, where + ": data_offsets begin is after end");
  if (t.end > data_size) {
    fail(ErrorCode::Parse, source,
         where + ": data_offsets [" + std::to_string(t.begin) + ", " + std::to_string(t.end) +
             "] run past the end of the data (" + std::to_string(data_size) + " bytes; file truncated?)");
  }
  const std::optional<std::size_t> count = checked_element_count(t.shape, *size);
  if (!count) {
    fail(ErrorCode::Parse, source, where + ": shape " + shape_text(t.shape) + " holds more elements than memory can address");
  }
  const std::size_t expected = *count * *size;
  if (t.end - t.begin != expected) {
    fail(ErrorCode::Parse, source,
         where + ": " + std::to_string(t.end - t.begin) + " bytes of data, but shape " + shape_text(t.shape) +
             " of " + t.dtype + " needs " + std::to_string(expected));
  }
  return t;
}

}  // namespace

std::size_t SafetensorsTensor::element_count() const {
  std::size_t n = 1;
  for (std::size_t d : shape) n *= d;
  return n;
}

SafetensorsFile SafetensorsFile::read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::Io, path.string() + ": cannot open for reading");
  check_input_file_size(path);
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(ErrorCode::Io, path.string() + ": read failed");
  return parse(std::move(bytes), path.string());
}

SafetensorsFile SafetensorsFile::parse(std::vector<std::uint8_t> bytes, std::string source) {
  SafetensorsFile file;
  file.source_ = std::move(source);
  const std::string& src = file.source_;
  if (bytes.size() < 8) {
    fail(ErrorCode::Parse, src,
         "truncated: " + std::to_string(bytes.size()) + " bytes, too short for the 8-byte header length");
  }
  std::uint64_t header_len = 0;
  std::memcpy(&header_len, bytes.data(), 8);
  if (header_len > kMaxHeaderBytes) {
    fail(ErrorCode::Parse, src, "header length " + std::to_string(header_len) + " is implausible (not safetensors?)");
  }
  if (header_len > bytes.size() - 8) {
    fail(ErrorCode::Parse, src,
         "truncated: header of " + std::to_string(header_len) + " bytes declared, " +
             std::to_string(bytes.size() - 8) + " present");
  }
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(bytes.begin() + 8, bytes.begin() + 8 + static_cast<std::ptrdiff_t>(header_len));
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(ErrorCode::Parse, at_offset(src, 8 + e.byte, std::string("header is not valid JSON: ") + e.what()));
  } catch (const nlohmann::json::exception& e) {  // out_of_range: a number beyond a double, such as 1e999
    fail(ErrorCode::Parse, src, std::string("header is not valid JSON: ") + e.what());
  }
  if (!header.is_object()) fail(ErrorCode::Parse, src, "header is not a JSON object");
  file.data_start_ = 8 + static_cast<std::size_t>(header_len);
  const std::size_t data_size = bytes.size() - file.data_start_;
  for (const auto& [name, entry] : header.items()) {
    if (name == "__metadata__") {
      if (!entry.is_object()) fail(ErrorCode::Parse, src, "__metadata__ is not a JSON object");
      for (const auto& [key, value] : entry.items()) {
        if (!value.is_string()) fail(ErrorCode::Parse, src, "__metadata__ entry '" + key + "' is not a string");
        file.metadata_[key] = value.get<std::string>();
      }
      continue;
    }
    file.tensors_.push_back(parse_entry(name, entry, data_size, src));
  }
  std::sort(file.tensors_.begin(), file.tensors_.end(),
            [](const SafetensorsTensor& a, const SafetensorsTensor& b) { return a.begin < b.begin; });
  file.bytes_ = std::move(bytes);
  return file;
}

const SafetensorsTensor* SafetensorsFile::find(std::string_view name) const {
  for (const SafetensorsTensor& t : tensors_) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::vector<float> SafetensorsFile::floats(const SafetensorsTensor& tensor) const {
  if (tensor.dtype != "F32") {
    fail(ErrorCode::Unsupported, source_, "tensor '" + tensor.name + "' has dtype " + tensor.dtype + ", expected F32");
  }
  std::vector<float> values(tensor.element_count());
  // memcpy from or to the null data() of an empty vector is undefined.
  if (!values.empty()) {
    std::memcpy(values.data(), bytes_.data() + data_start_ + tensor.begin, values.size() * sizeof(float));
  }
  return values;
}

void write_safetensors(const std::filesystem::path& path, std::span<const SafetensorsFloatTensor> tensors,
                       const std::map<std::string, std::string>& metadata) {
  nlohmann::json header = nlohmann::json::object();
  std::size_t offset = 0;
  for (const SafetensorsFloatTensor& t : tensors) {
    std::size_t count = 1;
    for (std::size_t d : t.shape) count *= d;
    if (count != t.values.size()) {
      throw Error(ErrorCode::InvalidArgument, "write_safetensors: tensor '" + t.name + "' has " +
                                                  std::to_string(t.values.size()) + " values for shape " +
                                                  shape_text(t.shape));
    }
    header[t.name] = {{"dtype", "F32"}, {"shape", t.shape}, {"data_offsets", {offset, offset + count * 4}}};
    offset += count * 4;
  }
  if (!metadata.empty()) header["__metadata__"] = metadata;
  std::string text = header.dump();
  text.append((8 - text.size() % 8) % 8, ' ');  // 8-byte aligned data
  const std::uint64_t length = text.size();
  AtomicFileWriter out(path);
  out.write(&length, 8);
  out.write(text);
  for (const SafetensorsFloatTensor& t : tensors) out.write(t.values.data(), t.values.size() * sizeof(float));
  out.commit();
}

}  // namespace sarmap
