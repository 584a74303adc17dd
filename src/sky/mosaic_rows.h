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
#include "sky/plate_sweep.h"
#include "sky/pq_store.h"
#include "sky/pq_window.h"
#include "sky/seam_sources.h"
#include "sky/seams.h"

namespace gdp::blending {
class Scratch;
class LabelPlane;
}

namespace gdp::sky {

// Label of PQ pixels no plate covers (stitch's "unknown": white); plate k has label k + 2.
inline constexpr float kNoPlate = 1.0f;

// Rows the mosaic keeps computed (across_row(j) needs rows j - 1 .. j + 1), and how far past a
// plate's last row its pixels stay held (the cache and two rows).
inline constexpr int kCachedRows = 6;
inline constexpr int kReleaseLag = kCachedRows + 2;

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
  // read once, in order (as the solve reads them): a plate's pixels are read (`pixels`, made with
  // lag kReleaseLag) when a row first reaches it and released once the rows computed are
  // kReleaseLag past the last row it reaches (plate_rows); a row that would need a released plate
  // again throws std::logic_error.
  MosaicRows(std::vector<Plate>& plates, PlatePixels& pixels, const PqWindow& window,
             const SeamSources* sources = nullptr, const std::filesystem::path& temp_dir = {},
             std::size_t memory_limit = kSmallScratch);
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
  // Row j's coverage (computed before): inside a plate with a value, its label (plate + 2), else 0
  // (an extension or no plate). Kept in scratch (4 bytes a pixel), since the solve writes a row
  // long after reading it; only the columns computed (want_columns) are set.
  void coverage_row(int j, std::span<float> out) const;
  // Only columns [begin, end) are read from now on (the union of the calls; RowReader::set_columns
  // of the three views: a rank of a distributed solve). Rows are then computed over those columns
  // and one more on each side (across() needs its neighbours' labels), the rest left blank.
  void want_columns(int begin, int end);
  // From now on each pixel takes the plate `seams` labels it with (1 + the plate, the window's
  // size: graph-cut seams, sky/pq_graphcut.h) where that plate reaches it, else the rule above.
  void use_seams(const blending::LabelPlane* seams) { seams_ = seams; }
  // PQ pixels computed so far (rows computed again counted again).
  long long pixels_computed() const { return pixels_computed_; }

  struct Row {
    std::vector<float> value, label;
    std::vector<float> covered;  // inside a plate: its label (else 0: an extension, or no plate)
    std::vector<std::vector<PlateHit>> hits;  // per pixel, the plates reaching it
    std::vector<int> preferred;               // per pixel, the plate of a star's disk there (else -1)
    std::vector<float> across;                // across_row(): empty until asked for
  };
  const Row& row(int j) { return fetch(j); }
  // Row j's across values (see across()).
  const std::vector<float>& across_row(int j);

 private:
  Row& fetch(int j);
  void compute(int j, Row& out);

  std::vector<Plate>& plates_;
  PlatePixels& pixels_;  // which plates' pixels are held
  PqWindow window_;
  int released_below_ = 0;  // rows below this may need plates already released
  std::vector<char> released_;
  std::vector<int> sizes_;
  const SeamSources* sources_;  // stars in the overlaps: each wholly from one plate
  const blending::LabelPlane* seams_ = nullptr;
  int begin_ = 0, end_ = 0;     // the columns computed
  std::array<int, 2> wanted_{};  // the union of want_columns
  bool columns_set_ = false;
  long long pixels_computed_ = 0;
  std::unique_ptr<blending::Scratch> coverage_;  // window.width floats a row
  std::map<int, Row> cache_;
  std::array<int, 2> pinned_{1, 0};  // rows fetch() keeps cached: across_row(j)'s j - 1 .. j + 1
  std::vector<float> none_;          // a row of kNoPlate (above the first row, below the last)
  std::unique_ptr<RowReader> composite_, labels_, across_;
};

}  // namespace gdp::sky
