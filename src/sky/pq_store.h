// The solved PQ image (or window) as rows in scratch: in memory when small, else an unlinked file; never needed whole.
#pragma once

#include <filesystem>
#include <memory>
#include <span>

#include "gdp/image.h"
#include "gdp/rows.h"
#include "sky/pq_window.h"

namespace gdp::blending {
class Scratch;
}

namespace gdp::sky {

// Scratch of gdp sky kept in memory at most (blend's rule), unless --memory says less.
inline constexpr std::size_t kSmallScratch = std::size_t{8} << 20;

// Rows of a PQ window (one float channel, window.width x window.rows), written once and read back
// in any order by PqSampler (reproject.h), the HiPS writer and the display range: gdp sky holds
// only the rows a target tile, a HiPS tile or the solve reaches (docs/sky.md, "Memory, bands and
// mpirun"). Up to `memory_limit` bytes stay in memory, more go to an unlinked file in `temp_dir`.
class PqStore {
 public:
  PqStore(const PqWindow& window, const std::filesystem::path& temp_dir, std::size_t memory_limit = kSmallScratch);
  ~PqStore();
  PqStore(const PqStore&) = delete;
  PqStore& operator=(const PqStore&) = delete;
  // A copy of an in-memory PQ image (`window.width` x `window.rows`, one channel).
  PqStore(const Image& pq, const PqWindow& window);

  const PqWindow& window() const { return window_; }
  void write_row(int j, std::span<const float> row);
  void read_row(int j, std::span<float> row) const;  // thread-safe

 private:
  PqWindow window_;
  std::unique_ptr<blending::Scratch> rows_;
};

// The display cut of a stored PQ image (TOAST and HiPS PNGs): the 0.5th and 99.5th percentiles of
// its covered (finite) pixels (hi > lo; 0, 1 when nothing is covered), from every k-th pixel of
// the row-major window (about a million samples at most), read row by row.
std::pair<float, float> display_range(const PqStore& pq);

}  // namespace gdp::sky
