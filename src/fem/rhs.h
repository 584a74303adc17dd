// Assembling right-hand-side rows from guidance rows, streaming through a window of rows.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "fem/axis.h"
#include "gdp/guidance.h"

namespace gdp::fem {

// b = (D (x) M) gx + (M (x) D) gy + alpha (M (x) M) value, with the folded 1D matrices of the
// finest axes; on a Mirrored y axis (spherical domains) rows and edges beyond the ends are the
// rows and edges they reflect to, mirrored, and the edges across the ends come from the first
// row's gy_above and the last row's gy. Guidance rows go in with push() in order; each right-hand-side row is handed
// to the sink as soon as the rows it depends on (two below it) have arrived.
class RhsAssembler {
 public:
  using Sink = std::function<void(int row, int channel, std::span<const double> b)>;

  RhsAssembler(const Axis& x, const Axis& y, double alpha, int channels);
  // Before the first push: only columns [begin, end) of b are needed, from guidance known at
  // columns [begin - 2, end + 2) (edges [begin - 2, end + 1)); b is 0 elsewhere. Not on a
  // Mirrored y axis, whose first and last rows read mirrored columns.
  void set_columns(int begin, int end);
  void push(int j, const GuidanceRow& row, const Sink& sink);
  // Emits the rows still pending after the last push().
  void finish(const Sink& sink);

 private:
  static constexpr int kRing = 8;
  void emit(int r, const Sink& sink);
  void mass_filter(const double* v, double* out) const;
  void derivative_filter(const double* gx, double* out) const;
  void add_mirrored(const std::vector<double>& row, double w, Mirror mirror);
  std::vector<double>& filtered(int j, int c) { return h_[(j % kRing) * channels_ + c]; }
  std::vector<double>& edge_row(int e, int c) { return m_[(e % kRing) * channels_ + c]; }

  const Axis& x_;
  const Axis& y_;
  double alpha_;
  int channels_;
  int next_emit_ = 0;
  int pushed_ = 0;
  int begin_ = 0, end_ = 0;  // the columns computed
  std::vector<std::vector<double>> h_;  // D gx + alpha M value, per buffered row and channel
  std::vector<std::vector<double>> m_;  // M gy, per buffered edge row and channel
  std::vector<std::vector<double>> top_;  // Mirrored axes: M gy_above of row 0, per channel
  std::vector<double> out_, tmp_, zero_;
};

}  // namespace gdp::fem
