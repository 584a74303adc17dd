// The rows a blend hands to stitching: composite (each pixel from its layer), labels, and across-seam values.
#pragma once

#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <vector>

#include "blend/layer_rows.h"
#include "blend/seams.h"
#include "gdp/blend.h"
#include "gdp/rows.h"

namespace gdp::blending {

// Sweeps the canvas top to bottom, opening each layer at its first row and closing it after its
// last, and computes per row: the composite (the labelled layer's pixel, 0 where no layer covers
// it) and, with `across`, the across-seam values, twice the channels: at a pixel whose left and
// right neighbours carry exactly one other label, that layer's value there if it covers the
// pixel (the first channels), and the same for its upper and lower neighbours (the next ones);
// NaN elsewhere (StitchOptions::across). Rows are asked for in order; asking for an earlier row
// starts the sweep again. The rows are computed on a thread of their own, up to kAhead rows ahead
// of the one asked for (its errors are rethrown to the caller): the layers' rows are converted,
// calibrated and put together beside the solve. Layers the seam pass kept (`kept`) are read from
// there rather than decoded again (the label plane is filled first, so that the seam pass has run).
class CanvasSweep {
 public:
  CanvasSweep(const BlendPlan& plan, const LabelPlane& labels, bool wrap_x, bool across,
              const KeptRows* kept = nullptr);
  ~CanvasSweep();
  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  // Only columns [begin, end) are needed (several calls: their union); before rows are read.
  void set_columns(int begin, int end);
  std::span<const float> composite(int y);
  std::span<const float> across(int y);

 private:
  struct Row {  // a computed row: composite and across values (NaN but at the columns `set`)
    std::vector<float> composite, across;
    std::vector<int> set;
  };
  static constexpr int kAhead = 8;
  const Row& row(int y);
  void restart();  // stops the producer: the next row asked for starts the sweep again
  void produce();  // the producer thread: rows 0, 1, ... into the ring
  void advance(Row& out);  // computes row row_ + 1
  void compute_across(std::span<const Label> up, std::span<const Label> here, std::span<const Label> down, Row& out);

  const BlendPlan& plan_;
  const LabelPlane& labels_;
  const KeptRows* kept_;
  bool wrap_x_, with_across_;
  int width_, height_, channels_;
  int begin_ = 0, end_ = -1;  // end_ < 0: whole rows
  bool columns_set_ = false;
  // The producer's own state.
  int row_ = -1;
  std::vector<int> order_;  // layers by first row
  std::size_t next_ = 0;
  std::vector<std::unique_ptr<OpenLayer>> open_;
  std::vector<OpenLayer*> slot_;  // per layer: its open state, or null
  std::vector<Label> label_rows_[3];  // rows row_-1, row_, row_+1 (by y % 3)
  std::vector<Label> none_;           // no row (above the first, below the last): no labels
  std::vector<unsigned char> edge_;   // per column: another label beside the pixel
  // Shared with the caller, under mutex_: row y in ring_[y % kAhead] once ready_ >= y; rows below
  // held_ (the one the caller reads) may be overwritten.
  std::vector<Row> ring_;
  std::thread producer_;
  std::mutex mutex_;
  std::condition_variable changed_;
  int ready_ = -1, held_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

// A view of the sweep as a RowReader: its composite or its across rows.
class SweepReader final : public RowReader {
 public:
  SweepReader(CanvasSweep& sweep, bool across) : sweep_(sweep), across_(across) {}
  int width() const override { return sweep_.width(); }
  int height() const override { return sweep_.height(); }
  int channels() const override { return (across_ ? 2 : 1) * sweep_.channels(); }
  void read_row(int y, std::span<float> out) override;
  void rewind() override {}
  void set_columns(int begin, int end) override { sweep_.set_columns(begin, end); }

 private:
  CanvasSweep& sweep_;
  bool across_;
};

// The label plane as a one-channel label map for stitching: 1.0 (white: unknown) where no layer
// covers a pixel, -(layer + 1) elsewhere.
class LabelReader final : public RowReader {
 public:
  explicit LabelReader(const LabelPlane& labels) : labels_(labels), row_(labels.width()) {}
  int width() const override { return labels_.width(); }
  int height() const override { return labels_.height(); }
  int channels() const override { return 1; }
  void read_row(int y, std::span<float> out) override;
  void rewind() override {}
  void set_columns(int begin, int end) override {
    begin_ = begin;
    end_ = end;
    labels_.want_columns(begin, end);
  }

 private:
  const LabelPlane& labels_;
  std::vector<Label> row_;
  int begin_ = 0, end_ = -1;
};

}  // namespace gdp::blending
