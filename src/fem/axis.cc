// Building fine axes by folding the interior stencils, and coarse axes by Galerkin products.
#include "fem/axis.h"

#include <algorithm>
#include <stdexcept>

#include "fem/stencils.h"

namespace gdp::fem {
namespace {

// Offset d in [-2, 2] with column(i, d) == c; for periodic tiny axes the first that matches.
int offset_of(const Axis& a, int i, int c) {
  for (int d = -2; d <= 2; ++d)
    if (a.column(i, d) == c) return d;
  throw std::logic_error("Galerkin product leaves the 5-wide band");
}

}  // namespace

int reflect_index(int c, int n) {
  while (c < 0 || c >= n) c = c < 0 ? -1 - c : 2 * n - 1 - c;
  return c;
}

int wrap_index(int c, int n) { return ((c % n) + n) % n; }

int mirror_column(Mirror m, int i, int n) {
  switch (m) {
    case Mirror::Top: return n - 1 - i;
    case Mirror::Bottom: return wrap_index(n / 2 - 1 - i, n);
    case Mirror::None: break;
  }
  return i;
}

int Axis::column(int i, int d) const {
  const int c = i + d;
  if (boundary == AxisBoundary::Periodic) return wrap_index(c, n);
  if (boundary == AxisBoundary::Mirrored) return reflect_index(c, n);
  return (c >= 0 && c < n) ? c : -1;
}

Mirror Axis::mirror(int i, int d) const {
  if (boundary != AxisBoundary::Mirrored) return Mirror::None;
  const int c = i + d;
  return c < 0 ? Mirror::Top : c >= n ? Mirror::Bottom : Mirror::None;
}

namespace {

// Row i of a fine matrix with the given interior stencil: Periodic and Mirrored rows keep every
// offset (the kernel reads the wrapped or mirrored row); Neumann rows move the coefficient of a
// ghost sample onto the sample it mirrors.
std::array<double, 5> fine_row(int i, int n, AxisBoundary boundary, const double* stencil, double scale) {
  std::array<double, 5> row{};
  for (int d = -2; d <= 2; ++d) {
    const int to = boundary != AxisBoundary::Neumann ? d : reflect_index(i + d, n) - i;
    row[to + 2] += stencil[d + 2] * scale;
  }
  return row;
}

std::array<double, 4> derivative_row(int i, int n, AxisBoundary boundary) {
  std::array<double, 4> row{};
  for (int k = 0; k < 4; ++k) {
    int e = i - 2 + k;
    double sign = 1.0;
    if (boundary == AxisBoundary::Neumann) {
      // Gradients extend oddly across a Neumann edge: edge -1 and n-1 straddle the
      // boundary (value 0), edge -2-e mirrors edge e with the opposite sign.
      while (e < -1 || e > n - 1) {
        e = e < -1 ? -2 - e : 2 * n - 2 - e;
        sign = -sign;
      }
      if (e == -1 || e == n - 1) continue;
      row[e - (i - 2)] += sign * kDerivative[k];
    } else {
      row[k] += kDerivative[k];
    }
  }
  return row;
}

}  // namespace

Axis make_fine_axis(int n, AxisBoundary boundary, int edge) {
  Axis a;
  a.n = n;
  a.boundary = boundary;
  a.mass = {n, [&](int i) { return fine_row(i, n, boundary, kMass.data(), 1.0); }, edge};
  a.stiffness = {n, [&](int i) { return fine_row(i, n, boundary, kStiffness.data(), 1.0); }, edge};
  a.derivative = {n, [&](int i) { return derivative_row(i, n, boundary); }, edge};
  return a;
}

int next_size(const Axis& fine) {
  const int m = (fine.n + 1) / 2;
  if (fine.boundary == AxisBoundary::Periodic) return m >= 3 ? m : fine.n;
  if (fine.boundary == AxisBoundary::Mirrored) return fine.n % 2 == 0 && fine.n >= 4 ? fine.n / 2 : fine.n;
  return m;
}

Prolongation make_prolongation(const Axis& fine, int m) {
  // Fine sample i interpolates from coarse i / 2: an odd axis halved to n / 2 would read past its end.
  if (m != fine.n && m != (fine.n + 1) / 2)
    throw std::logic_error("a prolongation keeps an axis or halves it rounding up");
  Prolongation p{m, std::vector<ProlongationRow>(fine.n)};
  for (int i = 0; i < fine.n; ++i) {
    if (m == fine.n) {
      p.rows[i] = {{i, i}, {1.0, 0.0}};
      continue;
    }
    const int j = i / 2;
    const int other = (i % 2 == 0) ? j - 1 : j + 1;
    const int o = fine.boundary == AxisBoundary::Periodic ? wrap_index(other, m) : reflect_index(other, m);
    const Mirror mirror = fine.boundary != AxisBoundary::Mirrored ? Mirror::None
                          : other < 0                              ? Mirror::Top
                          : other >= m                             ? Mirror::Bottom
                                                                   : Mirror::None;
    p.rows[i] = {{j, o}, {0.75, 0.25}, mirror};
  }
  return p;
}

Axis coarsen(const Axis& fine, const Prolongation& p, int edge) {
  const int m = p.coarse_n;
  Axis c;
  c.n = m;
  c.boundary = fine.boundary;
  c.scale = m == fine.n ? fine.scale : 2.0 * fine.scale;
  if (fine.boundary == AxisBoundary::Mirrored && m == fine.n) return fine;
  if ((fine.boundary == AxisBoundary::Periodic && m != fine.n && fine.n % 2 == 1) ||
      fine.boundary == AxisBoundary::Mirrored) {
    c.mass = {m, [&](int i) { return fine_row(i, m, fine.boundary, kMass.data(), c.scale); }, edge};
    c.stiffness = {m, [&](int i) { return fine_row(i, m, fine.boundary, kStiffness.data(), 1.0 / c.scale); }, edge};
    return c;
  }
  // Coarse row r of P^T A P, gathered from the fine rows whose prolongation reaches r: those
  // near 2r, and near the ends, where reflection or wrap-around sends rows to the other side.
  const auto galerkin = [&](int r, bool stiffness) {
    std::array<double, 5> row{};
    std::vector<int> candidates;
    for (int i = std::max(0, 2 * r - 3); i < std::min(fine.n, 2 * r + 5); ++i) candidates.push_back(i);
    for (int i = 0; i < std::min(3, fine.n); ++i) candidates.push_back(i);
    for (int i = std::max(0, fine.n - 3); i < fine.n; ++i) candidates.push_back(i);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    for (int i : candidates) {
      for (int d = -2; d <= 2; ++d) {
        const int k = fine.column(i, d);
        if (k < 0) continue;
        const double v = stiffness ? fine.stiffness[i][d + 2] : fine.mass[i][d + 2];
        if (fine.mass[i][d + 2] == 0.0 && fine.stiffness[i][d + 2] == 0.0) continue;
        for (int a = 0; a < 2; ++a) {
          if (p.rows[i].index[a] != r) continue;
          for (int b = 0; b < 2; ++b) {
            const double w = p.rows[i].weight[a] * p.rows[k].weight[b];
            if (w == 0.0) continue;
            row[offset_of(c, r, p.rows[k].index[b]) + 2] += w * v;
          }
        }
      }
    }
    return row;
  };
  c.mass = {m, [&](int r) { return galerkin(r, false); }, edge};
  c.stiffness = {m, [&](int r) { return galerkin(r, true); }, edge};
  return c;
}

}  // namespace gdp::fem
