// The process-wide scratch budget and budgeted anonymous memory for row stores.
#include "schedule/scratch_budget.h"

#include <sys/mman.h>

#include <algorithm>
#include <new>
#include <utility>

namespace gdp::schedule {
namespace {

void raise_peak(std::atomic<std::size_t>& peak, std::size_t value) {
  std::size_t seen = peak.load();
  while (value > seen && !peak.compare_exchange_weak(seen, value)) {
  }
}

}  // namespace

ScratchBudget& ScratchBudget::process() {
  static ScratchBudget budget;
  return budget;
}

bool ScratchBudget::reserve(std::size_t bytes) {
  std::size_t held = memory_.load();
  do {
    if (bytes > limit_.load() || held > limit_.load() - bytes) return false;
  } while (!memory_.compare_exchange_weak(held, held + bytes));
  raise_peak(memory_peak_, held + bytes);
  return true;
}

void ScratchBudget::release(std::size_t bytes) { memory_ -= bytes; }

void ScratchBudget::add_disk(std::ptrdiff_t bytes) {
  const std::size_t now = disk_ += static_cast<std::size_t>(bytes);
  raise_peak(disk_peak_, now);
}

void ScratchBudget::reset_peaks() {
  memory_peak_ = memory_.load();
  disk_peak_ = disk_.load();
  spilled_ = 0;
}

ScratchMemory::ScratchMemory(ScratchBudget& budget, std::size_t bytes) {
  if (!budget.reserve(bytes)) return;
  budget_ = &budget;
  size_ = bytes;
  if (bytes == 0) return;
  // Anonymous pages, zeroed by the kernel when prepare() maps them in, taken back at munmap. Not
  // asked for as 2 MB huge pages: where free memory is handed back to a hypervisor (this
  // development VM), a fresh huge page costs 2-4 s of system time per GB against about 0.6 s
  // for 4 KB pages mapped by prepare() (docs/how-streaming-works.md).
  void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p == MAP_FAILED) {
    free();
    throw std::bad_alloc();
  }
  data_ = static_cast<unsigned char*>(p);
}

void ScratchMemory::prepare(std::size_t bytes) {
  constexpr std::size_t kPage = 4096, kStep = std::size_t{4} << 20;
  if (bytes <= prepared_) return;
  const std::size_t end = std::min((std::max(bytes, prepared_ + kStep) + kPage - 1) & ~(kPage - 1),
                                   (size_ + kPage - 1) & ~(kPage - 1));
  ::madvise(data_ + prepared_, end - prepared_, MADV_POPULATE_WRITE);  // declined (before Linux 5.14): faults as before
  prepared_ = end;
}

ScratchMemory::~ScratchMemory() { free(); }

ScratchMemory::ScratchMemory(ScratchMemory&& other) noexcept { swap(other); }

ScratchMemory& ScratchMemory::operator=(ScratchMemory&& other) noexcept {
  ScratchMemory(std::move(other)).swap(*this);  // this one's old memory goes with the temporary
  return *this;
}

void ScratchMemory::swap(ScratchMemory& other) noexcept {
  std::swap(budget_, other.budget_);
  std::swap(data_, other.data_);
  std::swap(size_, other.size_);
  std::swap(prepared_, other.prepared_);
}

void ScratchMemory::free() {
  if (data_) ::munmap(data_, size_);
  if (budget_) budget_->release(size_);
  budget_ = nullptr;
  data_ = nullptr;
  size_ = prepared_ = 0;
}

}  // namespace gdp::schedule
