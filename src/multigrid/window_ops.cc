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
    const T* row = w.rows[d];
    if (!row) {  // unused rows have zero coefficients: any (finite) row will do
      u[d] = w.rows[2] + (from - w.origin[2]);
      continue;
    }
    m[d] = my[d], k[d] = cy[d];
    const fem::Mirror mirror = mirrors[d];
    u[d] = row + (from - w.origin[d]);
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
  if (m[0] == m[4] && m[1] == m[3] && k[0] == k[4] && k[1] == k[3]) {
    // Interior rows: symmetric coefficients, pairs of rows added before multiplying.
#pragma GCC ivdep
    for (int i = 0; i < count; ++i) {
      const T p1 = u[1][i] + u[3][i], p2 = u[0][i] + u[4][i];
      A[i] = m[2] * u[2][i] + m[1] * p1 + m[0] * p2;
      C[i] = k[2] * u[2][i] + k[1] * p1 + k[0] * p2;
    }
  } else {
#pragma GCC ivdep
    for (int i = 0; i < count; ++i) {
      A[i] = m[0] * u[0][i] + m[1] * u[1][i] + m[2] * u[2][i] + m[3] * u[3][i] + m[4] * u[4][i];
      C[i] = k[0] * u[0][i] + k[1] * u[1][i] + k[2] * u[2][i] + k[3] * u[3][i] + k[4] * u[4][i];
    }
  }
  std::fill(a, A, T(0)), std::fill(c, C, T(0));
  std::fill(A + count, a + len, T(0)), std::fill(C + count, c + len, T(0));
  if (!cols.wrap) return;
  for (int g = 1; g <= 2; ++g) {  // the ghost samples of a whole periodic row (a[2] is column 0)
    a[2 - g] = a[2 + fem::wrap_index(-g, n)], c[2 - g] = c[2 + fem::wrap_index(-g, n)];
    a[1 + n + g] = a[2 + fem::wrap_index(n - 1 + g, n)], c[1 + n + g] = c[2 + fem::wrap_index(n - 1 + g, n)];
  }
}

// What convolve writes per column: A u, the residual b - A u, or relax's t = (b - A u) / K_0.
enum class Out { Au, Residual, Correction };

// Column x of q, a, c: sum_d sx[d] a[x + d - 2] + mx[d] c[x + d - 2] with the coefficients of table column
// g + x (for Out::Correction its 1 / K_0 from inv[g + x]); b[i + x] is the column's b.
template <Out O, class T>
GDP_INLINE void general(const LevelOperator<T>& op, T* q, const T* a, const T* c, const T* b, const T* inv, int i,
                        int count, int g) {
  const T *sx[5], *mx[5];
  for (int d = 0; d < 5; ++d) sx[d] = op.sx[d].data() + g, mx[d] = op.mx[d].data() + g;
  // A plain loop: vectorised, it spent a short tile's time in its epilogue (count is a few columns).
  for (int x = 0; x < count; ++x) {
    T v = sx[0][x] * a[x - 2];
    for (int d = 1; d < 5; ++d) v += sx[d][x] * a[x + d - 2];
    for (int d = 0; d < 5; ++d) v += mx[d][x] * c[x + d - 2];
    if constexpr (O == Out::Au) q[x] = v;
    else if constexpr (O == Out::Residual) q[x] = b[i + x] - v;
    else q[x] = (b[i + x] - v) * inv[g + x];
  }
}

