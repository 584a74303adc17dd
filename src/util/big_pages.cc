// Huge-page anonymous mappings for large buffers (big_pages.h).
#include "util/big_pages.h"

#include <sys/mman.h>

#include <cstdint>

namespace gdp::util {
namespace {

// `bytes` rounded up to whole huge pages (what map_huge maps).
std::size_t huge_length(std::size_t bytes) { return (bytes + kHugePage - 1) & ~(kHugePage - 1); }

// What map_big(bytes) maps: whole huge pages for a big buffer, else the bytes asked for.
std::size_t mapped_length(std::size_t bytes) { return bytes >= kBigBuffer ? huge_length(bytes) : bytes; }

void* map_anonymous(std::size_t bytes) {
  void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  return p;
}

}  // namespace

void* map_big(std::size_t bytes) {
  if (bytes == 0) return nullptr;
  if (bytes < kBigBuffer) return map_anonymous(bytes);  // a few 4 KB pages: no huge page for them
  return map_huge(bytes);
}

void unmap_big(void* p, std::size_t bytes) noexcept {
  if (p) ::munmap(p, mapped_length(bytes));
}

void* map_huge(std::size_t bytes) {
  const std::size_t length = huge_length(bytes);
  if (length < bytes || length > static_cast<std::size_t>(-1) - kHugePage) throw std::bad_alloc();
  // Map a huge page more than needed, then cut the ends off so that what is left starts on a
  // 2 MiB boundary (mmap only promises 4 KB ones).
  const std::size_t mapped = length + kHugePage;
  void* p = map_anonymous(mapped);
  const auto start = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t aligned = (start + kHugePage - 1) & ~std::uintptr_t{kHugePage - 1};
  if (aligned > start) ::munmap(p, aligned - start);
  const std::size_t tail = start + mapped - (aligned + length);
  if (tail > 0) ::munmap(reinterpret_cast<void*>(aligned + length), tail);
  ::madvise(reinterpret_cast<void*>(aligned), length, MADV_HUGEPAGE);  // declined: 4 KB pages
  return reinterpret_cast<void*>(aligned);
}

void unmap_huge(void* p, std::size_t bytes) noexcept {
  if (p) ::munmap(p, huge_length(bytes));
}

void populate(void* p, std::size_t bytes) noexcept {
  constexpr std::uintptr_t kPage = 4096;
  const auto begin = reinterpret_cast<std::uintptr_t>(p) & ~(kPage - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes + kPage - 1) & ~(kPage - 1);
  if (bytes > 0) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
}

}  // namespace gdp::util
