// Row kernels: operator application, residual, Gauss-Seidel relaxation, transfers.
#include "multigrid/row_ops.h"

#include <algorithm>

namespace gdp::multigrid {
namespace {

// Each kernel is compiled twice, for x86-64-v3 (AVX2 + FMA) and for the baseline, and the
// loader picks one for the running CPU: a portable binary that still uses FMA where present
// (the Gauss-Seidel recurrence is latency-bound, and FMA shortens its chain).
#define GDP_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))

// a = sum_d my[d] u_{j+d}, c = sum_d cy[d] u_{j+d} over the window, with ghost samples
// (two each side) wrapped for periodic rows and zero otherwise (their coefficients are 0).
template <class T>
void combine_rows(const LevelOperator<T>& op, int j, const RowWindow<T>& rows, RowScratch<T>& s) {
  const int n = op.width;
  T* a = s.a.data() + 2;
  T* c = s.c.data() + 2;
  std::array<const T*, 5> u;
  std::array<T, 5> m{}, k{};
  for (int d = 0; d < 5; ++d) {
    u[d] = rows[d] ? rows[d] : s.zero.data();  // unused rows have zero coefficients
    if (rows[d]) m[d] = op.my[j][d], k[d] = op.cy[j][d];
    const fem::Mirror mirror = op.mirror_of(j, d);
    if (rows[d] && mirror != fem::Mirror::None) {
      // A row across a spherical domain's top or bottom edge: a mirrored copy of the row as it
      // is now (for the row being relaxed: its values before this sweep).
      std::vector<T>& copy = s.mirrored[d];
      copy.resize(n);
      for (int i = 0; i < n; ++i) copy[i] = rows[d][fem::mirror_column(mirror, i, n)];
      u[d] = copy.data();
    }
  }
  if (m[0] == m[4] && m[1] == m[3] && k[0] == k[4] && k[1] == k[3]) {
    // Interior rows: symmetric coefficients, pairs of rows added before multiplying.
#pragma GCC ivdep
    for (int i = 0; i < n; ++i) {
      const T p1 = u[1][i] + u[3][i], p2 = u[0][i] + u[4][i];
      a[i] = m[2] * u[2][i] + m[1] * p1 + m[0] * p2;
      c[i] = k[2] * u[2][i] + k[1] * p1 + k[0] * p2;
    }
  } else {
#pragma GCC ivdep
    for (int i = 0; i < n; ++i) {
      a[i] = m[0] * u[0][i] + m[1] * u[1][i] + m[2] * u[2][i] + m[3] * u[3][i] + m[4] * u[4][i];
      c[i] = k[0] * u[0][i] + k[1] * u[1][i] + k[2] * u[2][i] + k[3] * u[3][i] + k[4] * u[4][i];
    }
  }
  for (int g = 1; g <= 2; ++g) {
    a[-g] = c[-g] = a[n - 1 + g] = c[n - 1 + g] = T(0);
    if (op.periodic_x) {
      a[-g] = a[fem::wrap_index(-g, n)];
      c[-g] = c[fem::wrap_index(-g, n)];
      a[n - 1 + g] = a[fem::wrap_index(n - 1 + g, n)];
      c[n - 1 + g] = c[fem::wrap_index(n - 1 + g, n)];
    }
  }
}

// q = sum_d sx[d] a_{i+d} + mx[d] c_{i+d}: the operator applied to the window's row j.
template <class T>
void convolve(const LevelOperator<T>& op, RowScratch<T>& s, T* q) {
  const int n = op.width;
  const T* a = s.a.data() + 2;
  const T* c = s.c.data() + 2;
  const T *s0 = op.sx[0].data(), *s1 = op.sx[1].data(), *s2 = op.sx[2].data(),
          *s3 = op.sx[3].data(), *s4 = op.sx[4].data();
  const T *m0 = op.mx[0].data(), *m1 = op.mx[1].data(), *m2 = op.mx[2].data(),
          *m3 = op.mx[3].data(), *m4 = op.mx[4].data();
  // General columns (near the ends): per-column coefficients.
  const auto general = [&](int from, int to) {
    // The 20 input streams never alias q; without this GCC gives up on vectorising.
#pragma GCC ivdep
    for (int i = from; i < to; ++i) {
      q[i] = s0[i] * a[i - 2] + s1[i] * a[i - 1] + s2[i] * a[i] + s3[i] * a[i + 1] + s4[i] * a[i + 2] +
             m0[i] * c[i - 2] + m1[i] * c[i - 1] + m2[i] * c[i] + m3[i] * c[i + 1] + m4[i] * c[i + 2];
    }
  };
  const int ib = op.interior_begin, ie = op.interior_end;
  general(0, ib);
  // Interior: one symmetric stencil, pairs of neighbours added before multiplying.
  const T sc = op.sx_in[0], s1c = op.sx_in[1], s2c = op.sx_in[2];
  const T mc = op.mx_in[0], m1c = op.mx_in[1], m2c = op.mx_in[2];
#pragma GCC ivdep
  for (int i = ib; i < ie; ++i) {
    q[i] = sc * a[i] + s1c * (a[i - 1] + a[i + 1]) + s2c * (a[i - 2] + a[i + 2]) + mc * c[i] +
           m1c * (c[i - 1] + c[i + 1]) + m2c * (c[i - 2] + c[i + 2]);
  }
  general(ie, n);
}

}  // namespace

template <class T>
void RowScratch<T>::resize(int width) {
  a.assign(width + 4, T(0));
  c.assign(width + 4, T(0));
  zero.assign(width, T(0));
  inv.assign(width, T(0));
  block_b.assign(width, T(0));
  block_c.assign(width, T(0));
  coefficients_op = nullptr;
  q.assign(width, T(0));
  k1.assign(width, T(0));
  k2.assign(width, T(0));
  dx.assign(width + 2, T(0));
}

template <class T>
GDP_KERNEL void apply_row(const LevelOperator<T>& op, int j, const RowWindow<T>& rows, T* out, RowScratch<T>& s,
                          const T* diag) {
  combine_rows(op, j, rows, s);
  convolve(op, s, out);
  if (diag)
    for (int i = 0; i < op.width; ++i) out[i] += diag[i] * rows[2][i];
}

template <class T>
GDP_KERNEL void residual_row(const LevelOperator<T>& op, int j, const RowWindow<T>& rows, const T* b, T* r,
                             RowScratch<T>& s, const T* diag) {
  combine_rows(op, j, rows, s);
  convolve(op, s, s.q.data());
  if (diag) {
    // A pinned pixel's equation is u = value: it holds after relaxation (to ~1e-6), and what
    // b - A u - D u computes there is float round-off of D * value (b) against D * u, noise that
    // would swamp the residual norms: it is taken as zero.
    const T pinned = static_cast<T>(LevelOperator<T>::kPinnedDiagonal);
    for (int i = 0; i < op.width; ++i) r[i] = diag[i] >= pinned ? T(0) : b[i] - s.q[i] - diag[i] * rows[2][i];
  } else {
    for (int i = 0; i < op.width; ++i) r[i] = b[i] - s.q[i];
  }
}

// Gauss-Seidel along the row as a recurrence on the corrections: with q the operator applied
// to the old values, the update of sample i is
//   dx_i = (b_i - q_i - K_{-1}(i) dx_{i-1} - K_{-2}(i) dx_{i-2}) / K_0(i),
// K_d(i) being the in-row coupling sx[d] my0 + mx[d] cy0. All but the recurrence vectorises.
template <class T>
GDP_KERNEL void relax_row(const LevelOperator<T>& op, int j, const RowWindow<T>& rows, T* u, const T* b,
                          RowScratch<T>& s, const T* diag) {
  const int n = op.width;
  combine_rows(op, j, rows, s);
  T* q = s.q.data();
  convolve(op, s, q);
  const T m0 = op.my[j][2], c0 = op.cy[j][2];
  T* k1 = s.k1.data();
  T* k2 = s.k2.data();
  T* inv = s.inv.data();
  if (diag || s.coefficients_for != std::make_pair(m0, c0) || s.coefficients_op != &op) {
    // Interior rows share (m0, c0): the reciprocal diagonal is computed once for them all
    // (per row when a per-pixel diagonal term is added).
    for (int i = 0; i < n; ++i) {
      inv[i] = T(1) / (op.sx[2][i] * m0 + op.mx[2][i] * c0 + (diag ? diag[i] : T(0)));
      k1[i] = (op.sx[1][i] * m0 + op.mx[1][i] * c0) * inv[i];
      k2[i] = (op.sx[0][i] * m0 + op.mx[0][i] * c0) * inv[i];
    }
    // Blocks of four samples starting at multiples of 4: dx[i0 + r] = A_r + B_r dx[i0 - 1] +
    // C_r dx[i0 - 2], with B and C from the coefficients alone (A is the recurrence on q
    // started from zero inside the block, formed per row).
    T* bb = s.block_b.data();
    T* cc = s.block_c.data();
    for (int i0 = 0; i0 + 4 <= n; i0 += 4) {
      bb[i0] = -k1[i0];
      cc[i0] = -k2[i0];
      bb[i0 + 1] = -k1[i0 + 1] * bb[i0] - k2[i0 + 1];
      cc[i0 + 1] = -k1[i0 + 1] * cc[i0];
      for (int r = 2; r < 4; ++r) {
        bb[i0 + r] = -k1[i0 + r] * bb[i0 + r - 1] - k2[i0 + r] * bb[i0 + r - 2];
        cc[i0 + r] = -k1[i0 + r] * cc[i0 + r - 1] - k2[i0 + r] * cc[i0 + r - 2];
      }
    }
    s.coefficients_for = {m0, c0};
    s.coefficients_op = diag ? nullptr : &op;
  }
  if (diag) {
    for (int i = 0; i < n; ++i) q[i] = (b[i] - q[i] - diag[i] * u[i]) * inv[i];
  } else {
    for (int i = 0; i < n; ++i) q[i] = (b[i] - q[i]) * inv[i];
  }
  T* dx = s.dx.data() + 2;  // dx[-2], dx[-1] are zero: wrapped columns are not yet updated
  dx[-2] = dx[-1] = T(0);
  const int last = op.periodic_x ? n - 2 : n;
  // Four samples per step: the only chain carried from block to block is two multiply-adds
  // (the recurrence is latency-bound otherwise); the in-block terms overlap across blocks.
  const T* bb = s.block_b.data();
  const T* cc = s.block_c.data();
  T d2 = T(0), d1 = T(0);
  int i = 0;
  for (; i + 4 <= last; i += 4) {
    const T a0 = q[i];
    const T a1 = q[i + 1] - k1[i + 1] * a0;
    const T a2 = q[i + 2] - k1[i + 2] * a1 - k2[i + 2] * a0;
    const T a3 = q[i + 3] - k1[i + 3] * a2 - k2[i + 3] * a1;
    dx[i] = a0 + bb[i] * d1 + cc[i] * d2;
    dx[i + 1] = a1 + bb[i + 1] * d1 + cc[i + 1] * d2;
    const T n2 = a2 + bb[i + 2] * d1 + cc[i + 2] * d2;
    const T n1 = a3 + bb[i + 3] * d1 + cc[i + 3] * d2;
    dx[i + 2] = n2;
    dx[i + 3] = n1;
    d2 = n2;
    d1 = n1;
  }
  for (; i < last; ++i) {
    const T t = q[i] - k2[i] * d2;
    d2 = d1;
    d1 = t - k1[i] * d1;
    dx[i] = d1;
  }
  // Periodic rows: the last two samples also see the first two, already updated.
  for (int i = std::max(last, 0); i < n; ++i) {
    T v = q[i] - k1[i] * dx[i - 1] - k2[i] * dx[i - 2];
    for (int d = n - i; d <= 2; ++d) {
      const int col = fem::wrap_index(i + d, n);
      if (col < i) v -= (op.sx[d + 2][i] * m0 + op.mx[d + 2][i] * c0) * inv[i] * dx[col];
    }
    dx[i] = v;
  }
  for (int i = 0; i < n; ++i) u[i] += dx[i];
}

template <class T>
GDP_KERNEL void restrict_row(const fem::Prolongation& px, const fem::ProlongationRow& pyj, const T* fine,
                  T* coarse0, T* coarse1, T* tmp) {
  const int n = static_cast<int>(px.rows.size()), m = px.coarse_n;
  if (m == n) {
    std::copy(fine, fine + n, tmp);
  } else {
    // Coarse samples 1..m-2 take the plain two-scale weights from fine 2J-1..2J+2 (a gather
    // that vectorises); only samples 0 and m-1 see reflected or wrapped fine samples, and
    // those come only from the first and last three fine samples.
    for (int J = 1; J + 1 < m; ++J)
      tmp[J] = T(0.25) * (fine[2 * J - 1] + fine[2 * J + 2]) + T(0.75) * (fine[2 * J] + fine[2 * J + 1]);
    tmp[0] = tmp[m - 1] = T(0);
    const auto edge = [&](int i) {
      const fem::ProlongationRow& p = px.rows[i];
      for (int a = 0; a < 2; ++a)
        if (p.index[a] == 0 || p.index[a] == m - 1) tmp[p.index[a]] += static_cast<T>(p.weight[a]) * fine[i];
    };
    for (int i = 0; i < std::min(3, n); ++i) edge(i);
    for (int i = std::max(3, n - 3); i < n; ++i) edge(i);
  }
  const T w0 = static_cast<T>(pyj.weight[0]), w1 = static_cast<T>(pyj.weight[1]);
  for (int i = 0; i < m; ++i) coarse0[i] += w0 * tmp[i];
  if (w1 == T(0)) return;
  if (pyj.mirror == fem::Mirror::None) {
    for (int i = 0; i < m; ++i) coarse1[i] += w1 * tmp[i];
  } else {
    for (int i = 0; i < m; ++i) coarse1[fem::mirror_column(pyj.mirror, i, m)] += w1 * tmp[i];
  }
}

template <class T>
GDP_KERNEL void prolong_row(const fem::Prolongation& px, const fem::ProlongationRow& pyj, const T* coarse0,
                 const T* coarse1, T* fine, T* tmp) {
  const int n = static_cast<int>(px.rows.size()), m = px.coarse_n;
  const T w0 = static_cast<T>(pyj.weight[0]), w1 = static_cast<T>(pyj.weight[1]);
  if (pyj.mirror == fem::Mirror::None) {
    for (int i = 0; i < m; ++i) tmp[i] = w0 * coarse0[i] + w1 * coarse1[i];
  } else {
    for (int i = 0; i < m; ++i) tmp[i] = w0 * coarse0[i] + w1 * coarse1[fem::mirror_column(pyj.mirror, i, m)];
  }
  for (int i = 0; i < n; ++i) {
    const fem::ProlongationRow& p = px.rows[i];
    fine[i] += static_cast<T>(p.weight[0]) * tmp[p.index[0]] + static_cast<T>(p.weight[1]) * tmp[p.index[1]];
  }
}

#define GDP_INSTANTIATE(T)                                                                        \
  template struct RowScratch<T>;                                                                  \
  template void apply_row(const LevelOperator<T>&, int, const RowWindow<T>&, T*, RowScratch<T>&, \
                          const T*);                                                              \
  template void residual_row(const LevelOperator<T>&, int, const RowWindow<T>&, const T*, T*,     \
                             RowScratch<T>&, const T*);                                           \
  template void relax_row(const LevelOperator<T>&, int, const RowWindow<T>&, T*, const T*,        \
                          RowScratch<T>&, const T*);                                              \
  template void restrict_row(const fem::Prolongation&, const fem::ProlongationRow&, const T*, T*, \
                             T*, T*);                                                             \
  template void prolong_row(const fem::Prolongation&, const fem::ProlongationRow&, const T*,      \
                            const T*, T*, T*);
GDP_INSTANTIATE(float)
GDP_INSTANTIATE(double)
#undef GDP_INSTANTIATE
#undef GDP_KERNEL

}  // namespace gdp::multigrid
