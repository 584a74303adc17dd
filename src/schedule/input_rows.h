// The finest level's input rows (starting guess, right-hand side, mean weights, diagonal) from a guidance source.
#pragma once

#include <span>
#include <vector>

#include "fem/rhs.h"
#include "gdp/guidance.h"
#include "multigrid/hierarchy.h"

namespace gdp::schedule {

// Reads guidance rows in order and hands out, for rows j = 0, 1, ..., the starting guess u
// (non-finite samples -> 0), the right-hand side b (multiplied by LevelOperator::kScale) and the
// weight w of the pixel in the preserved mean (1 where counted and every channel of the
// starting guess is finite, else 0), converted to the kernel precision T. Sources with
// per-pixel weights also give the diagonal term d (row_ops.h: kScale * weight, or
// kPinnedDiagonal) and add d * value to b; d is empty otherwise. Keeps a few rows.
template <class T>
class InputRows {
 public:
  InputRows(GuidanceSource& source, const multigrid::Hierarchy& hierarchy);
  void next(std::span<T> u, std::span<T> b, std::span<T> w, std::span<T> d = {});

  // After the last row: per channel sum of w * u and |b|^2, and the sum of w.
  const std::vector<double>& weighted_sums() const { return weighted_sum_; }
  const std::vector<double>& rhs_norms2() const { return b_norm2_; }
  double weight_total() const { return weight_total_; }

 private:
  static constexpr int kRing = 4;  // guidance rows run two ahead of right-hand-side rows
  void read_guidance();

  GuidanceSource& source_;
  int width_, height_, channels_;
  fem::RhsAssembler assembler_;
  GuidanceRow row_;
  std::vector<std::vector<float>> initial_;           // ring of starting-guess rows
  std::vector<std::vector<unsigned char>> counted_;   // ring of counted flags
  std::vector<std::vector<double>> b_;                // ring of assembled rows, channels * width
  std::vector<std::vector<double>> d_, dv_;           // ring of diagonal rows and d * value
  int read_ = 0, emitted_ = 0, next_ = 0;
  std::vector<double> weighted_sum_, b_norm2_;
  double weight_total_ = 0.0;
};

}  // namespace gdp::schedule
