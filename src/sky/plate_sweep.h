// Plates' pixels in memory only while the PQ rows they reach are current: read on demand, released after, counted.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "sky/plate.h"
#include "sky/plate_backgrounds.h"
#include "sky/pq_window.h"

namespace gdp::sky {

// Holds the pixels of the plates (and of their --seams-from plates, read and released with
// theirs) that the current PQ rows reach, so that gdp sky's memory grows with the plates crossing
// a row, not with the plate count (docs/sky.md, "Memory, bands and mpirun"). The plates stay
// (their WCS and footprints); only their pixels come and go, read again from the files when a
// later pass needs them, less the fitted smooth backgrounds once those are set.
class PlatePixels {
 public:
  // `finders`: empty, or one plate per plate whose stars place the seams (same grids).
  // `lag`: rows a plate stays held after its last row (the solve's cached rows: MosaicRows).
  PlatePixels(std::vector<Plate>& plates, std::vector<Plate>& finders, const PqWindow& window, int lag);

  std::size_t size() const { return plates_.size(); }
  // The first and last window row plate k (or its finder) reaches, with its extension (plate_rows).
  const std::array<int, 2>& rows(std::size_t k) const { return rows_[k]; }
  // The same for the window's columns (plate_columns; every column on the whole sphere).
  const std::array<int, 2>& columns(std::size_t k) const { return columns_[k]; }
  // The plate whose stars place the seams: finders[k], or plate k itself.
  const Plate& finder(std::size_t k) const { return finders_.empty() ? plates_[k] : finders_[k]; }
  // Taken off every plate read from now on (subtract_smooth_background); empty: none.
  void set_backgrounds(std::vector<PlateBackground> backgrounds) { backgrounds_ = std::move(backgrounds); }

  void hold(std::size_t k);     // reads plate k's pixels (and its finder's) unless held
  void release(std::size_t k);  // frees them
  std::size_t held() const { return held_; }
  // The most plates held at once so far (over every pass), and the most whose rows, `lag` rows
  // after their last included, meet one PQ row: the first never exceeds the second.
  std::size_t most_held() const { return most_held_; }
  std::size_t most_crossing() const;
  // Plate pixels read from the files so far (finders' included; a plate read again counted again).
  long long pixels_read() const { return pixels_read_; }

  // Visits every plate in order of its first row (ties: plate order) with its pixels held and
  // `others`: the plates visited before whose rows reach that row, held too; plates whose rows
  // end above it are released first, and all at the end. Every pair of plates that share a point
  // of the sky is held together when the later one is visited (both reach that point's row).
  // `only`: empty, or one flag per plate: only the flagged plates are visited and held (a rank's
  // plates under mpirun, plate_passes.h).
  using Visit = std::function<void(std::size_t k, const std::vector<std::size_t>& others)>;
  void sweep(const Visit& visit, const std::vector<char>& only = {});

 private:
  std::vector<Plate>& plates_;
  std::vector<Plate>& finders_;
  std::vector<std::array<int, 2>> rows_, columns_;
  std::vector<PlateBackground> backgrounds_;
  std::vector<char> holding_;
  int lag_ = 0;
  std::size_t held_ = 0, most_held_ = 0;
  long long pixels_read_ = 0;
};

}  // namespace gdp::sky
