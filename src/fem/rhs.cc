// Right-hand-side assembly: x-filter each guidance row once, combine rows along y.
#include "fem/rhs.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "fem/stencils.h"
#include "util/clones.h"

namespace gdp::fem {
namespace {

// The interior loops, compiled for x86-64-v3 (AVX2) and the baseline, the loader picking one. This
// file is compiled with -ffp-contract=off (src/CMakeLists.txt): no multiply-add is fused, so both
// give the bits of the plain loops.

// out[i] = M v at columns [lo, hi), every neighbour inside the row.
GDP_CLONES void mass_interior(const double* v, double* out, int lo, int hi) {
  for (int i = lo; i < hi; ++i)
    out[i] = kMass[0] * (v[i - 2] + v[i + 2]) + kMass[1] * (v[i - 1] + v[i + 1]) + kMass[2] * v[i];
}

// out[i] = D gx at columns [lo, hi), every edge inside the row.
GDP_CLONES void derivative_interior(const double* gx, double* out, int lo, int hi) {
  for (int i = lo; i < hi; ++i)
    out[i] = kDerivative[0] * gx[i - 2] + kDerivative[1] * gx[i - 1] + kDerivative[2] * gx[i] + kDerivative[3] * gx[i + 1];
}

// out[i] = the sum of wt[k] * p[k][i] over the nine terms, in order, at columns [begin, end).
GDP_CLONES void combine_rows(const std::array<const double*, 9>& p, const std::array<double, 9>& wt, double* out,
                             int begin, int end) {
  const double *p0 = p[0], *p1 = p[1], *p2 = p[2], *p3 = p[3], *p4 = p[4], *p5 = p[5], *p6 = p[6], *p7 = p[7],
               *p8 = p[8];
#pragma GCC ivdep
  for (int i = begin; i < end; ++i)
    out[i] = wt[0] * p0[i] + wt[1] * p1[i] + wt[2] * p2[i] + wt[3] * p3[i] + wt[4] * p4[i] + wt[5] * p5[i] +
             wt[6] * p6[i] + wt[7] * p7[i] + wt[8] * p8[i];
}

}  // namespace

RhsAssembler::RhsAssembler(const Axis& x, const Axis& y, double alpha, int channels)
    : x_(x), y_(y), alpha_(alpha), channels_(channels),
      h_(kRing * channels, std::vector<double>(x.n)), m_(kRing * channels, std::vector<double>(x.n)),
      top_(y.boundary == AxisBoundary::Mirrored ? channels : 0, std::vector<double>(x.n)), out_(x.n), tmp_(x.n),
      zero_(x.n) {
  end_ = x.n;
}

void RhsAssembler::set_columns(int begin, int end) {
  if (pushed_ > 0 || y_.boundary == AxisBoundary::Mirrored || begin < 0 || begin > end || end > x_.n)
    throw std::logic_error("RhsAssembler::set_columns: not before the first row, on a folded axis or outside the row");
  begin_ = begin;
  end_ = end;
}

// out = M v along x at columns [begin_, end_): folded or wrapped coefficients near the ends, the
// plain stencil inside.
void RhsAssembler::mass_filter(const double* v, double* out) const {
  const int n = x_.n, lo = std::clamp(2, begin_, end_), hi = std::clamp(n - 2, lo, end_);
  const auto general = [&](int i) {
    double acc = 0.0;
    for (int d = -2; d <= 2; ++d) {
      const int col = x_.column(i, d);
      if (col >= 0) acc += x_.mass[i][d + 2] * v[col];
    }
    out[i] = acc;
  };
  for (int i = begin_; i < lo; ++i) general(i);
  mass_interior(v, out, lo, hi);
  for (int i = hi; i < end_; ++i) general(i);
}

// out = D gx along x at columns [begin_, end_) (the coupling of each B_i' with the edge hats).
void RhsAssembler::derivative_filter(const double* gx, double* out) const {
  const int n = x_.n, edges = x_.edges(), lo = std::clamp(2, begin_, end_), hi = std::clamp(n - 2, lo, end_);
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
  for (int i = begin_; i < lo; ++i) general(i);
  derivative_interior(gx, out, lo, hi);
  for (int i = hi; i < end_; ++i) general(i);
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
      for (int i = begin_; i < end_; ++i) h[i] += alpha_ * tmp_[i];
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

// out += w * row read mirrored (whole rows: Mirrored axes are never windowed).
void RhsAssembler::add_mirrored(const std::vector<double>& row, double w, Mirror mirror) {
  const int n = x_.n;
  for (int i = 0; i < n; ++i) out_[i] += w * row[mirror_column(mirror, i, n)];
}

void RhsAssembler::emit(int r, const Sink& sink) {
  const int n = y_.n;
  const bool mirrored = y_.boundary == AxisBoundary::Mirrored;
  for (int c = 0; c < channels_; ++c) {
    // At most 5 rows and 4 edge rows: one pass over all of them (zero rows fill the rest), then
    // the rows read mirrored, if any.
    std::array<const double*, 9> p;
    std::array<double, 9> wt{};
    p.fill(zero_.data());
    int terms = 0;
    struct Folded {
      const std::vector<double>* row;
      double w;
      Mirror mirror;
    };
    std::array<Folded, 9> folded{};
    int folds = 0;
    const auto add = [&](const std::vector<double>& row, double w, Mirror mirror) {
      if (mirror != Mirror::None) {
        folded[folds++] = {&row, w, mirror};
        return;
      }
      p[terms] = row.data();
      wt[terms++] = w;
    };
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
    combine_rows(p, wt, out_.data(), begin_, end_);
    for (int k = 0; k < folds; ++k) add_mirrored(*folded[k].row, folded[k].w, folded[k].mirror);
    sink(r, c, out_);
  }
}

}  // namespace gdp::fem
