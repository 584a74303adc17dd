// A stored PQ image of the sky onto a target image with its own WCS (Catmull-Rom cubic, bilinear next to blanks; blanks stay blank).
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "gdp/rows.h"
#include "gdp/sphere.h"
#include "sky/pq_store.h"
#include "sky/wcs.h"

namespace gdp::sphere {
class SourceGrid;
}

namespace gdp::sky {

// Values of a stored PQ image (`pq.window()` of a TOAST PQ image, one channel) at directions:
// Catmull-Rom cubic where its 4 x 4 pixels are finite, else bilinear between its finite pixels
// (interpolate.h; across the folds on the whole sphere; a window clamps); NaN where the nearest PQ
// pixel is NaN (no plate there) or outside the window. Directions come in batches (a target row's
// tile, a HiPS tile): the sampler reads the PQ rows the batch reaches, keeping those it already
// holds, and drops the others, so memory follows the batch, not the PQ image.
class PqSampler {
 public:
  explicit PqSampler(const PqStore& pq);
  ~PqSampler();
  // out[k] = the value at dirs[k], sampled by `threads` workers.
  void sample(std::span<const sphere::Vec3> dirs, std::span<float> out, int threads = 1);
  float at(const sphere::Vec3& d);  // one direction
  // The most PQ rows held at once so far.
  int peak_rows() const { return peak_rows_; }

 private:
  float value(const sphere::Point2& p) const;
  float pixel(int i, int j) const { return rows_[j - lo_][i]; }  // window pixel; row j held
  void hold(int lo, int hi);

  const PqStore& pq_;
  PqWindow window_;
  std::unique_ptr<sphere::SourceGrid> grid_;
  int lo_ = 0, peak_rows_ = 0;
  std::vector<std::vector<float>> rows_;  // window rows lo_, lo_ + 1, ...
  std::vector<sphere::Point2> coords_;
};

// Writes target.height() rows of target.width() samples (one channel): at each pixel centre's
// direction, PqSampler's value of `pq`; NaN where the nearest PQ pixel is NaN (no plate there) or
// outside the window, or where the pixel has no sky position. Target rows are sampled in tiles of
// 64 x 256 pixels (the PQ rows one tile reaches held at once). Returns how many target pixels got
// a value. commit() is left to the caller.
long long reproject_pq(const PqStore& pq, const Wcs& target, RowWriter& out);

}  // namespace gdp::sky
