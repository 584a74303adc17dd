// Right-hand-side assembly: x-filter each guidance row once, combine rows along y.
#include "fem/rhs.h"

#include <algorithm>

#include "fem/stencils.h"

namespace gdp::fem {

RhsAssembler::RhsAssembler(const Axis& x, const Axis& y, double alpha, int channels)
    : x_(x), y_(y), alpha_(alpha), channels_(channels),
      h_(kRing * channels, std::vector<double>(x.n)), m_(kRing * channels, std::vector<double>(x.n)),
      top_(y.boundary == AxisBoundary::Mirrored ? channels : 0, std::vector<double>(x.n)), out_(x.n), tmp_(x.n) {}

// out = M v along x: folded or wrapped coefficients near the ends, the plain stencil inside.
void RhsAssembler::mass_filter(const double* v, double* out) const {
  const int n = x_.n, lo = std::min(2, n), hi = std::max(lo, n - 2);
  const auto general = [&](int i) {
    double acc = 0.0;
    for (int d = -2; d <= 2; ++d) {
      const int col = x_.column(i, d);
      if (col >= 0) acc += x_.mass[i][d + 2] * v[col];
    }
    out[i] = acc;
  };
  for (int i = 0; i < lo; ++i) general(i);
  for (int i = lo; i < hi; ++i)
    out[i] = kMass[0] * (v[i - 2] + v[i + 2]) + kMass[1] * (v[i - 1] + v[i + 1]) + kMass[2] * v[i];
  for (int i = hi; i < n; ++i) general(i);
}

// out = D gx along x (the coupling of each B_i' with the edge hats).
void RhsAssembler::derivative_filter(const double* gx, double* out) const {
  const int n = x_.n, edges = x_.edges(), lo = std::min(2, n), hi = std::max(lo, n - 2);
  const bool periodic = x_.boundary == AxisBoundary::Periodic;
  const auto general = [&](int i) {
    double acc = 0.0;
    for (int k = 0; k < 4; ++k) {
      int e = i - 2 + k;
      if (periodic) e = wrap_index(e, n);
      else if (e < 0 || e >= edges) continue;
      acc += x_.derivative[i][k] * gx[e];
    }
    out[i] = acc;
  };
  for (int i = 0; i < lo; ++i) general(i);
  for (int i = lo; i < hi; ++i)
    out[i] = kDerivative[0] * gx[i - 2] + kDerivative[1] * gx[i - 1] + kDerivative[2] * gx[i] + kDerivative[3] * gx[i + 1];
  for (int i = hi; i < n; ++i) general(i);
}

void RhsAssembler::push(int j, const GuidanceRow& row, const Sink& sink) {
  const int n = x_.n, edges = x_.edges();
  const bool mirrored = y_.boundary == AxisBoundary::Mirrored;
  for (int c = 0; c < channels_; ++c) {
    const double* gx = row.gx.data() + static_cast<std::size_t>(c) * edges;
    const double* v = row.value.empty() ? nullptr : row.value.data() + static_cast<std::size_t>(c) * n;
    const double* gy = row.gy.empty() ? nullptr : row.gy.data() + static_cast<std::size_t>(c) * n;
    std::vector<double>& h = filtered(j, c);
    std::vector<double>& m = edge_row(j, c);
    derivative_filter(gx, h.data());
    if (v && alpha_ != 0.0) {
      mass_filter(v, tmp_.data());
      for (int i = 0; i < n; ++i) h[i] += alpha_ * tmp_[i];
    }
    // A Mirrored axis's last row has an edge below it too: across the bottom edge.
    if (gy && (j + 1 < y_.n || mirrored)) mass_filter(gy, m.data());
    else std::fill(m.begin(), m.end(), 0.0);
    if (mirrored && j == 0) {
      if (row.gy_above.empty()) std::fill(top_[c].begin(), top_[c].end(), 0.0);
      else mass_filter(row.gy_above.data() + static_cast<std::size_t>(c) * n, top_[c].data());
    }
  }
  pushed_ = j + 1;
  while (next_emit_ + 2 < pushed_) emit(next_emit_++, sink);
}

void RhsAssembler::finish(const Sink& sink) {
  while (next_emit_ < pushed_) emit(next_emit_++, sink);
}

// out += w * row, the row read mirrored where `mirror` says so.
void RhsAssembler::add(const std::vector<double>& row, double w, Mirror mirror) {
  const int n = x_.n;
  if (mirror == Mirror::None) {
    for (int i = 0; i < n; ++i) out_[i] += w * row[i];
  } else {
    for (int i = 0; i < n; ++i) out_[i] += w * row[mirror_column(mirror, i, n)];
  }
}

void RhsAssembler::emit(int r, const Sink& sink) {
  const int n = y_.n;
  const bool mirrored = y_.boundary == AxisBoundary::Mirrored;
  for (int c = 0; c < channels_; ++c) {
    std::fill(out_.begin(), out_.end(), 0.0);
    // Rows: a ghost row of a Mirrored axis is the row it reflects to, mirrored (the x-filtered
    // gradients and values of a 180-degree-rotated row are the filtered row, mirrored).
    for (int d = -2; d <= 2; ++d) {
      const int row = y_.column(r, d);
      const double w = y_.mass[r][d + 2];
      if (row < 0 || w == 0.0) continue;
      add(filtered(row, c), w, y_.mirror(r, d));
    }
    // Edges e = r-2 .. r+1 between rows e and e+1.
    for (int k = 0; k < 4; ++k) {
      const int e = r - 2 + k;
      const double w = y_.derivative[r][k];
      if (w == 0.0) continue;
      if (!mirrored) {
        if (e >= 0 && e < y_.edges()) add(edge_row(e, c), w, Mirror::None);
      } else if (e == -1) {
        add(top_[c], w, Mirror::None);  // across the top edge
      } else if (e < -1) {
        add(edge_row(-2 - e, c), -w, Mirror::Top);  // a rotated edge changes sign
      } else if (e >= n) {
        add(edge_row(2 * n - 2 - e, c), -w, Mirror::Bottom);
      } else {
        add(edge_row(e, c), w, Mirror::None);  // e == n - 1: across the bottom edge
      }
    }
    sink(r, c, out_);
  }
}

}  // namespace gdp::fem
