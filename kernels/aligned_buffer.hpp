// A grow-only, 64-byte-aligned array of floats for kernel workspaces and packed
// weights: kernels know no engine types, and a workspace that only grows means
// no allocation once the first block has run.
#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <new>

namespace sarmap::kernels {

template <class T>
class AlignedBuffer {
 public:
  AlignedBuffer() = default;
  explicit AlignedBuffer(std::size_t size) { resize(size); }
  AlignedBuffer(AlignedBuffer&&) noexcept = default;
  AlignedBuffer& operator=(AlignedBuffer&&) noexcept = default;
  AlignedBuffer(const AlignedBuffer& other) { *this = other; }
  AlignedBuffer& operator=(const AlignedBuffer& other) {
    if (this != &other) {
      size_ = 0;
      resize(other.size_);
      if (other.size_ != 0) std::memcpy(data_.get(), other.data_.get(), other.size_ * sizeof(T));
    }
    return *this;
  }

  // Makes room for `size` elements; keeps the storage (and its contents) when
  // it is already large enough. New storage is zero-filled.
  void resize(std::size_t size) {
    if (size > capacity_) {
      data_.reset(static_cast<T*>(::operator new(size * sizeof(T), std::align_val_t{kAlignment})));
      std::memset(static_cast<void*>(data_.get()), 0, size * sizeof(T));
      capacity_ = size;
    }
    size_ = size;
  }

  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  // Bytes held, which may exceed size() elements after a shrink.
  std::size_t capacity_bytes() const { return capacity_ * sizeof(T); }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  static constexpr std::size_t kAlignment = 64;
  struct Free {
    void operator()(T* p) const { ::operator delete(p, std::align_val_t{kAlignment}); }
  };
  std::unique_ptr<T[], Free> data_;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace sarmap::kernels
