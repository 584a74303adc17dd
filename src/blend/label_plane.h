// The canvas's seam labels, kept a row at a time as runs of one label (in memory while small, else in a file).
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <span>
#include <vector>

#include "blend/scratch.h"

namespace gdp::blending {

// Per canvas pixel: 0 where no layer covers it, else 1 + the index of the layer it takes.
using Label = std::uint16_t;
inline constexpr int kMaxLayers = 65535;

// The canvas's labels, a row at a time, in any order. A row is kept as its runs of one label (a
// seam row has a few: bytes per row, not per pixel), or as it is where that is smaller; the rows
// kept stay in memory up to 8 MiB, then go to a scratch file in `dir` (rows rewritten take new
// room). Rows may be written and read on several threads. The plane may be filled on demand:
// defer() names what fills it, want_columns() (from readers' set_columns) gathers the columns
// needed, and the first read_row fills the plane for their union, once (for every column when
// none was asked for). Outside those columns the labels are then undefined.
class LabelPlane {
 public:
  using Fill = std::function<void(LabelPlane& plane, int begin, int end)>;
  LabelPlane(const std::filesystem::path& dir, int width, int height);
  ~LabelPlane();
  LabelPlane(const LabelPlane&) = delete;
  LabelPlane& operator=(const LabelPlane&) = delete;
  int width() const { return width_; }
  int height() const { return height_; }
  void write_row(int y, std::span<const Label> row);
  // Columns [begin, end) of row y into row[begin, end) (0 for a row never written).
  void read_row(int y, std::span<Label> row, int begin = 0, int end = -1) const;
  // The bytes kept: the rows and their index.
  std::size_t bytes() const;
  void defer(Fill fill) {
    fill_ = std::move(fill);
    filled_ = false;
  }
  void want_columns(int begin, int end) const;
  // Fills a deferred plane now (no-op otherwise).
  void fill() const;

 private:
  struct Kept {  // where row y's units (Labels) are: `at` in the store, `units` of them
    std::uint64_t at = 0;
    std::uint32_t units = 0;  // 0: never written
    std::uint32_t runs = 0;   // 1: (label, length - 1) pairs; 0: the row as it is
  };
  void units(const Kept& k, std::vector<Label>& out) const;

  int width_, height_;
  std::filesystem::path dir_;
  Scratch index_;  // a Kept per row
  mutable std::mutex mutex_;  // the store
  std::vector<Label> memory_;  // the rows' units while they fit in memory
  int fd_ = -1;                // then a file (memory_ copied into it)
  std::uint64_t end_ = 0;      // units kept
  mutable Fill fill_;
  mutable int want_begin_ = 0, want_end_ = 0;  // want_end_ == 0: nothing asked for yet
  mutable std::atomic<bool> filled_{true};     // nothing (left) to fill
  mutable std::mutex fill_mutex_;              // readers on several threads fill it once
};

}  // namespace gdp::blending