// q[x] for column begin + x from the combined rows: per-column coefficients by the level's ends, the
// interior's one symmetric stencil (pairs of neighbours added before multiplying) elsewhere. b[i] is column
// i's b, inv the table of 1 / K_0 (relax's, cached per level and row coupling).
template <Out O, class T>
GDP_INLINE void convolve(const LevelOperator<T>& op, const Columns& cols, const Scratch<T>& s, T* q,
                         const T* b = nullptr, const T* inv = nullptr) {
  const T* a = s.a.data() + 2 - cols.begin;  // a[i]: column i
  const T* c = s.c.data() + 2 - cols.begin;
  q -= cols.begin;
  const T sc = op.sx_in[0], s1c = op.sx_in[1], s2c = op.sx_in[2];
  const T mc = op.mx_in[0], m1c = op.mx_in[1], m2c = op.mx_in[2];
  const T in = O == Out::Correction && op.interior_begin < op.interior_end ? inv[op.interior_begin] : T(1);
  for (int i = cols.begin; i < cols.end;) {  // run by run (one per periodic copy), each cut at the interior
    const Run r = copy_run(op.width, cols.periodic, i, cols.end);
    const int ib = std::clamp(op.interior_begin + r.base, i, r.end);
    const int ie = std::clamp(op.interior_end + r.base, ib, r.end);
    general<O>(op, q + i, a + i, c + i, b, inv, i, ib - i, i - r.base);
#pragma GCC ivdep
    for (int x = ib; x < ie; ++x) {
      const T v = sc * a[x] + s1c * (a[x - 1] + a[x + 1]) + s2c * (a[x - 2] + a[x + 2]) + mc * c[x] +
                  m1c * (c[x - 1] + c[x + 1]) + m2c * (c[x - 2] + c[x + 2]);
      if constexpr (O == Out::Au) q[x] = v;
      else if constexpr (O == Out::Residual) q[x] = b[x] - v;
      else q[x] = (b[x] - v) * in;
    }
    general<O>(op, q + ie, a + ie, c + ie, b, inv, ie, r.end - ie, ie - r.base);
    i = r.end;
  }
}

// The recurrence's terms of table columns [g0, g0 + count) into K[0..) (diag likewise), one direction.
// Out of line, so compiled for the baseline (no multiply-adds): its rounding is weighted solves' bits.
template <class T>
__attribute__((noinline)) void fill(const LevelOperator<T>& op, T m0, T c0, const T* diag, int g0, int count,
                                    bool forward, typename Scratch<T>::Coefficients& K) {
  const int near = forward ? 1 : 3, far = forward ? 0 : 4, dir = forward ? 0 : 1;
  T *inv = grow(K.inv, count), *k1 = grow(K.kn[dir], count), *k2 = grow(K.kf[dir], count);
  for (int i = 0; i < count; ++i) {
    const int g = g0 + i;
    inv[i] = T(1) / (op.sx[2][g] * m0 + op.mx[2][g] * c0 + (diag ? diag[i] : T(0)));
    k1[i] = (op.sx[near][g] * m0 + op.mx[near][g] * c0) * inv[i];
    k2[i] = (op.sx[far][g] * m0 + op.mx[far][g] * c0) * inv[i];
  }
  // Blocks of 4 on table multiples of 4: dx[b + r] = A_r + B[b + r] dx[b - 1] + C[b + r] dx[b - 2] (backward:
  // from the block's top down, with dx[e + 1], dx[e + 2]); A is the recurrence started from zero in the block.
  T *B = grow(K.B[dir], count), *C = grow(K.C[dir], count);
  const int s = forward ? 1 : -1;
  for (int b = (4 - g0 % 4) % 4; b + 4 <= count; b += 4) {
    T b1 = T(1), b2 = T(0), c1 = T(0), c2 = T(1);  // B, C one and two samples back (dx[b - 1], dx[b - 2] alone)
    for (int x = forward ? b : b + 3, r = 0; r < 4; ++r, x += s) {
      B[x] = -k1[x] * b1 - k2[x] * b2, C[x] = -k1[x] * c1 - k2[x] * c2;
      b2 = b1, b1 = B[x], c2 = c1, c1 = C[x];
    }
  }
}

