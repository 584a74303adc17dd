// Guidance taken from an image's own differences, with per-edge masks and offsets.
#pragma once

#include "gdp/guidance.h"
#include "gdp/image.h"

namespace gdp::apps {

// gx, gy = beta * (differences of `source`), value = `values` (may be null when alpha == 0).
// Subclasses decide which edges keep their gradient and may subtract a per-edge offset.
class ImageGuidance : public GuidanceSource {
 public:
  ImageGuidance(const Image& source, const Image* values, double alpha, double beta);
  int width() const override { return src_.width; }
  int height() const override { return src_.height; }
  int channels() const override { return src_.channels; }
  double alpha() const override { return alpha_; }
  void read_row(int j, GuidanceRow& out) override;

 protected:
  // Edge from (i, j) to (i2, j2), its right or lower neighbour (i2 may wrap to 0).
  virtual bool keep(int, int, int, int) const { return true; }
  // Value subtracted from a kept gradient along x (horizontal) or y, per channel.
  virtual double offset(int /*c*/, int /*i*/, int /*j*/, bool /*horizontal*/) const { return 0.0; }

  const Image& src_;

 private:
  const Image* values_;
  double alpha_, beta_;
};

}  // namespace gdp::apps
