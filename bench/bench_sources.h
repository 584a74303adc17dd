// Guidance and output for the solver benchmarks: a smooth RGB pattern made row by row, rows discarded.
#pragma once

#include <benchmark/benchmark.h>

#include <cmath>
#include <span>

#include "gdp/guidance.h"
#include "gdp/rows.h"

namespace gdp::bench {

// Gradients of a smooth RGB pattern, generated row by row (cheap next to the solve).
class Pattern final : public GuidanceSource {
 public:
  Pattern(int w, int h) : w_(w), h_(h) {}
  int width() const override { return w_; }
  int height() const override { return h_; }
  int channels() const override { return 3; }
  void read_row(int j, GuidanceRow& out) override {
    for (int c = 0; c < 3; ++c) {
      for (int i = 0; i + 1 < w_; ++i) out.gx[c * (w_ - 1) + i] = std::sin(0.01 * (i + c)) * 1e-2;
      for (int i = 0; i < w_; ++i) out.gy[c * w_ + i] = std::cos(0.02 * (j + c)) * 1e-2;
    }
  }

 private:
  int w_, h_;
};

class Discard final : public RowWriter {
 public:
  void write_row(int, std::span<const float> row) override { benchmark::DoNotOptimize(row.data()); }
};

}  // namespace gdp::bench