// The recurrence dx[x] = t[x] - kn[x] dx[x - S] - kf[x] dx[x - 2S] for x = 0, S, .. (S - 1) *
// count, carrying d1 = dx[x - S], d2 = dx[x - 2S]; blocks of four from step `lead` on (the only
// chain carried from block to block is two multiply-adds). Add: out[x] += dx[x] (u), else out[x] = dx[x].
template <int S, bool Add, class T>
GDP_INLINE void recur(const typename Scratch<T>::Coefficients& K, int at, const T* t, int count, int lead, T* out,
                      T& d1, T& d2) {
  constexpr int dir = S > 0 ? 0 : 1;
  const T *kn = K.kn[dir].data() + at, *kf = K.kf[dir].data() + at;
  const T *B = K.B[dir].data() + at, *C = K.C[dir].data() + at;
  const auto put = [out](int x, T v) __attribute__((always_inline)) {
    if constexpr (Add) out[x] += v;
    else out[x] = v;
  };
  for (int n = 0; n < count;) {
    const int x = S * n;
    if (n < lead || n + 4 > count) {  // one sample
      const T v = t[x] - kf[x] * d2;
      d2 = d1, d1 = v - kn[x] * d1;
      put(x, d1);
      ++n;
      continue;
    }
    T a[4], o[4];  // the in-block recurrence started from zero, then the corrections carried in added
    for (int r = 0, y = x; r < 4; ++r, y += S) {
      a[r] = t[y];
      if (r > 0) a[r] -= kn[y] * a[r - 1];
      if (r > 1) a[r] -= kf[y] * a[r - 2];
    }
    for (int r = 0, y = x; r < 4; ++r, y += S) put(y, o[r] = a[r] + B[y] * d1 + C[y] * d2);
    d2 = o[2], d1 = o[3], n += 4;
  }
}

// The same recurrence on blocks of eight samples with constant coefficients (the level's interior):
// each block's in-block part as a vector, the matrix M's eight columns times t (M: Coefficients::block,
// then the responses B, C to the corrections carried in); the chain from block to block is two scalar
// multiply-adds (the carried lanes known at compile time, so it stays in registers), the outputs two vector
// multiply-adds off it. Blocks [lo, hi) of t, in the sweep's direction (backward: lanes in memory order, the
// sweep running from lane 7 down). Changes the rounding against blocks of four; every schedule uses it alike.
// Blocks of sixteen were faster on whole rows, slower on short tiles, and round differently
// (docs/multigrid.md, "t in the filter loop").
constexpr int kBlock = 8;

template <bool Add, bool forward, class T>
GDP_INLINE void recur_blocks(const T* t, const T* M, int lo, int hi, T* out, T& d1, T& d2) {
  typedef T V __attribute__((vector_size(8 * sizeof(T))));  // eight lanes
  constexpr int last = forward ? 7 : 0, before = forward ? 6 : 1;  // the lanes carried to the next block
  V H[8], B, C;
  for (int k = 0; k < 8; ++k) std::memcpy(&H[k], M + 8 * k, sizeof(V));
  std::memcpy(&B, M + 64, sizeof(V)), std::memcpy(&C, M + 72, sizeof(V));
  for (int n = 0; n < (hi - lo) / 8; ++n) {
    const int x = forward ? lo + 8 * n : hi - 8 * (n + 1);
    V A = H[0] * t[x];
    for (int k = 1; k < 8; ++k) A += H[k] * t[x + k];
    const T n1 = A[last] + B[last] * d1 + C[last] * d2, n2 = A[before] + B[before] * d1 + C[before] * d2;
    V o = A + B * d1 + C * d2;
    if constexpr (Add) {
      V u;
      std::memcpy(&u, out + x, sizeof(V));
      o += u;
    }
    std::memcpy(out + x, &o, sizeof(V));
    d1 = n1, d2 = n2;
  }
}

// The recurrence over t[0, count) (table columns g0 .., K's at `at` ..) in the sweep's direction: blocks of
// eight on the level's interior where K has them, blocks of four (recur) before and after.
template <bool Add, class T>
GDP_INLINE void recur_run(const LevelOperator<T>& op, const typename Scratch<T>::Coefficients& K, int at, int g0,
                          const T* t, int count, bool fwd, T* out, T& d1, T& d2) {
  if (count <= 0) return;
  const std::vector<T>& M = K.block[fwd ? 0 : 1];
  int v0 = count, v1 = count;  // [v0, v1): whole blocks in the interior
  if (!M.empty()) {
    const int ib = std::clamp(op.interior_begin - g0, 0, count), ie = std::clamp(op.interior_end - g0, ib, count);
    const int span = (ie - ib) / kBlock * kBlock;
    if (span > 0) v0 = fwd ? ib : ie - span, v1 = v0 + span;
  }
  const auto four = [&](int lo, int hi) __attribute__((always_inline)) {
    if (hi <= lo) return;
    if (fwd) recur<1, Add>(K, at + lo, t + lo, hi - lo, (4 - (g0 + lo) % 4) % 4, out + lo, d1, d2);
    else recur<-1, Add>(K, at + hi - 1, t + hi - 1, hi - lo, (g0 + hi) % 4, out + hi - 1, d1, d2);
  };
  four(fwd ? 0 : v1, fwd ? v0 : count);
  if (v1 > v0 && fwd) recur_blocks<Add, true>(t, M.data(), v0, v1, out, d1, d2);
  if (v1 > v0 && !fwd) recur_blocks<Add, false>(t, M.data(), v0, v1, out, d1, d2);
  four(fwd ? v1 : 0, fwd ? count : v0);
}

