// Building fine axes by folding the interior stencils, and coarse axes by Galerkin products.
#include "fem/axis.h"

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

int Axis::column(int i, int d) const {
  const int c = i + d;
  if (boundary == AxisBoundary::Periodic) return wrap_index(c, n);
  return (c >= 0 && c < n) ? c : -1;
}

Axis make_fine_axis(int n, AxisBoundary boundary) {
  Axis a;
  a.n = n;
  a.boundary = boundary;
  a.mass.assign(n, {});
  a.stiffness.assign(n, {});
  a.derivative.assign(n, {});
  for (int i = 0; i < n; ++i) {
    for (int d = -2; d <= 2; ++d) {
      // Periodic rows keep every offset (the kernel reads the wrapped column); Neumann rows
      // move the coefficient of a ghost sample onto the sample it mirrors.
      const int to = boundary == AxisBoundary::Periodic ? d : reflect_index(i + d, n) - i;
      a.mass[i][to + 2] += kMass[d + 2];
      a.stiffness[i][to + 2] += kStiffness[d + 2];
    }
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
        a.derivative[i][e - (i - 2)] += sign * kDerivative[k];
      } else {
        a.derivative[i][k] += kDerivative[k];
      }
    }
  }
  return a;
}

int next_size(const Axis& fine) {
  const int m = (fine.n + 1) / 2;
  if (fine.boundary == AxisBoundary::Periodic) return m >= 3 ? m : fine.n;
  return m;
}

Prolongation make_prolongation(const Axis& fine, int m) {
  Prolongation p{m, std::vector<ProlongationRow>(fine.n)};
  for (int i = 0; i < fine.n; ++i) {
    if (m == fine.n) {
      p.rows[i] = {{i, i}, {1.0, 0.0}};
      continue;
    }
    const int j = i / 2;
    const int other = (i % 2 == 0) ? j - 1 : j + 1;
    const int o = fine.boundary == AxisBoundary::Periodic ? wrap_index(other, m) : reflect_index(other, m);
    p.rows[i] = {{j, o}, {0.75, 0.25}};
  }
  return p;
}

Axis coarsen(const Axis& fine, const Prolongation& p) {
  const int m = p.coarse_n;
  const double scale = m == fine.n ? fine.scale : 2.0 * fine.scale;
  if (fine.boundary == AxisBoundary::Periodic && m != fine.n && fine.n % 2 == 1) {
    Axis c = make_fine_axis(m, AxisBoundary::Periodic);
    c.derivative.clear();
    c.scale = scale;
    for (auto& row : c.mass)
      for (double& v : row) v *= scale;
    for (auto& row : c.stiffness)
      for (double& v : row) v /= scale;
    return c;
  }
  Axis c;
  c.n = m;
  c.boundary = fine.boundary;
  c.scale = scale;
  c.mass.assign(m, {});
  c.stiffness.assign(m, {});
  for (int i = 0; i < fine.n; ++i) {
    for (int d = -2; d <= 2; ++d) {
      const int k = fine.column(i, d);
      if (k < 0) continue;
      const double mass = fine.mass[i][d + 2], stiff = fine.stiffness[i][d + 2];
      if (mass == 0.0 && stiff == 0.0) continue;
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
          const int row = p.rows[i].index[a], col = p.rows[k].index[b];
          const double w = p.rows[i].weight[a] * p.rows[k].weight[b];
          if (w == 0.0) continue;
          const int off = offset_of(c, row, col) + 2;
          c.mass[row][off] += w * mass;
          c.stiffness[row][off] += w * stiff;
        }
      }
    }
  }
  return c;
}

}  // namespace gdp::fem
