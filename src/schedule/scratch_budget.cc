// The process-wide scratch budget: bytes held in memory and on disk, and their peaks.
#include "schedule/scratch_budget.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

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

std::size_t ScratchBudget::direct_from(const SolverOptions& options) {
  const char* v = std::getenv("GDP_DIRECT_SCRATCH");
  const std::string text = v ? v : "";
  return text.empty() ? options.direct_scratch_from : text == "off" ? SIZE_MAX : parse_memory_size(text);
}

void ScratchBudget::apply(const SolverOptions& options) {
  const char* v = std::getenv("GDP_DIRECT_SCRATCH");
  set_limit(options.scratch_memory);
  set_direct(!v || std::string(v) != "off", direct_from(options));
}

std::size_t ScratchBudget::system_available() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::size_t kb = 0;
  while (meminfo >> key >> kb)
    if (key == "MemAvailable:") return kb << 10;
    else meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  return std::numeric_limits<std::size_t>::max();
}

bool ScratchBudget::reserve(std::size_t bytes) {
  if (bytes > limit_.load()) return false;  // (--memory 0: no /proc/meminfo read per store)
  const std::size_t room = std::min(limit_.load(), available_() / 2);
  std::size_t held = memory_.load();
  do {
    if (bytes > room || held > room - bytes) return false;
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
