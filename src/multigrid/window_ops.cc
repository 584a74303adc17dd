// Window kernels: edges decided once per call, the edge/interior split inside, transfers as gathers.
#include "multigrid/window_ops.h"
#include "util/clones.h"

#include <algorithm>
#include <cstring>

namespace gdp::multigrid {
namespace {

// Each kernel is compiled for x86-64-v3 (AVX2 + FMA) and the baseline, the loader picking one;
// the helpers are forced inline, or their loops would be compiled for the baseline only.
#define GDP_INLINE __attribute__((always_inline)) inline

GDP_INLINE int floor_div(int a, int n) { return a >= 0 ? a / n : -((n - 1 - a) / n); }

// A run of columns [x, end) read linearly: column i reads column i - base of a table (one
// periodic copy) or column base - i of a row mirrored across a fold.
struct Run { int end, base; };

GDP_INLINE Run copy_run(int n, bool periodic, int x, int hi) {
  const int k = periodic ? floor_div(x, n) : 0;
  return {periodic ? std::min(hi, (k + 1) * n) : hi, k * n};
}

// fem::mirror_column of the wrapped column, run by run.
GDP_INLINE Run mirror_run(fem::Mirror m, int n, int x, int hi) {
  const int k = floor_div(x, n), h = n / 2;
  if (m == fem::Mirror::Top) return {std::min(hi, (k + 1) * n), n - 1 + k * n};
  if (x - k * n < h) return {std::min(hi, k * n + h), h - 1 + k * n};
  return {std::min(hi, (k + 1) * n), h - 1 + k * n + n};
}

template <class T>
GDP_INLINE T* grow(std::vector<T>& v, int n) {
  if (static_cast<int>(v.size()) < n) v.resize(n);
  return v.data();
}

// a = sum_d my[d] u_{j+d}, c = sum_d cy[d] u_{j+d} at columns [begin - 2, end + 2), from s.a[0]:
// from the rows where they hold the columns, zero beyond a non-periodic level, wrapped for Wrap.
// Both as (sum_d my[d]) u_j + sum_d my[d] (u_{j+d} - u_j): the stiffness's rows sum to zero, so c is
// rounded like the differences, not like u (docs/multigrid.md, "Differences").
template <class T>
GDP_INLINE void combine(const LevelOperator<T>& op, int j, const Window<T>& w, const Columns& cols, Scratch<T>& s) {
  const int n = op.width, lo = cols.begin - 2, len = cols.end - cols.begin + 4;
  const bool clip = cols.wrap || !cols.periodic;
  const int from = clip ? std::max(lo, 0) : lo, to = clip ? std::min(lo + len, n) : lo + len;
  const int count = std::max(to - from, 0);
  T *a = grow(s.a, len), *c = grow(s.c, len);
  std::array<const T*, 5> u;
  std::array<T, 5> m{}, k{};
  const std::array<T, 5> &my = op.my[j], &cy = op.cy[j];  // row tables: one lookup each, not one per row
  const std::array<fem::Mirror, 5>& mirrors = op.mirrors(j);
  for (int d = 0; d < 5; ++d) {
    const T* row = w.rows[d];  // unused rows (null) have zero coefficients: any (finite) row will do
    u[d] = row ? row + (from - w.origin[d]) : w.rows[2] + (from - w.origin[2]);
    if (row) m[d] = my[d], k[d] = cy[d];
    const fem::Mirror mirror = row ? mirrors[d] : fem::Mirror::None;
    if (mirror == fem::Mirror::None) continue;
    // Across a spherical fold: a mirrored copy as it is now (row j: as before this sweep).
    T* copy = grow(s.mirrored[d], count);
    for (int x = from; x < to;) {
      const Run r = mirror_run(mirror, n, x, to);
      for (; x < r.end; ++x) copy[x - from] = row[r.base - x - w.origin[d]];
    }
    u[d] = copy;
  }
  T* A = a + (from - lo);
  T* C = c + (from - lo);
  const T ms = m[0] + m[1] + m[2] + m[3] + m[4], ks = k[0] + k[1] + k[2] + k[3] + k[4];  // ks = 0 unless alpha > 0
#pragma GCC ivdep
  for (int i = 0; i < count; ++i) {
    const T v = u[2][i], d0 = u[0][i] - v, d1 = u[1][i] - v, d3 = u[3][i] - v, d4 = u[4][i] - v;
    A[i] = ms * v + m[0] * d0 + m[1] * d1 + m[3] * d3 + m[4] * d4;
    C[i] = ks * v + k[0] * d0 + k[1] * d1 + k[3] * d3 + k[4] * d4;
  }
  std::fill(a, A, T(0)), std::fill(c, C, T(0));
  std::fill(A + count, a + len, T(0)), std::fill(C + count, c + len, T(0));
  if (cols.wrap)  // the ghost samples of a whole periodic row (a[2] is column 0)
    for (T* v : {a, c})
      for (int g : {0, 1, n + 2, n + 3}) v[g] = v[2 + fem::wrap_index(g - 2, n)];
}

// What convolve writes per column: A u, the residual b - A u, or relax's t = (b - A u) / K_0 (on the level's
// interior, 1 / K_0 given; b - A u by its ends, which relax scales itself).
enum class Out { Au, Residual, Correction };

// q[x] for column begin + x from the combined rows: per-column coefficients by the level's ends, the
// interior's one symmetric stencil (pairs of neighbours added before multiplying) elsewhere. b[i] is column
// i's b, `in` the interior's 1 / K_0. The stiffness sx acts on differences a_{x+d} - a_x (its rows sum to
// exactly zero: hierarchy.h), as combine does for c.
template <Out O, class T>
GDP_INLINE void convolve(const LevelOperator<T>& op, const Columns& cols, const Scratch<T>& s, T* q,
                         const T* b = nullptr, T in = T(1)) {
  const T* a = s.a.data() + 2 - cols.begin;  // a[i]: column i
  const T* c = s.c.data() + 2 - cols.begin;
  q -= cols.begin;
  // Columns [from, to) with the coefficients of table columns from - base ..: a plain loop (vectorised, it spent
  // a short tile's time in its epilogue; these are a few columns).
  const auto general = [&](int from, int to, int base) __attribute__((always_inline)) {
    for (int x = from; x < to; ++x) {
      T v = T(0);  // (the stiffness's d = 2 term is zero)
      for (int d = 0; d < 5; ++d) v += op.mx[d][x - base] * c[x + d - 2] + op.sx[d][x - base] * (a[x + d - 2] - a[x]);
      q[x] = O == Out::Au ? v : b[x] - v;
    }
  };
  const T s1c = op.sx_in[1], s2c = op.sx_in[2], mc = op.mx_in[0], m1c = op.mx_in[1], m2c = op.mx_in[2];
  for (int i = cols.begin; i < cols.end;) {  // run by run (one per periodic copy), each cut at the interior
    const Run r = copy_run(op.width, cols.periodic, i, cols.end);
    const int ib = std::clamp(op.interior_begin + r.base, i, r.end);
    const int ie = std::clamp(op.interior_end + r.base, ib, r.end);
    general(i, ib, r.base);
#pragma GCC ivdep
    for (int x = ib; x < ie; ++x) {
      const T v = s1c * ((a[x - 1] - a[x]) + (a[x + 1] - a[x])) + s2c * ((a[x - 2] - a[x]) + (a[x + 2] - a[x])) +
                  mc * c[x] + m1c * (c[x - 1] + c[x + 1]) + m2c * (c[x - 2] + c[x + 2]);
      q[x] = O == Out::Au ? v : O == Out::Residual ? b[x] - v : (b[x] - v) * in;
    }
    general(ie, r.end, r.base);
    i = r.end;
  }
}

// Relax's terms at table column g (d: the per-pixel diagonal term there): kn = K_{-1} / K_0, kf = K_{-2} / K_0
// (backward: K_1, K_2) and 1 / K_0, K_d = sx[d] my0 + mx[d] cy0 (+ d on the diagonal).
template <class T>
struct Term { T kn, kf, inv; };

template <class T>
GDP_INLINE Term<T> term(const LevelOperator<T>& op, T m0, T c0, bool fwd, int g, T d) {
  const int near = fwd ? 1 : 3, far = fwd ? 0 : 4;
  const T inv = T(1) / (op.sx[2][g] * m0 + op.mx[2][g] * c0 + d);
  return {(op.sx[near][g] * m0 + op.mx[near][g] * c0) * inv, (op.sx[far][g] * m0 + op.mx[far][g] * c0) * inv, inv};
}

// dx_r = t_r - kn_r dx_{r-1} - kf_r dx_{r-2} (r in the sweep's order) on a block of eight is dx = H t + B d1 + C d2
// (d1, d2: the corrections before it), H = L^-1, L[r][r-1] = kn_r, L[r][r-2] = kf_r, L[r][r] = 1. From H L = I,
// last column first: H_r = e_r - kn_{r+1} H_{r+1} - kf_{r+2} H_{r+2}; B = -kn_0 H_0 - kf_1 H_1, C = -kf_0 H_0.
// Into H[0..7] by memory lane (backward sweeps run from lane 7 down), H[8] = B, H[9] = C; k(p): lane p's terms.
template <bool fwd, class V, class K>
GDP_INLINE void block(const K& k, V* H) {
  const auto lane = [](int r) { return fwd ? r : 7 - r; };
  V h1{}, h2{};
  for (int r = 7; r >= 0; --r) {
    V h{};
    h[lane(r)] = 1;
    if (r < 7) h -= k(lane(r + 1)).kn * h1;
    if (r < 6) h -= k(lane(r + 2)).kf * h2;
    H[lane(r)] = h, h2 = h1, h1 = h;
  }
  H[8] = -k(lane(0)).kn * H[lane(0)] - k(lane(1)).kf * H[lane(1)];
  H[9] = -k(lane(0)).kf * H[lane(0)];
}

// The recurrence over t[0, count) in the sweep's direction, d1, d2 carried in and out, each dx[x] added to out[x]:
// blocks of eight from the sweep's start, H built per block from the tables kn, kf, but once for [v0, v1) (whole
// blocks with the interior's terms c), then the last count % 8 samples one by one. The chain from block to block
// is two scalar multiply-adds, everything else vectors (docs/multigrid.md, "One recurrence").
template <bool fwd, class T>
GDP_INLINE void recur(const T* t, int count, const T* kn, const T* kf, int v0, int v1, Term<T> c, T* out, T& d1,
                      T& d2) {
  typedef T V __attribute__((vector_size(8 * sizeof(T))));  // eight lanes
  constexpr int last = fwd ? 7 : 0, before = fwd ? 6 : 1;  // the lanes carried to the next block
  const int blocks = count / 8, n0 = std::min((fwd ? v0 : count - v1) / 8, blocks);
  const int n1 = std::clamp((fwd ? v1 : count - v0) / 8, n0, blocks);
  V Hc[10], Hb[10];
  if (n1 > n0) block<fwd>([&](int) { return c; }, Hc);
  const auto run = [&](int from, int to, bool constant) __attribute__((always_inline)) {
    for (int n = from; n < to; ++n) {
      const int x = fwd ? 8 * n : count - 8 * (n + 1);
      if (!constant) block<fwd>([&](int p) { return Term<T>{kn[x + p], kf[x + p], T(0)}; }, Hb);
      const V* H = constant ? Hc : Hb;
      V A = H[0] * t[x];
      for (int k = 1; k < 8; ++k) A += H[k] * t[x + k];
      const T e1 = A[last] + H[8][last] * d1 + H[9][last] * d2, e2 = A[before] + H[8][before] * d1 + H[9][before] * d2;
      V o;
      std::memcpy(&o, out + x, sizeof(V));
      o += A + H[8] * d1 + H[9] * d2;
      std::memcpy(out + x, &o, sizeof(V));
      d1 = e1, d2 = e2;
    }
  };
  run(0, n0, false), run(n0, n1, true), run(n1, blocks, false);
  for (int n = 8 * blocks; n < count; ++n) {
    const int x = fwd ? n : count - 1 - n;
    const T v = t[x] - kf[x] * d2;
    d2 = d1, d1 = v - kn[x] * d1;
    out[x] += d1;
  }
}

}  // namespace

template <class T>
GDP_CLONES void apply(const LevelOperator<T>& op, int j, const Window<T>& w, Columns cols, T* out, Scratch<T>& s,
                      const T* diag) {
  if (cols.end <= cols.begin) return;
  const int o = cols.begin - w.origin[2];
  combine(op, j, w, cols, s);
  convolve<Out::Au>(op, cols, s, out + o);
  if (diag)
    for (int x = o; x < o + cols.end - cols.begin; ++x) out[x] += diag[x] * w.rows[2][x];
}

template <class T>
GDP_CLONES void residual(const LevelOperator<T>& op, int j, const Window<T>& w, Columns cols, const T* b, T* r,
                         Scratch<T>& s, const T* diag) {
  const int len = cols.end - cols.begin, o = cols.begin - w.origin[2];
  if (len <= 0) return;
  combine(op, j, w, cols, s);
  convolve<Out::Residual>(op, cols, s, r + o, b + o - cols.begin);
  if (!diag) return;
  // Pinned pixels hold u = value (to ~1e-6); b - A u - D u there is round-off that would swamp the norms: 0.
  const T pinned = static_cast<T>(LevelOperator<T>::kPinnedDiagonal), *u = w.rows[2];
  for (int i = o; i < o + len; ++i) r[i] = diag[i] >= pinned ? T(0) : r[i] - diag[i] * u[i];
}

// Gauss-Seidel as a recurrence on the corrections: with q = A u before the sweep, dx_i = (b_i - q_i
// - K_{-1}(i) dx_{i-1} - K_{-2}(i) dx_{i-2}) / K_0(i) (backward: K_1, K_2), K_d = sx[d] my0 + mx[d] cy0.
// Corrections beyond the columns are zero, but a whole periodic row's ends see each other.
template <class T>
GDP_CLONES void relax(const LevelOperator<T>& op, int j, const Window<T>& w, Columns cols, T* u, const T* b,
                      Scratch<T>& s, const T* diag) {
  const int len = cols.end - cols.begin, o = cols.begin - w.origin[2];
  if (len <= 0) return;
  const T m0 = op.my[j][2], c0 = op.cy[j][2];
  const bool wrap = cols.wrap, fwd = cols.forward || wrap, inside = !diag && op.interior_begin < op.interior_end;
  const Term<T> c = inside ? term(op, m0, c0, fwd, op.interior_begin, T(0)) : Term<T>{};
  T *q = grow(s.q, len), *kn = grow(s.kn, len), *kf = grow(s.kf, len);
  combine(op, j, w, cols, s);  // t = (b - A u) / K_0 on the interior, b - A u elsewhere (scaled per run below)
  if (inside) convolve<Out::Correction>(op, cols, s, q, b + o - cols.begin, c.inv);
  else convolve<Out::Residual>(op, cols, s, q, b + o - cols.begin);
  T d1 = T(0), d2 = T(0);
  for (int done = 0; done < len;) {  // run by run (one per periodic copy) in the sweep's order: [x0, x1)
    const Run r = copy_run(op.width, cols.periodic, cols.begin + (fwd ? done : len - 1 - done), cols.end);
    const int x0 = fwd ? done : std::max(r.base, cols.begin) - cols.begin, x1 = fwd ? r.end - cols.begin : len - done;
    const int count = x1 - x0, g0 = cols.begin + x0 - r.base;  // g0: x0's table column
    const int ib = inside ? std::clamp(op.interior_begin - g0, 0, count) : 0;
    const int ie = inside ? std::clamp(op.interior_end - g0, ib, count) : 0;
    const int e = fwd ? 0 : count % 8;  // blocks start at e + 8k; [v0, v1): those in the interior
    const int v0 = std::min(count, e - 8 * floor_div(e - ib, 8)), v1 = std::max(v0, e + 8 * floor_div(ie - e, 8));
    const auto scale = [&](int from, int to) __attribute__((always_inline)) {  // tables; t = (b - A u - D u) / K_0
#pragma GCC ivdep
      for (int x = x0 + from; x < x0 + to; ++x) {
        const T d = diag ? diag[o + x] : T(0);
        const bool in = x - x0 >= ib && x - x0 < ie;  // the interior's: c's terms, q is t already
        const Term<T> k = in ? c : term(op, m0, c0, fwd, g0 - x0 + x, d);
        kn[x] = k.kn, kf[x] = k.kf;
        if (!in) q[x] = (q[x] - d * u[o + x]) * k.inv;
      }
    };
    scale(0, v0), scale(v1, count);
    // A whole periodic row: its last two samples see the first two, updated (dx_0 = t_0, dx_1 = t_1 - kn_1 t_0).
    for (int i = wrap ? std::max(len - 2, 0) : len; i < len; ++i) {
      const Term<T> k = term(op, m0, c0, false, i, diag ? diag[o + i] : T(0));  // K_1 / K_0, K_2 / K_0
      for (int d = 1, col = i + 1 - len; d <= 2; ++d, ++col)
        if (col >= 0 && col < i) q[i] -= (d == 1 ? k.kn : k.kf) * (col ? q[1] - kn[1] * q[0] : q[0]);
    }
    if (fwd) recur<true>(q + x0, count, kn + x0, kf + x0, v0, v1, c, u + o + x0, d1, d2);
    else recur<false>(q + x0, count, kn + x0, kf + x0, v0, v1, c, u + o + x0, d1, d2);
    done += count;
  }
}

// Coarse J = 1 .. m-2 gather the two-scale weights from fine 2J-1 .. 2J+2; only J = 0 and m-1 see reflected or
// wrapped fine samples, only the first and last three, read at the copy nearest to J (Halo) or in the row.
template <class T>
GDP_CLONES void restrict_rows(const fem::Prolongation& px, const fem::ProlongationRow& py, const T* fine,
                              int fine_origin, Columns cols, T* coarse0, T* coarse1, std::array<int, 2> origin,
                              Scratch<T>& s) {
  const int n = static_cast<int>(px.rows.size()), m = px.coarse_n, len = cols.end - cols.begin;
  if (len <= 0) return;
  T* tmp = grow(s.line, len) - cols.begin;  // tmp[J]
  const bool unwrap = cols.periodic && !cols.wrap;
  for (int J = cols.begin; J < cols.end;) {
    const Run r = copy_run(m, cols.periodic, J, cols.end);
    const int k = r.base / std::max(m, 1), off = k * n - fine_origin;  // fine[off + i]: copy k's column i
    if (m == n) {  // x not coarsened: a copy
      for (; J < r.end; ++J) tmp[J] = fine[J - fine_origin];
      continue;
    }
    const auto edge = [&](int Jw) __attribute__((always_inline)) {
      T v = T(0);
      for (int i = 0; i < n; i = i + 1 == std::min(3, n) ? std::max(3, n - 3) : i + 1) {
        const int at = unwrap ? i + n * floor_div(2 * Jw + n / 2 - i, n) : i;
        for (int a = 0; a < 2; ++a)
          if (px.rows[i].index[a] == Jw) v += static_cast<T>(px.rows[i].weight[a]) * fine[off + at];
      }
      return v;
    };
    const int j0 = std::clamp(1 + r.base, J, r.end), j1 = std::clamp(m - 1 + r.base, j0, r.end);
    if (J < j0) tmp[J] = edge(J - r.base);
    const T* f = fine + (off - 2 * r.base);  // f[2J + d]: fine column 2(J - base) + d of copy k
#pragma GCC ivdep
    for (int x = j0; x < j1; ++x) tmp[x] = T(0.25) * (f[2 * x - 1] + f[2 * x + 2]) + T(0.75) * (f[2 * x] + f[2 * x + 1]);
    if (j1 < r.end) tmp[j1] = edge(j1 - r.base);
    J = r.end;
  }
  const T w0 = static_cast<T>(py.weight[0]), w1 = static_cast<T>(py.weight[1]);
  for (int J = cols.begin; J < cols.end; ++J) coarse0[J - origin[0]] += w0 * tmp[J];
  if (w1 == T(0)) return;
  if (py.mirror == fem::Mirror::None) {
    for (int J = cols.begin; J < cols.end; ++J) coarse1[J - origin[1]] += w1 * tmp[J];
    return;
  }
  for (int J = cols.begin; J < cols.end;) {
    const Run r = mirror_run(py.mirror, m, J, cols.end);
    for (; J < r.end; ++J) coarse1[r.base - J - origin[1]] += w1 * tmp[J];
  }
}

// Fine 2J, 2J+1 take 3/4 of coarse J, 1/4 of J-1 / J+1 (y-interpolated coarse samples formed once); only
// the first and last three fine samples read reflected or wrapped ones.
template <class T>
GDP_CLONES void prolong_rows(const fem::Prolongation& px, const fem::ProlongationRow& py, const T* coarse0,
                             const T* coarse1, std::array<int, 2> origin, bool coarse_whole, Columns cols, T* fine,
                             int fine_origin, Scratch<T>& s) {
  const int n = static_cast<int>(px.rows.size()), m = px.coarse_n;
  if (cols.end <= cols.begin) return;
  const bool unwrap = cols.periodic && !cols.wrap;
  // The coarse columns read: [lo, hi), unwrapped where the fine ones are.
  const auto coarse = [&](int i) { return floor_div(i, n) * m + (i - floor_div(i, n) * n) * m / n; };
  int lo = coarse(cols.begin) - 1, hi = coarse(cols.end - 1) + 2;
  if (!unwrap) lo = std::max(lo, 0), hi = std::min(hi, m);
  if (cols.wrap) lo = 0, hi = m;
  T* t = grow(s.line, hi - lo) - lo;  // t[J]
  const T w0 = static_cast<T>(py.weight[0]), w1 = static_cast<T>(py.weight[1]);
  for (int J = lo; J < hi;) {
    const Run r = copy_run(m, unwrap && coarse_whole, J, hi);  // whole rows: periodic copies read [0, m)
    const Run f = py.mirror == fem::Mirror::None ? Run{r.end, 0} : mirror_run(py.mirror, m, J, r.end);
    const T *c0 = coarse0 - origin[0] - r.base, *c1 = coarse1 - origin[1] - r.base;
    if (py.mirror == fem::Mirror::None)
      for (; J < r.end; ++J) t[J] = w0 * c0[J] + w1 * c1[J];
    else
      for (; J < f.end; ++J) t[J] = w0 * c0[J] + w1 * coarse1[f.base - J - origin[1]];
  }
  fine -= fine_origin;
  for (int i = cols.begin; i < cols.end;) {
    const Run r = copy_run(n, cols.periodic, i, cols.end);
    const int base = r.base / n * m;  // coarse copy of this fine copy
    int ib = std::clamp(m == n ? n : 3 + r.base, i, r.end), ie = std::clamp(n - 3 + r.base, ib, r.end);
    ib += (ib - r.base) % 2 && ib < ie, ie -= (ie - ib) % 2;  // pairs 2J, 2J + 1 between them
    const auto general = [&](int from, int to) __attribute__((always_inline)) {
      for (int x = from; x < to; ++x) {
        const fem::ProlongationRow& p = px.rows[x - r.base];
        std::array<int, 2> J = p.index;
        if (unwrap)
          for (int& v : J) v += m * floor_div(2 * ((x - r.base) * m / n - v) + m, 2 * m);
        fine[x] += static_cast<T>(p.weight[0]) * t[base + J[0]] + static_cast<T>(p.weight[1]) * t[base + J[1]];
      }
    };
    general(i, ib);
    // Fine 2J, 2J + 1 (from the copy's start): 3/4 of coarse J, 1/4 of the one beside it.
    T* fr = fine + r.base;
    const T* tb = t + base;
#pragma GCC ivdep
    for (int x = ib - r.base; x < ie - r.base; x += 2) {
      fr[x] += T(0.75) * tb[x / 2] + T(0.25) * tb[x / 2 - 1];
      fr[x + 1] += T(0.75) * tb[x / 2] + T(0.25) * tb[x / 2 + 1];
    }
    general(ie, r.end);
    i = r.end;
  }
}

#define GDP_INSTANTIATE(T)                                                                     \
  template decltype(apply<T>) apply<T>; template decltype(residual<T>) residual<T>;            \
  template decltype(relax<T>) relax<T>; template decltype(restrict_rows<T>) restrict_rows<T>; \
  template decltype(prolong_rows<T>) prolong_rows<T>;
GDP_INSTANTIATE(float)
GDP_INSTANTIATE(double)

}  // namespace gdp::multigrid
