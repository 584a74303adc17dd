// One layer of a blend, opened: its rows on the canvas with their coverage.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "blend/kept_rows.h"
#include "blend/photometric.h"
#include "gdp/blend.h"
#include "gdp/rows.h"

namespace gdp::blending {

// Where layer `index` of a plan lies on the canvas: canvas columns [x0, x1) and rows [y0, y1)
// (clipped to the canvas), starting at the layer's own column skip_x and row skip_y.
struct Footprint {
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  int skip_x = 0, skip_y = 0;
  int width() const { return x1 - x0; }
};
Footprint footprint(const BlendPlan& plan, int index);

// The colour channels of a layer of `channels` channels: 2 and 4 end with alpha.
inline int colour_channels_of(int channels) { return channels == 2 || channels == 4 ? channels - 1 : channels; }

// Coverage threshold of alpha and mask samples.
inline constexpr float kCovered = 0.5f;

// A layer's rows in canvas order. Opened on demand (files decoded row by row).
class LayerRows {
 public:
  // Only canvas columns [begin, end) will be used (a band or rank of a distributed solve): the
  // files decode only those (the rest of each row is left as it is). With `keep_into`, the rows
  // decoded are kept there (the seam pass); with `read_from`, they are read from there where the
  // layer was kept, instead of decoded again (the sweep).
  LayerRows(const BlendPlan& plan, int index, int begin, int end, bool prefetch, KeptRows* keep_into = nullptr,
            const KeptRows* read_from = nullptr);
  ~LayerRows();
  const Footprint& where() const { return where_; }
  // Canvas row y in [y0, y1), in increasing order: colour samples (the plan's colour channels x
  // width(), channel-major; a grey layer among RGB ones gives its grey to all three) and coverage
  // flags (width()), for the footprint's columns; calibrated when the plan has a photometry.
  void read(int y, std::span<float> colour, std::span<unsigned char> covered);
  // The coverage flags of canvas row y only (as read's; the colour is not converted).
  void coverage(int y, std::span<unsigned char> covered);

 private:
  int seek(int y);
  // Layer row `row`, its columns [x0, x0 + w): out -= the layer's LayerBackground.
  void subtract_background(int row, int x0, int w, float* out) const;

  Footprint where_;
  int channels_ = 0, colour_ = 0, next_ = 0;  // next_: the next row of the layer itself
  int own_ = 0;  // the layer's own colour channels (1: grey, promoted when colour_ is 3)
  float offset_ = 0.0f, mask_scale_ = 1.0f;  // LayerSource's
  LayerBackground background_;
  std::string name_;
  std::unique_ptr<RowReader> image_, mask_;
  std::unique_ptr<KeptRows::Writer> keep_;
  std::unique_ptr<KeptRows::Reader> kept_;
  std::vector<float> row_, mask_row_;
  RowCalibration calibration_;
};

// A layer open in a sweep down the canvas: its rows (LayerRows' arguments) and the last row read.
struct OpenLayer {
  OpenLayer(const BlendPlan& plan, int index, int begin, int end, bool prefetch, const KeptRows* read_from = nullptr);
  void read(int y) { rows->read(y, colour, covered); }

  int index;
  std::unique_ptr<LayerRows> rows;
  std::vector<float> colour;           // the plan's colour channels x the footprint's width, channel-major
  std::vector<unsigned char> covered;  // the footprint's width
};

}  // namespace gdp::blending
