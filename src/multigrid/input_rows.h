// The finest level's input rows (starting guess, right-hand side, mean weights, diagonal) from a guidance source.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "fem/rhs.h"
#include "gdp/guidance.h"
#include "multigrid/hierarchy.h"

namespace gdp::multigrid {

// What a solve needs to know of all its input rows: per channel the sum of w * u (the mean a
// pure gradient solve keeps) and |b|^2 (relative residuals), and the sum of w.
struct InputTotals {
  std::vector<double> weighted_sums, rhs_norms2;
  double weight_total = 0.0;
  void add(const InputTotals& t);
};

// Reads guidance rows in order and hands out, for rows j = 0, 1, ..., the starting guess u
// (non-finite samples -> 0), the right-hand side b (multiplied by LevelOperator::kScale) and the
// weight w of the pixel in the preserved mean (1 where counted and every channel of the
// starting guess is finite, else 0), converted to the kernel precision T. Sources with
// per-pixel weights also give the diagonal term d (row_ops.h: kScale * weight, or
// kPinnedDiagonal) and add d * value to b; d is empty otherwise. Keeps a few rows.
//
// The sums a solve needs (InputTotals) are kept per column range: the whole row by default, or
// each band's own columns, so that the band schedule adds them up in band order however its bands
// are spread over processes. With `columns`, only those columns of the rows handed out are
// computed (the others are 0): a process of a distributed solve, whose source knows the guidance
// two columns beyond them (GuidanceSource::set_columns), or a reader of the input pass by band
// (InputRing); not on spherical domains. `read` reads a guidance row (default: source.read_row).
template <class T>
class InputRows {
 public:
  using Range = std::pair<int, int>;  // columns [first, second)

  using Reader = std::function<void(int, GuidanceRow&)>;
  InputRows(GuidanceSource& source, const Hierarchy& hierarchy, std::vector<Range> sum_ranges = {},
            Range columns = {0, -1}, Reader read = {});
  void next(std::span<T> u, std::span<T> b, std::span<T> w, std::span<T> d = {});

  // After the last row: the sums over each range, and over all of them (added in range order).
  const std::vector<InputTotals>& range_totals() const { return totals_; }
  InputTotals totals() const;

 private:
  static constexpr int kRing = 4;  // guidance rows run two ahead of right-hand-side rows
  void read_guidance();

  GuidanceSource& source_;
  Reader read_row_;
  int width_, height_, channels_;
  fem::RhsAssembler assembler_;
  GuidanceRow row_;
  std::vector<std::vector<float>> initial_;           // ring of starting-guess rows
  std::vector<std::vector<unsigned char>> counted_;   // ring of counted flags
  std::vector<std::vector<T>> b_;                     // ring of right-hand-side rows, channels * width
  std::vector<std::vector<double>> d_, dv_;           // ring of diagonal rows and d * value
  int read_ = 0, emitted_ = 0, next_ = 0;
  int direct_row_ = -1;  // the row next() is filling, whose b goes straight to `direct_`
  T* direct_ = nullptr;
  int begin_ = 0, end_ = 0;  // the columns computed
  std::vector<Range> ranges_;
  std::vector<InputTotals> totals_;
};

}  // namespace gdp::multigrid
