// Page-aligned byte buffers (posix_memalign) for O_DIRECT transfers, and the alignment they need.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>

namespace gdp::io {

// Offsets, lengths and addresses of O_DIRECT transfers are multiples of this: a page, itself a
// multiple of every logical block size in use (512, 4096).
inline constexpr std::size_t kDirectAlign = 4096;

inline std::size_t align_up(std::size_t n) { return (n + kDirectAlign - 1) / kDirectAlign * kDirectAlign; }
inline std::size_t align_down(std::size_t n) { return n / kDirectAlign * kDirectAlign; }

// `size` bytes (rounded up to kDirectAlign) at a kDirectAlign-aligned address; std::bad_alloc.
class AlignedBytes {
 public:
  explicit AlignedBytes(std::size_t size) : size_(align_up(size)) {
    void* p = nullptr;
    if (::posix_memalign(&p, kDirectAlign, size_ ? size_ : kDirectAlign) != 0) throw std::bad_alloc();
    data_.reset(static_cast<unsigned char*>(p));
  }
  unsigned char* data() const { return data_.get(); }
  std::size_t size() const { return size_; }

 private:
  struct Free {
    void operator()(unsigned char* p) const { std::free(p); }
  };
  std::size_t size_;
  std::unique_ptr<unsigned char, Free> data_;
};

}  // namespace gdp::io
