// The process-wide scratch budget and budgeted anonymous memory for row stores.
#include "schedule/scratch_budget.h"

#include <algorithm>
#include <new>
#include <utility>

#include "util/big_pages.h"

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
  // Anonymous memory, zeroed by the kernel when prepare() maps it in, taken back at unmap: 2 MiB
  // huge pages where it is large (util::map_big), so prepare() maps a huge page per call where
  // it would map 512 small ones (docs/how-streaming-works.md, "Huge pages").
  try {
    data_ = static_cast<unsigned char*>(util::map_big(bytes));
  } catch (const std::bad_alloc&) {
    free();
    throw;
  }
}

void ScratchMemory::prepare(std::size_t bytes) {
  constexpr std::size_t kStep = std::size_t{4} << 20;
  if (bytes <= prepared_) return;
  const std::size_t end = std::min(std::max(bytes, prepared_ + kStep), size_);
  util::populate(data_ + prepared_, end - prepared_);
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
  util::unmap_big(data_, size_);
  if (budget_) budget_->release(size_);
  budget_ = nullptr;
  data_ = nullptr;
  size_ = prepared_ = 0;
}

}  // namespace gdp::schedule
