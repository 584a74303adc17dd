// Per-layer weights and pins as the per-pixel rows stitching takes: from the label plane, plus canvas images.
#pragma once

#include <vector>

#include "blend/seams.h"
#include "gdp/rows.h"

namespace gdp::blending {

// At each canvas pixel, the value of the layer that pixel takes: `per_layer[label - 1]` (0 where
// no layer covers it or the list is empty), combined with the first channel of `image` (optional,
// the canvas's size): added (weights) or, with `either`, 1 where either is above 0.5 (pins).
// One channel; InputError naming `image_name` when the image's size is not the canvas's.
class LayerFidelityReader final : public RowReader {
 public:
  LayerFidelityReader(const LabelPlane& labels, std::vector<float> per_layer, RowReader* image,
                      const std::string& image_name, bool either);
  int width() const override { return labels_.width(); }
  int height() const override { return labels_.height(); }
  int channels() const override { return 1; }
  void read_row(int y, std::span<float> out) override;
  void rewind() override {
    if (image_) image_->rewind();
  }
  void set_columns(int begin, int end) override;

 private:
  const LabelPlane& labels_;
  std::vector<float> per_layer_;
  RowReader* image_;
  bool either_;
  std::vector<Label> labels_row_;
  std::vector<float> image_row_;
  int begin_ = 0, end_ = -1;
};

}  // namespace gdp::blending