// Coefficients::block of a level whose interior (one constant stencil) is eight columns or more.
template <class T>
void fill_blocks(const LevelOperator<T>& op, typename Scratch<T>::Coefficients& K) {
  for (int dir = 0; dir < 2; ++dir) K.block[dir].clear();
  if (op.interior_end - op.interior_begin < kBlock) return;
  for (int dir = 0; dir < 2; ++dir) {
    const T kn = K.kn[dir][op.interior_begin], kf = K.kf[dir][op.interior_begin];
    T h[9], C[8];  // sample r of a block: h[r] from its first t, h[r + 1] and C[r] from the corrections before it
    h[0] = T(1), h[1] = -kn, C[0] = -kf, C[1] = -kn * C[0];
    for (int r = 2; r < 9; ++r) h[r] = -kn * h[r - 1] - kf * h[r - 2];
    for (int r = 2; r < 8; ++r) C[r] = -kn * C[r - 1] - kf * C[r - 2];
    std::vector<T>& M = K.block[dir];
    M.assign(80, T(0));
    for (int k = 0; k < 8; ++k)  // lane p of column k: sample p takes h[steps from sample k to it]
      for (int p = 0; p < 8; ++p) {
        const int r = dir ? k - p : p - k;
        M[8 * k + p] = r >= 0 ? h[r] : T(0);
      }
    for (int p = 0; p < 8; ++p) M[64 + p] = h[dir ? 8 - p : p + 1], M[72 + p] = C[dir ? 7 - p : p];
  }
}

}  // namespace

Columns Columns::whole(int n, bool periodic) { return {0, n, periodic, periodic, true}; }

Columns Columns::range(int n, bool periodic, int begin, int end, bool forward) {
  if (!periodic) begin = std::max(begin, 0), end = std::min(end, n);
  return {begin, end, periodic, false, forward};
}

