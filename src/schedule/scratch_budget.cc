// The process-wide scratch budget: bytes held in memory and on disk, and their peaks.
#include "schedule/scratch_budget.h"

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

}  // namespace gdp::schedule
