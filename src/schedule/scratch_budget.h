// One process-wide budget of memory for scratch rows: how much row stores may keep in memory.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

#include "gdp/solver.h"

namespace gdp::schedule {

// How many bytes of scratch the row stores of the whole process may keep in memory; a store
// that does not fit goes to a file instead (row_store.h). Thread-safe: lanes and bands create
// their stores concurrently. Also counts what went where, for --stats.
class ScratchBudget {
 public:
  // What the system can still give, in bytes (the default: MemAvailable of /proc/meminfo, read at
  // each reserve() within the limit). A store in memory is a memfd, whose pages nothing can reclaim
  // without swap, so what the budget holds stays within half of what is available: on a machine
  // that others have filled, stores go to files rather than push out the page cache or call in the
  // OOM killer. MemAvailable already leaves out the memfd pages held, so in practice the stores
  // take at most a third of what was available before the first of them.
  using Available = std::size_t (*)();
  static std::size_t system_available();
  explicit ScratchBudget(std::size_t limit = 0, Available available = &system_available)
      : limit_(limit), available_(available) {}
  // The budget every solve of this process shares (its limit set from SolverOptions::scratch_memory).
  static ScratchBudget& process();

  void set_limit(std::size_t bytes) { limit_.store(bytes); }
  // Stores of at least direct_from() bytes are O_DIRECT files where the directory takes them, even
  // when they would fit the budget; with direct_files() false none is, not even one past the budget.
  void set_direct(bool files, std::size_t from) { direct_files_ = files, direct_from_ = from; }
  // A solve's: the limit SolverOptions::scratch_memory, direct_from() the one below.
  void apply(const SolverOptions& options);
  // SolverOptions::direct_scratch_from, or GDP_DIRECT_SCRATCH's ("off": none at all, or a size).
  static std::size_t direct_from(const SolverOptions& options);
  bool direct_files() const { return direct_files_.load(); }
  std::size_t direct_from() const { return direct_from_.load(); }

  // Takes `bytes` from the budget if they fit its limit and half of what is available (true),
  // else takes nothing (false).
  bool reserve(std::size_t bytes);
  void release(std::size_t bytes);
  // Bytes written to (or dropped from) scratch files.
  void add_disk(std::ptrdiff_t bytes);

  std::size_t in_memory() const { return memory_.load(); }
  std::size_t on_disk() const { return disk_.load(); }
  // The most held at once since reset_peaks(), and the stores that did not fit.
  std::size_t peak_in_memory() const { return memory_peak_.load(); }
  std::size_t peak_on_disk() const { return disk_peak_.load(); }
  std::size_t spilled() const { return spilled_.load(); }
  void count_spill() { ++spilled_; }
  void reset_peaks();

 private:
  std::atomic<std::size_t> limit_, direct_from_{static_cast<std::size_t>(-1)};
  std::atomic<bool> direct_files_{true};
  Available available_;
  std::atomic<std::size_t> memory_{0}, disk_{0}, memory_peak_{0}, disk_peak_{0}, spilled_{0};
};

}  // namespace gdp::schedule
