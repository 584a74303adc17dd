// In-core V-cycle: pre-smooth, restrict, recurse, coarse CG, prolong, post-smooth.
#include "multigrid/incore_vcycle.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "multigrid/coarse_cg.h"
#include "multigrid/plane_ops.h"

namespace gdp::multigrid {

template <class T>
Operators<T>::Operators(const Hierarchy& h)
    : hierarchy(&h), coarsest(h.levels.back(), h.alpha), singular(h.alpha == 0.0) {
  for (const LevelGeometry& g : h.levels) levels.emplace_back(g, h.alpha);
}

namespace {

// Level l + 1's weights restricted from level l's (`fine`), rows in order: each coarse row in a row of
// its own from its first to its last fine row, then kept, where `held_once` says after the row kept
// before it when the two are the same bits. The same restrict_rows calls in the same order as into a
// whole zeroed plane: the same bits.
template <class T>
Plane<T> restrict_level(const Operators<T>& ops, int l, const Plane<T>& fine, bool held_once, Scratch<T>& s) {
  const LevelGeometry& g = ops.hierarchy->levels[l + 1];
  const int width = g.width(), height = g.height();
  const std::size_t n = static_cast<std::size_t>(width);
  std::vector<int> last(height, -1);  // the last fine row restricted into each coarse row
  for (int j = 0; j < ops.levels[l].height; ++j)
    for (const int k : g.py.rows[j].index) last[k] = j;
  Plane<T> out;
  out.width = width;
  out.data.reserve(n * height);  // (pages mapped as rows are kept)
  out.rows_of.assign(height, 0);
  std::vector<std::vector<T>> open(height), spare;  // (rows handed back for reuse: no page faults a row)
  const auto row = [&](int k) {
    if (open[k].empty()) {
      if (!spare.empty()) open[k] = std::move(spare.back()), spare.pop_back();
      open[k].assign(n, T(0));
    }
    return open[k].data();
  };
  const auto keep = [&](int k) {
    const T* r = row(k);
    const T* held = out.data.data() + (out.data.size() - n * (out.height > 0));
    if (!held_once || out.height == 0 || std::memcmp(held, r, n * sizeof(T)) != 0) {
      out.data.insert(out.data.end(), r, r + n);
      ++out.height;
    }
    out.rows_of[k] = out.height - 1;
    spare.push_back(std::move(open[k]));
  };
  int kept = 0;  // coarse rows [0, kept) kept
  for (int j = 0; j < ops.levels[l].height; ++j) {
    const fem::ProlongationRow& py = g.py.rows[j];
    T* c0 = row(py.index[0]);
    restrict_rows(g.px, py, weight_row(fine, j), 0, Columns::whole(width, ops.levels[l + 1].periodic_x), c0,
                  row(py.index[1]), {0, 0}, s);
    for (; kept < height && last[kept] <= j; ++kept) keep(kept);
  }
  for (; kept < height; ++kept) keep(kept);
  if (!held_once) out.rows_of.clear();
  return out;
}

}  // namespace

template <class T>
std::vector<Plane<T>> restrict_weights(const Operators<T>& ops, int first, Plane<T> w, bool held_once) {
  std::vector<Plane<T>> out;
  out.push_back(std::move(w));
  Scratch<T> s;
  for (int l = first; l + 1 < ops.count(); ++l) out.push_back(restrict_level(ops, l, out.back(), held_once, s));
  return out;
}

template <class T>
void WeightRows<T>::add() {
  // Compared as bytes: a plane of one row must give every row's exact bits.
  if (plane_.height == 1 && rows_ > 0 && std::memcmp(row_.data(), plane_.row(0), row_.size() * sizeof(T)) != 0) {
    Plane<T> whole(plane_.width, height_);
    for (int j = 0; j < rows_; ++j) std::copy_n(plane_.row(0), plane_.width, whole.row(j));
    plane_ = std::move(whole);
  }
  std::copy(row_.begin(), row_.end(), plane_.row(plane_.height == 1 ? 0 : rows_));
  ++rows_;
}

template <class T>
InCoreVCycle<T>::InCoreVCycle(const Operators<T>& ops, int sweeps, double coarse_tolerance, int first)
    : ops_(ops), sweeps_(sweeps), post_sweeps_(sweeps), coarse_tolerance_(coarse_tolerance), first_(first) {
  for (int l = first + 1; l < ops.count(); ++l) {
    // (Mapped in one call: cheaper than faulting fresh pages in one at a time, docs/multigrid.md.)
    u_.push_back(Plane<T>::mapped(ops.levels[l].width, ops.levels[l].height));
    b_.push_back(Plane<T>::mapped(ops.levels[l].width, ops.levels[l].height));
  }
  lane_.r.resize(ops.levels[first].width);
  lead_.r = lane_.r;
  coarse_b_ = Plane<double>(ops.coarsest.width, ops.coarsest.height);
  coarse_u_ = coarse_b_;
}

template <class T>
void InCoreVCycle<T>::run(Plane<T>& u0, Plane<T>& b0, const std::vector<Plane<T>>* weights, CycleProbe* probe) {
  run(u0, Rhs{&b0}, weights, probe);
}

template <class T>
void InCoreVCycle<T>::run(Plane<T>& u0, RowFeed<T>& b0, const std::vector<Plane<T>>* weights, CycleProbe* probe) {
  if (first_ + 1 >= ops_.count()) {  // a single level has no passes: b whole
    Plane<T> whole(ops_.levels[first_].width, ops_.levels[first_].height);
    b0.rewind();
    for (int j = 0; j < whole.height; ++j) b0.read(std::span<T>(whole.row(j), whole.width));
    return run(u0, whole, weights, probe);
  }
  // Rows a pass may still read: those of its last 2 max(sweeps) + 2 steps, and room for the lead to
  // run ahead of the follower's word (PassPair::kDoneEvery) and wait (wait_done) beyond them.
  const int rows = 2 * std::max(sweeps_, post_sweeps_) + 2 + 8 * PassPair::kDoneEvery;
  if (ring_.height != rows) ring_ = Plane<T>(ops_.levels[first_].width, rows);
  run(u0, Rhs{nullptr, &b0}, weights, probe);
}

// Rows of a fed b up to j read into the ring (the lead's, or a single thread's). The row it replaces
// was read at step j - ring rows or before: with two threads the lead waits for the follower past it.
template <class T>
void InCoreVCycle<T>::feed_to(Rhs& b, int j) {
  if (!b.feed) return;
  const bool paired = pair_ && ops_.levels[first_].height >= kPairRows;
  for (j = std::min(j, ops_.levels[first_].height - 1); b.fed <= j; ++b.fed) {
    const int past = b.fed - ring_.height + 2 * std::max(sweeps_, post_sweeps_) + 3;
    if (paired && past > 0) pair_->wait_done(past);
    T* row = ring_.row(b.fed % ring_.height);
    b.feed->read(std::span<T>(row, ring_.width));
    if (b.feed->rounded) round_to_half(row, ring_.width);
  }
}

template <class T>
void InCoreVCycle<T>::run(Plane<T>& u0, Rhs b0, const std::vector<Plane<T>>* weights, CycleProbe* probe) {
  const int levels = ops_.count();
  auto U = [&](int l) -> Plane<T>& { return l == first_ ? u0 : u_[l - first_ - 1]; };
  auto B = [&](int l) -> Plane<T>& { return l == first_ ? *b0.plane : b_[l - first_ - 1]; };
  auto W = [&](int l) -> const Plane<T>& { return (*weights)[l - first_]; };
  auto D = [&](int l) -> const Plane<T>* { return diag_ ? &(*diag_)[l - first_] : nullptr; };
  auto R = [&](int l) { return l == first_ ? b0 : Rhs{&b_[l - first_ - 1]}; };

  // |b - A u| on level `first` before and after, where asked, in the passes of descend and ascend
  // (a single level has none: then residual_norm()).
  double* before = probe && probe->norm_before ? &probe->before : nullptr;
  double* after = probe && probe->norm_after ? &probe->after : nullptr;
  const bool passes = first_ + 1 < levels, level_norms = probe && probe->sum_level_norms;
  if (probe) probe->before = probe->after = 0.0;
  if (before && !passes) *before = residual_norm(u0, B(first_));
  for (int l = first_; l + 1 < levels; ++l) {
    Plane<T>& coarse_b = b_[l - first_];  // zeroed by descend as its rows are reached, like U(l) for l > first
    if (l + 2 == levels) std::fill(U(l + 1).data.begin(), U(l + 1).data.end(), T(0));  // the coarsest's guess
    double dots = 0.0;
    Rhs b = R(l);
    const double rr =
        descend(l, U(l), b, D(l), coarse_b, weights && probe ? &W(l) : nullptr, dots, level_norms,
                l == first_ ? before : nullptr);
    if (weights && probe) probe->dots.push_back(dots);
    if (level_norms) probe->level_norms.push_back(std::sqrt(rr));
    if (!half_u_.empty() && half_u_[l - first_]) round_to_half(U(l).data.data(), U(l).data.size());
    if (half_b_.empty() || !half_b_[l - first_]) continue;
    if (b.feed) b.feed->rounded = true;
    else round_to_half(B(l).data.data(), B(l).data.size());
  }

  {  // Coarsest level: conjugate gradients in double precision.
    const LevelOperator<double>& op = ops_.coarsest;
    Plane<double> &b = coarse_b_, &u = coarse_u_;  // b is overwritten, u is the initial guess
    std::copy(B(levels - 1).data.begin(), B(levels - 1).data.end(), b.data.begin());
    std::copy(U(levels - 1).data.begin(), U(levels - 1).data.end(), u.data.begin());
    const Plane<double>* dp = diag_ ? &coarse_diag_ : nullptr;
    solve_cg(op, ops_.singular && !diag_, b, u, coarse_tolerance_, 20 * (op.width + op.height) + 100, dp,
             coarse_inverse_);
    if (level_norms) {
      Plane<double> r(op.width, op.height);
      Scratch<double> s;
      residual(op, u, b, r, s, dp);
      probe->level_norms.push_back(norm2(r));
    }
    std::transform(u.data.begin(), u.data.end(), U(levels - 1).data.begin(),
                   [](double v) { return static_cast<T>(v); });
    if (weights && probe) {
      double s = 0.0;
      for (int j = 0; j < op.height; ++j) s += row_dot(weight_row(W(levels - 1), j), U(levels - 1).row(j), op.width);
      probe->dots.push_back(s);
    }
  }

  for (int l = levels - 2; l >= first_; --l) {
    Rhs b = R(l);
    ascend(l, U(l), b, D(l), U(l + 1), l == first_ ? after : nullptr);
  }
  if (before && passes) *before = std::sqrt(*before);
  if (after) *after = passes ? std::sqrt(*after) : residual_norm(u0, B(first_));
}

// Row j's |b - A u|^2 on level l (as residual_norm() sums it), in the lane's temporaries.
template <class T>
double InCoreVCycle<T>::row_residual2(int l, const Plane<T>& u, const T* b, const Plane<T>* d, int j, Lane& lane) {
  const LevelOperator<T>& op = ops_.levels[l];
  residual(op, j, window(op, u, j), whole_row(op), b, lane.r.data(), lane.scratch, diag_row(d, j));
  return row_squares(lane.r.data(), op.width);
}

// The sweeps of a pass the lead takes: the split whose larger share of a row's work is the least
// (more to the lead where two are as good), counting a row's relaxation 1 and the lead's and the
// follower's other work on it, `lead` and `follow`, in relaxations: a residual (with its square
// sum) or a prolongation about 0.6, a restriction (with the weights' dot) 0.4 (perf of the 8192²
// in-core stitch). Any split gives the same bits (PassPair).
inline int lead_sweeps(int sweeps, double lead, double follow) {
  int best = 0;
  for (int s = 1; s <= sweeps; ++s)
    if (std::max(s + lead, sweeps - s + follow) <= std::max(best + lead, sweeps - best + follow)) best = s;
  return best;
}
constexpr double kResidualCost = 0.6, kProlongCost = 0.6, kRestrictCost = 0.4;

// One pass of `steps` steps over a level of `rows` rows: lead(t) then follow(t) for each t on this
// thread, or the two on the pair's threads, the follower's step t after the lead's.
template <class T>
template <class Lead, class Follow>
void InCoreVCycle<T>::pass(int steps, int rows, const Lead& lead, const Follow& follow) {
  if (!pair_ || rows < kPairRows) {
    for (int t = 0; t < steps; ++t) lead(t), follow(t);
    return;
  }
  pair_->run(
      steps,
      [&] {
        for (int t = 0; t < steps; ++t) lead(t), pair_->ahead(t + 1);
      },
      [&] {
        for (int t = 0; t < steps; ++t) {
          pair_->behind(t), follow(t);
          if ((t + 1) % PassPair::kDoneEvery == 0) pair_->done(t + 1);
        }
      });
}

// Pre-smoothing, then residual and restriction, in one pass down the rows: at step t sweep s + 1
// relaxes row t - 2s, and row t - 2k, whose neighbours are then final, has its residual restricted
// into the coarser level. Every relaxation sees what it sees in k whole sweeps one after the other
// (rows above at this sweep, rows below at the one before; they couple within two rows), so the
// bits are the same; the rows being worked on stay in cache. A coarser level's u (the zero guess) and
// the coarser b are zeroed row by row just before they are first touched, not in passes of their own.
// The lead zeroes, sums `before` and does the first sweeps (lead_sweeps); the follower the other sweeps and the rest.
// Returns |r|^2 with `norms` (else 0: the sum costs about 2 % of a V-cycle); adds <w, u> to dots.
template <class T>
double InCoreVCycle<T>::descend(int l, Plane<T>& u, Rhs& b, const Plane<T>* d, Plane<T>& coarse_b,
                                const Plane<T>* w, double& dots, bool norms, double* before) {
  const LevelOperator<T>& op = ops_.levels[l];
  const LevelGeometry& g = ops_.hierarchy->levels[l + 1];
  const Columns row = whole_row(op), coarse_row = whole_row(ops_.levels[l + 1]);
  const int led = lead_sweeps(sweeps_, before ? kResidualCost : 0.0, kResidualCost + kRestrictCost);
  double rr = 0.0;
  const auto zero_rows = [](Plane<T>& p, int& done, int to) {
    to = std::min(to, p.height);
    if (to > done) std::fill(p.row(done), p.row(done) + static_cast<std::size_t>(to - done) * p.width, T(0));
    done = std::max(done, to);
  };
  const auto relax_row = [&](int s, int j, Scratch<T>& scratch) {
    if (j >= 0 && j < op.height)
      relax(op, j, window(op, u, j), sweep_columns(row, s, j), u.row(j), b_row(b, j), scratch, diag_row(d, j));
  };
  int u_zeroed = l > first_ ? 0 : op.height, b_zeroed = 0;
  // `before`: row j's residual reads rows j - 2 .. j + 2, all as they came while j - 2 is unrelaxed.
  rewind(b);
  feed_to(b, 1);
  for (int j = 0; before && j < std::min(2, op.height); ++j) *before += row_residual2(l, u, b_row(b, j), d, j, lead_);
  const auto lead = [&](int t) {
    zero_rows(u, u_zeroed, t + 3);  // relaxing row t reads rows up to t + 2
    feed_to(b, before ? t + 2 : t);
    if (before && t + 2 < op.height) *before += row_residual2(l, u, b_row(b, t + 2), d, t + 2, lead_);
    for (int s = 0; s < led; ++s) relax_row(s, t - 2 * s, lead_.scratch);
  };
  const auto follow = [&](int t) {
    for (int s = led; s < sweeps_; ++s) relax_row(s, t - 2 * s, lane_.scratch);
    const int j = t - 2 * sweeps_;
    if (j < 0) return;
    if (w) dots += row_dot(weight_row(*w, j), u.row(j), op.width);
    residual(op, j, window(op, u, j), row, b_row(b, j), lane_.r.data(), lane_.scratch, diag_row(d, j));
    if (norms) rr += row_squares(lane_.r.data(), op.width);
    const fem::ProlongationRow& py = g.py.rows[j];
    zero_rows(coarse_b, b_zeroed, std::max(py.index[0], py.index[1]) + 1);
    restrict_rows(g.px, py, lane_.r.data(), 0, coarse_row, coarse_b.row(py.index[0]), coarse_b.row(py.index[1]),
                  {0, 0}, lane_.scratch);
  };
  pass(op.height + 2 * sweeps_, op.height, lead, follow);
  zero_rows(coarse_b, b_zeroed, coarse_b.height);
  return rr;
}

// Prolongation of the coarser level's correction, then post-smoothing, in one pass down the rows:
// at step t row t takes the correction and sweep s + 1 relaxes row t - 2 - 2s (same bits as above).
// The lead prolongs and does the first sweeps (lead_sweeps); the follower the other sweeps and sums `after`.
template <class T>
void InCoreVCycle<T>::ascend(int l, Plane<T>& u, Rhs& b, const Plane<T>* d, const Plane<T>& coarse,
                             double* after) {
  const LevelOperator<T>& op = ops_.levels[l];
  const LevelGeometry& g = ops_.hierarchy->levels[l + 1];
  const Columns row = whole_row(op);
  const int led = lead_sweeps(post_sweeps_, kProlongCost, after ? kResidualCost : 0.0);
  const auto relax_row = [&](int s, int j, Scratch<T>& scratch) {
    if (j >= 0 && j < op.height)
      relax(op, j, window(op, u, j), sweep_columns(row, sweeps_ + s, j), u.row(j), b_row(b, j), scratch,
            diag_row(d, j));
  };
  // `after`: row j is final at step j + 2 * post_sweeps, so row j's residual two steps later.
  const int last = 2 + 2 * post_sweeps_;
  rewind(b);
  const auto lead = [&](int t) {
    feed_to(b, t - 2);  // (every pass reads rows up to t - 2 at step t)
    if (t < op.height) {
      const fem::ProlongationRow& py = g.py.rows[t];
      prolong_rows(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), {0, 0}, true, row, u.row(t), 0,
                   lead_.scratch);
    }
    for (int s = 0; s < led; ++s) relax_row(s, t - 2 - 2 * s, lead_.scratch);
  };
  const auto follow = [&](int t) {
    for (int s = led; s < post_sweeps_; ++s) relax_row(s, t - 2 - 2 * s, lane_.scratch);
    if (after && t >= last && t - last < op.height) *after += row_residual2(l, u, b_row(b, t - last), d, t - last, lane_);
  };
  pass(op.height + (after ? last : 2 * post_sweeps_), op.height, lead, follow);
}

