// numpy's .npy format for float32 arrays: how a prepared DGCNN block and its
// logits travel between sarmap and any other implementation. The reader
// checks magic, version, descr ('<f4'), fortran_order and shape, and names
// what was wrong.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <vector>

namespace sarmap {

struct NpyArray {
  std::vector<std::size_t> shape;
  std::vector<float> values;  // C order
};

// Throws sarmap::Error (Io, Parse, Unsupported) naming the file and field.
NpyArray read_npy_f32(const std::filesystem::path& path);
// Writes a version 1.0 file, atomically.
void write_npy_f32(const std::filesystem::path& path, std::span<const std::size_t> shape, std::span<const float> values);

}  // namespace sarmap
