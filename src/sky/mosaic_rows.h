// PQ rows of a plate mosaic: each pixel's value from the plate it lies deepest inside (stars from one plate), and that plate's label.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "gdp/rows.h"
#include "gdp/sphere.h"
#include "sky/plate.h"
#include "sky/pq_store.h"
#include "sky/pq_window.h"
#include "sky/seam_sources.h"
#include "sky/seams.h"

namespace gdp::blending {
class Scratch;
}

namespace gdp::sky {

// Label of PQ pixels no plate covers (stitch's "unknown": white); plate k has label k + 2.
inline constexpr float kNoPlate = 1.0f;

// Computes PQ rows (TOAST map, height H, width 4H) on demand: the composite (the chosen plate's
// bilinear value) and the label map (which plate). Around the plates, up to half a plate's size
// beyond its edges, pixels take the nearest plate's edge values (its extension, its label), so
// that the solve's unknown region (farther out: NaN, label kNoPlate) meets the plates only
// there (docs/sky.md); coverage() tells the plates from their extensions. Three RowReaders
// share the rows (the stitch reads the composite, the labels and `across` in step); a few recent
// rows are kept, older ones are computed again if asked for.
class MosaicRows {
 public:
  // Rows of `window` (its columns only); the views are window.width x window.rows. `sources`:
  // the stars the seams go around (none: each point from the plate it lies deepest inside).
  // `temp_dir`: where the coverage rows go when they exceed `memory_limit` bytes (coverage_row()). Rows are
  // read once, in order (as the solve reads them): a plate's pixels are released (emptied) once
  // the rows computed are past the last row it reaches (plate_rows), and a row that would need a
  // released plate again throws std::logic_error.
  MosaicRows(std::vector<Plate>& plates, const PqWindow& window, const SeamSources* sources = nullptr,
             const std::filesystem::path& temp_dir = {}, std::size_t memory_limit = kSmallScratch);
  ~MosaicRows();
  RowReader& composite() { return *composite_; }
  RowReader& labels() { return *labels_; }
  // Stitch's `across` image, two channels: at a pixel whose left and right neighbours that belong
  // to another plate belong to one plate M, M's (extended) value there (the first channel), and
  // the same for its neighbours in the rows above and below (the second); NaN elsewhere (no
  // neighbour of another plate, or two different ones in a pair). A seam edge then gets the mean
  // of both plates' differences as guidance, also where three plates meet.
  RowReader& across() { return *across_; }
  const PqWindow& window() const { return window_; }
  // Pixels (over all rows computed so far) each plate was chosen for.
  const std::vector<long long>& chosen() const { return chosen_; }
  // Row j's coverage (computed before): 1 inside a plate with a value, else 0 (an extension or no
  // plate). Kept in scratch (a byte a pixel), since the solve writes a row long after reading it.
  void coverage_row(int j, std::span<unsigned char> out) const;

  struct Row {
    std::vector<float> value, label;
    std::vector<unsigned char> covered;  // inside a plate (else an extension, or no plate)
    std::vector<std::vector<PlateHit>> hits;  // per pixel, the plates reaching it
    std::vector<float> across;                // across_row(): empty until asked for
  };
  const Row& row(int j) { return fetch(j); }
  // Row j's across values (see across()).
  const std::vector<float>& across_row(int j);

 private:
  Row& fetch(int j);
  void compute(int j, Row& out);

  std::vector<Plate>& plates_;
  PqWindow window_;
  std::vector<std::array<int, 2>> rows_of_;  // per plate: the first and last window row it reaches
  int released_below_ = 0;                   // rows below this may need plates already released
  std::vector<int> sizes_;
  const SeamSources* sources_;  // stars in the overlaps: each wholly from one plate
  std::vector<long long> chosen_;
  std::vector<unsigned char> counted_;  // rows already counted in chosen_
  std::unique_ptr<blending::Scratch> coverage_;  // window.width bytes a row
  std::map<int, Row> cache_;
  std::unique_ptr<RowReader> composite_, labels_, across_;
};

}  // namespace gdp::sky
