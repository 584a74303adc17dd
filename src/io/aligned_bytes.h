// Page-aligned byte buffers (posix_memalign, or a fresh huge-page mapping) for O_DIRECT transfers, and the alignment they need.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>

#include "util/big_pages.h"

namespace gdp::io {

// Offsets, lengths and addresses of O_DIRECT transfers are multiples of this: a page, itself a
// multiple of every logical block size in use (512, 4096).
inline constexpr std::size_t kDirectAlign = 4096;
using util::kHugePage;

inline std::size_t align_up(std::size_t n) { return (n + kDirectAlign - 1) / kDirectAlign * kDirectAlign; }
inline std::size_t align_down(std::size_t n) { return n / kDirectAlign * kDirectAlign; }

// `size` bytes (rounded up to kDirectAlign) at a kDirectAlign-aligned address; std::bad_alloc.
// With `huge`, `size` rounded up to kHugePage instead, mapped afresh at a kHugePage-aligned
// address and advised MADV_HUGEPAGE: where transparent huge pages are on (even "madvise" only),
// each kHugePage bytes are one page, which an O_DIRECT transfer pins in one step rather than 512
// (docs/how-streaming-works.md, "Cheaper O_DIRECT stores"); elsewhere ordinary pages back it.
class AlignedBytes {
 public:
  explicit AlignedBytes(std::size_t size, bool huge = false)
      : size_(huge ? (size + kHugePage - 1) / kHugePage * kHugePage : align_up(size)) {
    if (huge) {
      const std::size_t n = size_ ? size_ : kHugePage;
      data_ = {static_cast<unsigned char*>(util::map_huge(n)), Free{n}};
      return;
    }
    void* p = nullptr;
    if (::posix_memalign(&p, kDirectAlign, size_ ? size_ : kDirectAlign) != 0) throw std::bad_alloc();
    data_ = {static_cast<unsigned char*>(p), Free{0}};
  }
  unsigned char* data() const { return data_.get(); }
  std::size_t size() const { return size_; }

 private:
  struct Free {
    std::size_t mapped;  // bytes of a util::map_huge block (0: posix_memalign'ed)
    void operator()(unsigned char* p) const { mapped ? util::unmap_huge(p, mapped) : std::free(p); }
  };
  std::size_t size_;
  std::unique_ptr<unsigned char, Free> data_{nullptr, Free{0}};
};

}  // namespace gdp::io
