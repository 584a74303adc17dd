// Right-hand-side assembly: x-filter each guidance row once, combine rows along y.
#include "fem/rhs.h"

#include <algorithm>

#include "fem/stencils.h"

namespace gdp::fem {

RhsAssembler::RhsAssembler(const Axis& x, const Axis& y, double alpha, int channels)
    : x_(x), y_(y), alpha_(alpha), channels_(channels),
      h_(kRing * channels, std::vector<double>(x.n)), m_(kRing * channels, std::vector<double>(x.n)),
      out_(x.n) {}

void RhsAssembler::push(int j, const GuidanceRow& row, const Sink& sink) {
  const int n = x_.n, edges = x_.edges();
  const bool periodic = x_.boundary == AxisBoundary::Periodic;
  for (int c = 0; c < channels_; ++c) {
    const double* gx = row.gx.data() + static_cast<std::size_t>(c) * edges;
    const double* v = row.value.empty() ? nullptr : row.value.data() + static_cast<std::size_t>(c) * n;
    const double* gy = row.gy.empty() ? nullptr : row.gy.data() + static_cast<std::size_t>(c) * n;
    std::vector<double>& h = filtered(j, c);
    std::vector<double>& m = edge_row(j, c);
    const bool use_v = v && alpha_ != 0.0, use_gy = gy && j + 1 < y_.n;
    // Samples near the ends: folded or wrapped coefficients, looked up one by one.
    const auto general = [&](int i) {
      double acc = 0.0;
      for (int k = 0; k < 4; ++k) {
        int e = i - 2 + k;
        if (periodic) e = wrap_index(e, n);
        else if (e < 0 || e >= edges) continue;
        acc += x_.derivative[i][k] * gx[e];
      }
      double mv = 0.0, mg = 0.0;
      for (int d = -2; d <= 2; ++d) {
        const int col = x_.column(i, d);
        if (col < 0) continue;
        if (use_v) mv += x_.mass[i][d + 2] * v[col];
        if (use_gy) mg += x_.mass[i][d + 2] * gy[col];
      }
      h[i] = acc + alpha_ * mv;
      m[i] = mg;
    };
    // Interior samples: the plain stencils, vectorisable.
    const int lo = std::min(2, n), hi = std::max(lo, n - 2);
    for (int i = 0; i < lo; ++i) general(i);
    for (int i = lo; i < hi; ++i)
      h[i] = kDerivative[0] * gx[i - 2] + kDerivative[1] * gx[i - 1] + kDerivative[2] * gx[i] +
             kDerivative[3] * gx[i + 1];
    if (use_v)
      for (int i = lo; i < hi; ++i)
        h[i] += alpha_ * (kMass[0] * (v[i - 2] + v[i + 2]) + kMass[1] * (v[i - 1] + v[i + 1]) + kMass[2] * v[i]);
    for (int i = lo; i < hi; ++i)
      m[i] = use_gy ? kMass[0] * (gy[i - 2] + gy[i + 2]) + kMass[1] * (gy[i - 1] + gy[i + 1]) + kMass[2] * gy[i]
                    : 0.0;
    for (int i = hi; i < n; ++i) general(i);
  }
  pushed_ = j + 1;
  while (next_emit_ + 2 < pushed_) emit(next_emit_++, sink);
}

void RhsAssembler::finish(const Sink& sink) {
  while (next_emit_ < pushed_) emit(next_emit_++, sink);
}

void RhsAssembler::emit(int r, const Sink& sink) {
  const int n = x_.n, y_edges = y_.edges();
  for (int c = 0; c < channels_; ++c) {
    std::fill(out_.begin(), out_.end(), 0.0);
    for (int d = -2; d <= 2; ++d) {
      const int row = y_.column(r, d);
      const double w = y_.mass[r][d + 2];
      if (row < 0 || w == 0.0) continue;
      const std::vector<double>& h = filtered(row, c);
      for (int i = 0; i < n; ++i) out_[i] += w * h[i];
    }
    for (int k = 0; k < 4; ++k) {
      const int e = r - 2 + k;
      const double w = y_.derivative[r][k];
      if (e < 0 || e >= y_edges || w == 0.0) continue;
      const std::vector<double>& m = edge_row(e, c);
      for (int i = 0; i < n; ++i) out_[i] += w * m[i];
    }
    sink(r, c, out_);
  }
}

}  // namespace gdp::fem
