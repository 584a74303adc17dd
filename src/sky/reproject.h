// A PQ image of the sky onto a target image with its own WCS (Catmull-Rom cubic, bilinear next to blanks; blanks stay blank).
#pragma once

#include <memory>

#include "gdp/image.h"
#include "gdp/rows.h"
#include "sky/pq_window.h"
#include "sky/wcs.h"

namespace gdp::sphere {
class SourceGrid;
}

namespace gdp::sky {

// Values of `pq` (`window` of a TOAST PQ image, one channel) at directions: Catmull-Rom cubic where
// its 4 x 4 pixels are finite, else bilinear between its finite pixels (interpolate.h; across the folds on the whole sphere; a window clamps); NaN where the nearest
// PQ pixel is NaN (no plate there) or outside the window. at() may run on several threads.
class PqSampler {
 public:
  PqSampler(const Image& pq, const PqWindow& window);
  ~PqSampler();
  float at(const sphere::Vec3& d) const;

 private:
  const Image& pq_;
  PqWindow window_;
  std::unique_ptr<sphere::SourceGrid> grid_;
};

// Writes target.height() rows of target.width() samples (one channel): at each pixel centre's
// direction, PqSampler's value of `pq` (`window` of a TOAST PQ image, one channel) between its
// finite pixels; NaN where the nearest PQ pixel is NaN (no plate there) or outside the window,
// or where the pixel has no sky position. Returns how many target pixels got a value.
// commit() is left to the caller.
long long reproject_pq(const Image& pq, const PqWindow& window, const Wcs& target, RowWriter& out);

}  // namespace gdp::sky
