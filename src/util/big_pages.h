// Large buffers in anonymous memory on 2 MiB boundaries, asked for as transparent huge pages.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <vector>

namespace gdp::util {

// Buffers of at least kBigBuffer bytes come from map_big(); smaller ones from the heap.
inline constexpr std::size_t kHugePage = std::size_t{2} << 20;
inline constexpr std::size_t kBigBuffer = std::size_t{4} << 20;

// `bytes` of zeroed anonymous memory. At least kBigBuffer bytes start on a 2 MiB boundary, their
// length rounded up to whole 2 MiB pages, advised as huge pages (madvise(MADV_HUGEPAGE); the kernel's THP mode "madvise"
// or "always" honours it, "never" gives 4 KB pages). A huge page costs one fault instead of 512,
// and under a hypervisor that shadows the guest's page tables one exit instead of 512
// (docs/how-streaming-works.md, "Huge pages"). std::bad_alloc when the system refuses.
void* map_big(std::size_t bytes);
// Gives back what map_big(bytes) returned (the same `bytes`).
void unmap_big(void* p, std::size_t bytes) noexcept;
// `bytes` (> 0) rounded up to whole huge pages of zeroed anonymous memory on a 2 MiB boundary,
// advised as huge pages whatever the size (map_big's large buffers; O_DIRECT buffers, io/aligned_bytes.h).
// std::bad_alloc when the system refuses. unmap_huge(p, bytes) gives it back.
void* map_huge(std::size_t bytes);
void unmap_huge(void* p, std::size_t bytes) noexcept;
// Maps the pages of [p, p + bytes) in now, in one call (MADV_POPULATE_WRITE, Linux 5.14; where the
// kernel declines they fault in as they are written). p need not be page-aligned.
void populate(void* p, std::size_t bytes) noexcept;

// An allocator for std::vector: blocks of kBigBuffer bytes and more are map_big() memory, the
// rest the heap's. Stateless, so vectors of it swap and move like plain ones.
template <class T>
struct BigAllocator {
  using value_type = T;
  BigAllocator() = default;
  template <class U>
  BigAllocator(const BigAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    if (n * sizeof(T) >= kBigBuffer) return static_cast<T*>(map_big(n * sizeof(T)));
    return std::allocator<T>().allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) >= kBigBuffer) unmap_big(p, n * sizeof(T));
    else std::allocator<T>().deallocate(p, n);
  }
  template <class U>
  bool operator==(const BigAllocator<U>&) const noexcept { return true; }
};

// A vector whose large buffers are huge-page memory (planes, windows of rows).
template <class T>
using BigVector = std::vector<T, BigAllocator<T>>;

}  // namespace gdp::util