template <class T>
const typename Scratch<T>::Coefficients& Scratch<T>::coefficients(const LevelOperator<T>& op, T m0, T c0) {
  for (const Coefficients& k : cached)
    if (k.op == &op && k.m0 == m0 && k.c0 == c0) return k;
  if (cached.size() >= 8) std::rotate(cached.begin(), cached.begin() + 1, cached.end());  // reuse the oldest
  else cached.emplace_back();
  Coefficients& k = cached.back();
  k.op = &op, k.m0 = m0, k.c0 = c0;
  for (bool forward : {true, false}) fill(op, m0, c0, static_cast<const T*>(nullptr), 0, op.width, forward, k);
  fill_blocks(op, k);
  return k;
}

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
  if (!diag) return convolve<Out::Residual>(op, cols, s, r + o, b + o - cols.begin);
  T* q = grow(s.q, len);  // q = A u on the columns
  convolve<Out::Au>(op, cols, s, q);
  // Pinned pixels hold u = value (to ~1e-6); b - A u - D u there is round-off that would swamp the norms: 0.
  const T pinned = static_cast<T>(LevelOperator<T>::kPinnedDiagonal), *u = w.rows[2];
  for (int x = 0, i = o; x < len; ++x, ++i) r[i] = diag[i] >= pinned ? T(0) : b[i] - q[x] - diag[i] * u[i];
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
  const typename Scratch<T>::Coefficients* K = diag ? &s.local : &s.coefficients(op, m0, c0);
  T* q = grow(s.q, len);  // t = (b - A u) / K_0 on the columns; with a diagonal term A u, t formed per run below
  combine(op, j, w, cols, s);
  if (diag) convolve<Out::Au>(op, cols, s, q);
  else convolve<Out::Correction>(op, cols, s, q, b + o - cols.begin, K->inv.data());
  T* dx = grow(s.dx, len + 4) + 2;
  dx[-2] = dx[-1] = dx[len] = dx[len + 1] = T(0);
  const bool wrap = cols.wrap, fwd = cols.forward || wrap;
  const int swept = wrap ? std::max(len - 2, 0) : len;
  T d1 = T(0), d2 = T(0);
  for (int done = 0; done < len;) {  // run by run (one per periodic copy) in the sweep's order: [x0, x1)
    const Run r = copy_run(op.width, cols.periodic, cols.begin + (fwd ? done : len - 1 - done), cols.end);
    const int x0 = fwd ? done : std::max(r.base, cols.begin) - cols.begin, x1 = fwd ? r.end - cols.begin : len - done;
    const int count = x1 - x0, g0 = cols.begin + x0 - r.base;
    if (diag) fill(op, m0, c0, diag + o + x0, g0, count, fwd, s.local);
    const int at = diag ? 0 : g0;  // K's column for x0
    T* t = q + x0;
    if (diag)
      for (int x = 0, i = o + x0; x < count; ++x, ++i) t[x] = (b[i] - t[x] - diag[i] * u[i]) * K->inv[x];
    if (wrap)  // corrections kept for the last two samples, added below
      recur_run<false>(op, *K, at, g0, t, std::min(count, swept - x0), true, dx + x0, d1, d2);
    else
      recur_run<true>(op, *K, at, g0, t, count, fwd, u + o + x0, d1, d2);
    done += count;
  }
  for (int i = swept; i < len; ++i) {  // wrap: the last two samples (one run, K's columns from 0)
    T v = q[i] - K->kn[0][i] * dx[i - 1] - K->kf[0][i] * dx[i - 2];
    for (int d = len - i; d <= 2; ++d) {
      const int col = fem::wrap_index(i + d, len);
      if (col < i) v -= (op.sx[d + 2][i] * m0 + op.mx[d + 2][i] * c0) * K->inv[i] * dx[col];
    }
    dx[i] = v;
  }
  if (wrap)
    for (int x = 0; x < len; ++x) u[o + x] += dx[x];
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
    if (m == n) {
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
  int lo = floor_div(cols.begin, n) * m + (cols.begin - floor_div(cols.begin, n) * n) * m / n - 1;
  int hi = floor_div(cols.end - 1, n) * m + (cols.end - 1 - floor_div(cols.end - 1, n) * n) * m / n + 2;
  if (!unwrap) lo = std::max(lo, 0), hi = std::min(hi, m);
  if (cols.wrap) lo = 0, hi = m;
  T* t = grow(s.line, hi - lo) - lo;  // t[J]
  const T w0 = static_cast<T>(py.weight[0]), w1 = static_cast<T>(py.weight[1]);
  for (int J = lo; J < hi;) {
    const Run r = copy_run(m, unwrap && coarse_whole, J, hi);  // whole rows: periodic copies read [0, m)
    const Run f = py.mirror == fem::Mirror::None ? Run{r.end, 0} : mirror_run(py.mirror, m, J, r.end);
    const T* c0 = coarse0 - origin[0] - r.base;
    if (py.mirror == fem::Mirror::None) {
      const T* c1 = coarse1 - origin[1] - r.base;
      for (; J < r.end; ++J) t[J] = w0 * c0[J] + w1 * c1[J];
    } else {
      for (; J < f.end; ++J) t[J] = w0 * c0[J] + w1 * coarse1[f.base - J - origin[1]];
    }
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

#define GDP_INSTANTIATE(T)                                                             \
  template struct Scratch<T>;                                                          \
  template decltype(apply<T>) apply<T>;                                                \
  template decltype(residual<T>) residual<T>;                                          \
  template decltype(relax<T>) relax<T>;                                                \
  template decltype(restrict_rows<T>) restrict_rows<T>;                                \
  template decltype(prolong_rows<T>) prolong_rows<T>;
GDP_INSTANTIATE(float)
GDP_INSTANTIATE(double)

}  // namespace gdp::multigrid