// The columns of sweep `sweep` (counted from the first pre-smoothing sweep) of row j.
template <class T>
Columns InCoreVCycle<T>::sweep_columns(const Columns& row, int sweep, int j) const {
  Columns c = row;
  if (direction_ == SweepDirection::AlternateSweeps) c.forward = sweep % 2 == 0;
  if (direction_ == SweepDirection::AlternateRows) c.forward = (sweep + j) % 2 == 0;
  return c;
}

template <class T>
void InCoreVCycle<T>::set_sweeps(int pre, int post) {
  sweeps_ = pre;
  post_sweeps_ = post;
}

template <class T>
void InCoreVCycle<T>::set_smoother(int pre, int post, SweepDirection direction) {
  set_sweeps(pre, post);
  direction_ = direction;
}

template <class T>
void InCoreVCycle<T>::set_diagonal(const std::vector<Plane<T>>* diag) {
  diag_ = diag;
  coarse_diag_ = Plane<double>();
  coarse_inverse_.clear();
  if (!diag) return;
  const Plane<T>& coarsest = diag->back();
  coarse_diag_ = Plane<double>(coarsest.width, coarsest.height);
  std::copy(coarsest.data.begin(), coarsest.data.end(), coarse_diag_.data.begin());
  coarse_inverse_ = inverse_diagonal(ops_.coarsest, coarse_diag_);
}

template <class T>
void InCoreVCycle<T>::set_half(const HalfPolicy* half) {
  half_u_.clear();
  half_b_.clear();
  if (!half || !half->any()) return;
  for (int l = first_; l < ops_.count(); ++l) {
    half_u_.push_back(half->rounds(l, "u"));
    half_b_.push_back(half->rounds(l, "b"));
  }
}

template <class T>
double InCoreVCycle<T>::residual_norm(const Plane<T>& u, const Plane<T>& b) {
  double rr = 0.0;
  for (int j = 0; j < u.height; ++j) rr += row_residual2(first_, u, b.row(j), diag_ ? &(*diag_)[0] : nullptr, j, lane_);
  return std::sqrt(rr);
}

template struct Operators<float>;
template struct Operators<double>;
template class WeightRows<float>;
template class WeightRows<double>;
template class InCoreVCycle<float>;
template class InCoreVCycle<double>;
template std::vector<Plane<float>> restrict_weights(const Operators<float>&, int, Plane<float>, bool);
template std::vector<Plane<double>> restrict_weights(const Operators<double>&, int, Plane<double>, bool);

}  // namespace gdp::multigrid
