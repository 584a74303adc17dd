// Column-range kernels: residual, Gauss-Seidel in either direction, transfers on part of a row.
#include "multigrid/band_ops.h"

#include <algorithm>
#include <cmath>

namespace gdp::multigrid {
namespace {

#define GDP_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))

template <class T>
int column_of(const LevelOperator<T>& op, int i) {
  return op.periodic_x ? fem::wrap_index(i, op.width) : i;
}

// a = sum_d my[d] u_{j+d}, c = sum_d cy[d] u_{j+d} at columns [i0 - 2, i1 + 2), stored from
// s.a[0]; samples outside a non-periodic row are zero (their coefficients are zero too).
template <class T>
void combine_columns(const LevelOperator<T>& op, int j, const BandWindow<T>& w, int i0, int i1, BandScratch<T>& s) {
  const int n = op.width, lo = i0 - 2, len = i1 - i0 + 4;
  if (static_cast<int>(s.a.size()) < len) {
    s.a.resize(len);
    s.c.resize(len);
  }
  T* a = s.a.data();
  T* c = s.c.data();
  // Common case (rows inside the level, none mirrored): one fused pass over the five rows.
  const bool inside = op.periodic_x || (lo >= 0 && lo + len <= n);
  bool plain = inside;
  for (int d = 0; d < 5; ++d) plain = plain && (!w.rows[d] || op.mirror_of(j, d) == fem::Mirror::None);
  if (plain) {
    if (static_cast<int>(s.zero.size()) < len) s.zero.assign(len, T(0));
    std::array<const T*, 5> u;
    std::array<T, 5> m{}, k{};
    for (int d = 0; d < 5; ++d) {
      u[d] = w.rows[d] ? w.rows[d] + (lo - w.origin[d]) : s.zero.data();
      if (w.rows[d]) m[d] = op.my[j][d], k[d] = op.cy[j][d];
    }
#pragma GCC ivdep
    for (int x = 0; x < len; ++x) {
      a[x] = m[0] * u[0][x] + m[1] * u[1][x] + m[2] * u[2][x] + m[3] * u[3][x] + m[4] * u[4][x];
      c[x] = k[0] * u[0][x] + k[1] * u[1][x] + k[2] * u[2][x] + k[3] * u[3][x] + k[4] * u[4][x];
    }
    return;
  }
  std::fill_n(a, len, T(0));
  std::fill_n(c, len, T(0));
  for (int d = 0; d < 5; ++d) {
    if (!w.rows[d]) continue;
    const T m = op.my[j][d], k = op.cy[j][d];
    const fem::Mirror mirror = op.mirror_of(j, d);
    const T* row = w.rows[d];
    const int origin = w.origin[d];
    // Columns that exist: all on periodic rows, [0, n) otherwise.
    const int from = op.periodic_x ? lo : std::max(lo, 0), to = op.periodic_x ? lo + len : std::min(lo + len, n);
    if (mirror == fem::Mirror::None) {
#pragma GCC ivdep
      for (int i = from; i < to; ++i) {
        a[i - lo] += m * row[i - origin];
        c[i - lo] += k * row[i - origin];
      }
    } else {
      for (int i = from; i < to; ++i) {
        const T v = row[fem::mirror_column(mirror, fem::wrap_index(i, n), n) - origin];
        a[i - lo] += m * v;
        c[i - lo] += k * v;
      }
    }
  }
}

// q[i - i0] = (A u)[i] for i in [i0, i1) from the combined rows.
template <class T>
void convolve_columns(const LevelOperator<T>& op, int i0, int i1, BandScratch<T>& s) {
  const int len = i1 - i0;
  if (static_cast<int>(s.q.size()) < len) s.q.resize(len);
  const T* a = s.a.data() + 2;
  const T* c = s.c.data() + 2;
  T* q = s.q.data();
  if (i0 >= op.interior_begin && i1 <= op.interior_end) {
    const T sc = op.sx_in[0], s1c = op.sx_in[1], s2c = op.sx_in[2];
    const T mc = op.mx_in[0], m1c = op.mx_in[1], m2c = op.mx_in[2];
#pragma GCC ivdep
    for (int x = 0; x < len; ++x)
      q[x] = sc * a[x] + s1c * (a[x - 1] + a[x + 1]) + s2c * (a[x - 2] + a[x + 2]) + mc * c[x] +
             m1c * (c[x - 1] + c[x + 1]) + m2c * (c[x - 2] + c[x + 2]);
    return;
  }
  for (int x = 0; x < len; ++x) {
    const int col = column_of(op, i0 + x);
    T v = T(0);
    for (int d = 0; d < 5; ++d) v += op.sx[d][col] * a[x + d - 2] + op.mx[d][col] * c[x + d - 2];
    q[x] = v;
  }
}

// On a periodic axis: the copy J + t m of coarse column J nearest to where fine column i
// (possibly outside [0, n)) lies on the coarse axis.
int nearest_copy(int J, int i, int n, int m) {
  return J + m * static_cast<int>(std::lround((static_cast<double>(i) * m / n - J) / m));
}

}  // namespace

template <class T>
const typename BandScratch<T>::Coefficients& BandScratch<T>::coefficients(const LevelOperator<T>& op, T m0, T c0) {
  for (auto it = cached.begin(); it != cached.end(); ++it)
    if (it->op == &op && it->m0 == m0 && it->c0 == c0) return *it;
  if (cached.size() >= 8) cached.erase(cached.begin());
  Coefficients& k = cached.emplace_back();
  k.op = &op;
  k.m0 = m0;
  k.c0 = c0;
  const int n = op.width;
  k.inv.resize(n);
  for (auto& v : k.k) v.resize(n);
  for (int i = 0; i < n; ++i) {
    k.inv[i] = T(1) / (op.sx[2][i] * m0 + op.mx[2][i] * c0);
    for (int d = 0; d < 5; ++d) k.k[d][i] = (op.sx[d][i] * m0 + op.mx[d][i] * c0) * k.inv[i];
  }
  // Forward block from q: dx[q + r] = A_r + fb[q + r] dx[q - 1] + fc[q + r] dx[q - 2]; backward
  // block down from e = q + 3: dx[e - r] = A_r + bb[e - r] dx[e + 1] + bc[e - r] dx[e + 2].
  k.fb.assign(n, T(0));
  k.fc.assign(n, T(0));
  k.bb.assign(n, T(0));
  k.bc.assign(n, T(0));
  for (int q = 0; q + 4 <= n; q += 4) {
    const auto block = [&](std::vector<T>& B, std::vector<T>& C, const std::vector<T>& k1, const std::vector<T>& k2,
                           auto at) {
      B[at(0)] = -k1[at(0)];
      C[at(0)] = -k2[at(0)];
      B[at(1)] = -k1[at(1)] * B[at(0)] - k2[at(1)];
      C[at(1)] = -k1[at(1)] * C[at(0)];
      for (int r = 2; r < 4; ++r) {
        B[at(r)] = -k1[at(r)] * B[at(r - 1)] - k2[at(r)] * B[at(r - 2)];
        C[at(r)] = -k1[at(r)] * C[at(r - 1)] - k2[at(r)] * C[at(r - 2)];
      }
    };
    block(k.fb, k.fc, k.k[1], k.k[0], [q](int r) { return q + r; });
    block(k.bb, k.bc, k.k[3], k.k[4], [q](int r) { return q + 3 - r; });
  }
  return k;
}

template <class T>
GDP_KERNEL void residual_columns(const LevelOperator<T>& op, int j, const BandWindow<T>& w, const T* b, T* out,
                                 int out_origin, int i0, int i1, BandScratch<T>& s, const T* diag) {
  if (i1 <= i0) return;
  combine_columns(op, j, w, i0, i1, s);
  convolve_columns(op, i0, i1, s);
  if (!diag) {
    for (int i = i0; i < i1; ++i) out[i - out_origin] = b[i - out_origin] - s.q[i - i0];
    return;
  }
  const T pinned = static_cast<T>(LevelOperator<T>::kPinnedDiagonal), *u = w.rows[2];
  for (int i = i0; i < i1; ++i) {  // as residual_row: zero at pinned pixels
    const T d = diag[i - out_origin];
    out[i - out_origin] = d >= pinned ? T(0) : b[i - out_origin] - s.q[i - i0] - d * u[i - w.origin[2]];
  }
}

// Gauss-Seidel as a recurrence on the corrections (as relax_row): with q the operator applied
// to the current values, dx_i = (b_i - q_i - sum over already updated neighbours K dx) / K_0,
// the neighbours being the two before i (forward) or after it (backward) inside the range.
template <class T>
GDP_KERNEL void relax_columns(const LevelOperator<T>& op, int j, const BandWindow<T>& w, T* u, const T* b, int i0,
                              int i1, bool forward, BandScratch<T>& s, const T* diag) {
  if (i1 <= i0) return;
  combine_columns(op, j, w, i0, i1, s);
  convolve_columns(op, i0, i1, s);
  const int len = i1 - i0, origin = w.origin[2];
  const auto& K = s.coefficients(op, op.my[j][2], op.cy[j][2]);
  if (static_cast<int>(s.dx.size()) < len + 4) s.dx.resize(len + 4);
  T* dx = s.dx.data() + 2;
  dx[-2] = dx[-1] = dx[len] = dx[len + 1] = T(0);
  const T* q = s.q.data();
  // The right-hand side of the recurrence first (vectorised), then the recurrence alone. Within
  // [0, n) the columns are the coefficient indices themselves; periodic ranges may leave it.
  if (static_cast<int>(s.t.size()) < len) s.t.resize(len);
  T* t = s.t.data();
  const bool direct = i0 >= 0 && i1 <= op.width;
  const int shift = i0;
  if (direct) {
    const T* inv = K.inv.data() + shift;
#pragma GCC ivdep
    for (int x = 0; x < len; ++x) t[x] = (b[i0 + x - origin] - q[x]) * inv[x];
  } else {
    for (int x = 0; x < len; ++x) t[x] = (b[i0 + x - origin] - q[x]) * K.inv[column_of(op, i0 + x)];
  }
  const auto coefficient = [&](int d, int x) { return direct ? K.k[d][shift + x] : K.k[d][column_of(op, i0 + x)]; };
  if (diag) {
    // With a diagonal term D: every coefficient divided by K_0 + D instead of K_0, i.e. scaled by
    // 1 / (1 + D / K_0); sample by sample.
    T* scale = s.q.data();  // q is folded into t already
    for (int x = 0; x < len; ++x) {
      const T d_over_k0 = diag[i0 + x - origin] * K.inv[column_of(op, i0 + x)];
      scale[x] = T(1) / (T(1) + d_over_k0);
      t[x] = (t[x] - d_over_k0 * u[i0 + x - origin]) * scale[x];
    }
    T d1 = T(0), d2 = T(0);
    for (int n = 0; n < len; ++n) {
      const int x = forward ? n : len - 1 - n;
      const T r = scale[x];
      const T v = t[x] - r * (forward ? coefficient(1, x) * d1 + coefficient(0, x) * d2
                                      : coefficient(3, x) * d1 + coefficient(4, x) * d2);
      dx[x] = v;
      d2 = d1;
      d1 = v;
    }
    for (int x = 0; x < len; ++x) u[i0 + x - origin] += dx[x];
    return;
  }
  // Whole blocks [4q, 4q + 3] inside the range go four samples per step (the chain carried from
  // block to block is two multiply-adds); the ends sample by sample.
  const int first_block = direct ? (i0 + 3) / 4 * 4 : i1, last_block = direct ? i1 / 4 * 4 : i1;
  if (forward) {
    T d1 = T(0), d2 = T(0);  // dx[x - 1], dx[x - 2]
    const auto one = [&](int x) {
      const T v = t[x] - coefficient(1, x) * d1 - coefficient(0, x) * d2;
      dx[x] = v;
      d2 = d1;
      d1 = v;
    };
    int x = 0;
    for (; i0 + x < std::min(first_block, i1); ++x) one(x);
    for (; i0 + x + 4 <= last_block; x += 4) {
      const int g = i0 + x;
      const T* k1 = K.k[1].data() + g;
      const T* k2 = K.k[0].data() + g;
      const T a0 = t[x];
      const T a1 = t[x + 1] - k1[1] * a0;
      const T a2 = t[x + 2] - k1[2] * a1 - k2[2] * a0;
      const T a3 = t[x + 3] - k1[3] * a2 - k2[3] * a1;
      const T* B = K.fb.data() + g;
      const T* C = K.fc.data() + g;
      dx[x] = a0 + B[0] * d1 + C[0] * d2;
      dx[x + 1] = a1 + B[1] * d1 + C[1] * d2;
      const T n2 = a2 + B[2] * d1 + C[2] * d2, n1 = a3 + B[3] * d1 + C[3] * d2;
      dx[x + 2] = n2;
      dx[x + 3] = n1;
      d2 = n2;
      d1 = n1;
    }
    for (; x < len; ++x) one(x);
  } else {
    T d1 = T(0), d2 = T(0);  // dx[x + 1], dx[x + 2]
    const auto one = [&](int x) {
      const T v = t[x] - coefficient(3, x) * d1 - coefficient(4, x) * d2;
      dx[x] = v;
      d2 = d1;
      d1 = v;
    };
    int x = len - 1;
    for (; x >= 0 && i0 + x >= std::max(last_block, i0); --x) one(x);
    for (; x - 3 >= 0 && i0 + x - 3 >= first_block; x -= 4) {
      const int e = i0 + x;  // the block's top column (4q + 3)
      const T* k1 = K.k[3].data() + e;
      const T* k2 = K.k[4].data() + e;
      const T a0 = t[x];
      const T a1 = t[x - 1] - k1[-1] * a0;
      const T a2 = t[x - 2] - k1[-2] * a1 - k2[-2] * a0;
      const T a3 = t[x - 3] - k1[-3] * a2 - k2[-3] * a1;
      const T* B = K.bb.data() + e;
      const T* C = K.bc.data() + e;
      dx[x] = a0 + B[0] * d1 + C[0] * d2;
      dx[x - 1] = a1 + B[-1] * d1 + C[-1] * d2;
      const T n2 = a2 + B[-2] * d1 + C[-2] * d2, n1 = a3 + B[-3] * d1 + C[-3] * d2;
      dx[x - 2] = n2;
      dx[x - 3] = n1;
      d2 = n2;
      d1 = n1;
    }
    for (; x >= 0; --x) one(x);
  }
  for (int x = 0; x < len; ++x) u[i0 + x - origin] += dx[x];
}

template <class T>
GDP_KERNEL void restrict_columns(const fem::Prolongation& px, const fem::ProlongationRow& py, bool periodic,
                                 const T* fine, int fine_origin, int f0, int f1, T* coarse0, T* coarse1,
                                 std::array<int, 2> coarse_origin, int c0, int c1, BandScratch<T>& s) {
  const int n = static_cast<int>(px.rows.size()), m = px.coarse_n;
  const T w0 = static_cast<T>(py.weight[0]), w1 = static_cast<T>(py.weight[1]);
  // Coarse J collects from fine 2J - 2 .. 2J + 2 at most: walk the fine columns that can
  // reach [c0, c1) and keep the contributions that land there.
  const int lo = std::max(f0, 2 * c0 - 3), hi = std::min(f1, 2 * c1 + 3);
  std::vector<T>& tmp = s.sums;  // no allocation per call
  tmp.assign(static_cast<std::size_t>(std::max(0, c1 - c0)), T(0));
  for (int i = lo; i < hi; ++i) {
    if (!periodic && (i < 0 || i >= n)) continue;
    const fem::ProlongationRow& p = px.rows[periodic ? fem::wrap_index(i, n) : i];
    for (int a = 0; a < 2; ++a) {
      int J = p.index[a];
      if (periodic) J = nearest_copy(J, i, n, m);
      if (J >= c0 && J < c1) tmp[J - c0] += static_cast<T>(p.weight[a]) * fine[i - fine_origin];
    }
  }
  for (int J = c0; J < c1; ++J) coarse0[J - coarse_origin[0]] += w0 * tmp[J - c0];
  if (w1 == T(0)) return;
  for (int J = c0; J < c1; ++J) {
    const int to = py.mirror == fem::Mirror::None ? J
                                                  : fem::mirror_column(py.mirror, periodic ? fem::wrap_index(J, m) : J, m);
    coarse1[to - coarse_origin[1]] += w1 * tmp[J - c0];
  }
}

template <class T>
GDP_KERNEL void prolong_columns(const fem::Prolongation& px, const fem::ProlongationRow& py, bool periodic,
                                const T* coarse0, const T* coarse1, std::array<int, 2> coarse_origin,
                                bool coarse_whole, T* fine, int fine_origin, int f0, int f1) {
  const int n = static_cast<int>(px.rows.size()), m = px.coarse_n;
  const T w0 = static_cast<T>(py.weight[0]), w1 = static_cast<T>(py.weight[1]);
  const auto coarse = [&](int J) {  // the y-interpolated coarse sample J (any representative)
    const T v0 = coarse0[J - coarse_origin[0]];
    int J1 = J;
    if (py.mirror != fem::Mirror::None) J1 = fem::mirror_column(py.mirror, periodic ? fem::wrap_index(J, m) : J, m);
    return w0 * v0 + w1 * coarse1[J1 - coarse_origin[1]];
  };
  for (int i = f0; i < f1; ++i) {
    if (!periodic && (i < 0 || i >= n)) continue;
    const fem::ProlongationRow& p = px.rows[periodic ? fem::wrap_index(i, n) : i];
    T v = T(0);
    for (int a = 0; a < 2; ++a) {
      int J = p.index[a];
      if (periodic && !coarse_whole) J = nearest_copy(J, i, n, m);
      v += static_cast<T>(p.weight[a]) * coarse(J);
    }
    fine[i - fine_origin] += v;
  }
}

#define GDP_INSTANTIATE(T)                                                                                 \
  template struct BandScratch<T>;                                                                          \
  template void residual_columns(const LevelOperator<T>&, int, const BandWindow<T>&, const T*, T*, int, int, \
                                 int, BandScratch<T>&, const T*);                                          \
  template void relax_columns(const LevelOperator<T>&, int, const BandWindow<T>&, T*, const T*, int, int,  \
                              bool, BandScratch<T>&, const T*);                                            \
  template void restrict_columns(const fem::Prolongation&, const fem::ProlongationRow&, bool, const T*, int, \
                                 int, int, T*, T*, std::array<int, 2>, int, int, BandScratch<T>&);                                         \
  template void prolong_columns(const fem::Prolongation&, const fem::ProlongationRow&, bool, const T*,     \
                                const T*, std::array<int, 2>, bool, T*, int, int, int);
GDP_INSTANTIATE(float)
GDP_INSTANTIATE(double)
#undef GDP_INSTANTIATE
#undef GDP_KERNEL

}  // namespace gdp::multigrid
