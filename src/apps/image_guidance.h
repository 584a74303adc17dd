// Guidance taken from an image's own differences, streamed row by row, with per-edge masks and offsets.
#pragma once

#include <span>
#include <vector>

#include "fem/axis.h"
#include "gdp/guidance.h"
#include "gdp/rows.h"

namespace gdp::apps {

// gx, gy = beta * (differences of the source rows); value (when alpha > 0) = the source rows.
// The source rows are also the solver's `initial` rows: its starting guess, or, with
// start_from_source false, only the values whose mean a pure gradient solve keeps.
// Subclasses decide which edges keep their gradient and may subtract a per-edge offset.
class ImageGuidance : public GuidanceSource {
 public:
  ImageGuidance(RowReader& source, double alpha, double beta, bool start_from_source = true);
  // The source's, kept: per-pixel loops ask (through the readers' virtual calls otherwise).
  int width() const override { return width_; }
  int height() const override { return height_; }
  int channels() const override { return channels_; }
  double alpha() const override { return alpha_; }
  bool has_initial() const override { return true; }
  bool start_from_initial() const override { return start_; }
  void read_row(int j, GuidanceRow& out) override;
  // Splitting (GuidanceSource::splits): subclasses that keep their per-row data in slot(y) say so.
  void set_slots(int slots) override;
  void decode(int y) override;
  void compute(int j, GuidanceRow& out, int begin, int end) const override;
  // Passes the columns on to the source image (with the one column beyond that gx needs) and
  // computes only those columns' fields from then on.
  void set_columns(int begin, int end) override;

 protected:
  // The columns computed: [column_begin(), column_end()) of values and vertical edges, the same
  // less the last of horizontal ones; the whole row until set_columns.
  int column_begin() const { return end_ < 0 ? 0 : begin_; }
  int column_end() const { return end_ < 0 ? width() : end_; }
  bool windowed() const { return end_ >= 0 && (begin_ > 0 || end_ < width()); }
  // Row j's edges that keep their gradient, at columns [begin, end): right[i] from (i, j) to (i + 1, j) (wrapping to
  // column 0 on a periodic row), down[i] from (i, j) to below(i, j), above[i] (row 0 of a
  // spherical domain only, else empty: every column) from (i, 0) to above(i). All arrive set to 1,
  // except down on the last row of a non-spherical domain.
  virtual void keep_edges(int /*j*/, int /*begin*/, int /*end*/, std::span<unsigned char> /*right*/,
                          std::span<unsigned char> /*down*/, std::span<unsigned char> /*above*/) const {}
  // The column of the pixel below (i, j): i in row j + 1, or on the last row of a spherical
  // domain its partner across the bottom fold, in row j (fem::mirror_column).
  int below(int i, int j) const { return j + 1 < height() ? i : fem::mirror_column(fem::Mirror::Bottom, i, width()); }
  // The column of (i, 0)'s partner across the top fold of a spherical domain, in row 0.
  int above(int i) const { return fem::mirror_column(fem::Mirror::Top, i, width()); }
  // When true, offset() is subtracted from every kept gradient.
  virtual bool has_offsets() const { return false; }
  // Value subtracted from a kept gradient along x (horizontal) or y, per channel.
  virtual double offset(int /*c*/, int /*i*/, int /*j*/, bool /*horizontal*/) const { return 0.0; }
  // With offsets: marks (1) row j's edges, as keep_edges', whose offset() may be nonzero; every
  // other edge's is 0 and offset() is not asked. False (the default): ask at every kept edge.
  virtual bool offset_edges(int /*j*/, int /*begin*/, int /*end*/, std::span<unsigned char> /*right*/,
                            std::span<unsigned char> /*down*/) const {
    return false;
  }
  // Called once per source row y, in order, as soon as it is read (before rows up to y are
  // used): subclasses read their own per-row data here.
  virtual void on_source_row(int /*y*/, std::span<const float> /*row*/) {}
  // The slot of decoded row y (two slots unless set_slots said more): a subclass keeps its own
  // per-row data (on_source_row) in as many slots.
  int slots() const { return static_cast<int>(rows_.size()); }
  int slot(int y) const { return y % slots(); }
  // Decoded source row y (in its slot), channels * width samples.
  std::span<const float> source_row(int y) const { return rows_[slot(y)]; }

 private:

  RowReader& src_;
  int width_, height_, channels_;
  double alpha_, beta_;
  bool start_;
  std::vector<std::vector<float>> rows_;
  int begin_ = 0, end_ = -1;  // the columns computed (end_ < 0: whole rows)
};

}  // namespace gdp::apps
