// Input rows: guidance rows through the right-hand-side assembler, two rows of look-ahead.
#include "multigrid/input_rows.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "multigrid/incore_vcycle.h"
#include "multigrid/row_kernels.h"

namespace gdp::multigrid {

void InputTotals::add(const InputTotals& t) {
  weighted_sums.resize(t.weighted_sums.size(), 0.0);
  rhs_norms2.resize(t.rhs_norms2.size(), 0.0);
  for (std::size_t c = 0; c < t.weighted_sums.size(); ++c) weighted_sums[c] += t.weighted_sums[c];
  for (std::size_t c = 0; c < t.rhs_norms2.size(); ++c) rhs_norms2[c] += t.rhs_norms2[c];
  weight_total += t.weight_total;
}

template <class T>
InputTotals InputRows<T>::totals() const {
  InputTotals all;
  for (const InputTotals& t : totals_) all.add(t);
  return all;
}

template <class T>
InputRows<T>::InputRows(GuidanceSource& source, const Hierarchy& hierarchy, std::vector<Range> sum_ranges,
                        Range columns, Reader read)
    : source_(source), read_row_(std::move(read)), width_(source.width()), height_(source.height()), channels_(source.channels()),
      assembler_(hierarchy.levels[0].x, hierarchy.levels[0].y, source.alpha(), source.channels()),
      initial_(kRing), counted_(kRing), b_(kRing), d_(kRing), dv_(kRing), begin_(columns.first),
      end_(columns.second < 0 ? width_ : columns.second), ranges_(std::move(sum_ranges)) {
  if (ranges_.empty()) ranges_.emplace_back(begin_, end_);
  if (begin_ < 0 || begin_ > end_ || end_ > width_) throw std::logic_error("InputRows: bad column window");
  for (const Range& r : ranges_)
    if (r.first < begin_ || r.first > r.second || r.second > end_) throw std::logic_error("InputRows: bad sum range");
  if (begin_ != 0 || end_ != width_) assembler_.set_columns(begin_, end_);
  totals_.assign(ranges_.size(), InputTotals{std::vector<double>(channels_, 0.0), std::vector<double>(channels_, 0.0), 0.0});
  const std::size_t n = static_cast<std::size_t>(channels_) * width_;
  row_.x_edges = hierarchy.levels[0].x.edges();
  row_.gx.assign(static_cast<std::size_t>(channels_) * row_.x_edges, 0.0);
  row_.gy.assign(n, 0.0);
  row_.spherical = hierarchy.levels[0].y.boundary == fem::AxisBoundary::Mirrored;
  row_.gy_above.assign(row_.spherical ? n : 0, 0.0);
  row_.value.assign(n, 0.0);
  row_.initial.assign(n, 0.0f);
  row_.counted.assign(width_, 1);
  if (source.has_weights()) row_.weight.assign(width_, 0.0);
  for (int k = 0; k < kRing; ++k) {
    if (source.has_weights()) {
      d_[k].assign(width_, 0.0);
      dv_[k].assign(n, 0.0);
    }
    initial_[k].assign(n, 0.0f);
    counted_[k].assign(width_, 1);
    b_[k].assign(n, T(0));
  }
}

template <class T>
void InputRows<T>::read_guidance() {
  const int j = read_++;
  std::fill(row_.counted.begin() + begin_, row_.counted.begin() + end_, 1);
  if (read_row_) read_row_(j, row_);
  else source_.read_row(j, row_);
  // Swapped, not copied: a source with a column window fills only its columns of them.
  if (source_.has_initial()) initial_[j % kRing].swap(row_.initial);
  counted_[j % kRing].swap(row_.counted);
  if (source_.has_weights()) {
    std::vector<double>&d = d_[j % kRing], &dv = dv_[j % kRing];
    for (int i = begin_; i < end_; ++i) {
      const double wt = row_.weight[i];
      bool finite = true;
      for (int c = 0; c < channels_; ++c) finite = finite && std::isfinite(row_.value[static_cast<std::size_t>(c) * width_ + i]);
      // No weight where there is no value to hold (blank pixels).
      d[i] = !finite || !(wt > 0.0) ? 0.0
             : wt >= kPinned       ? LevelOperator<T>::kPinnedDiagonal
                                   : LevelOperator<T>::kScale * wt;
      for (int c = 0; c < channels_; ++c) {
        const std::size_t k = static_cast<std::size_t>(c) * width_ + i;
        dv[k] = d[i] == 0.0 ? 0.0 : d[i] * row_.value[k];
      }
    }
  }
  // Scaled, the diagonal's d * value added, and converted as the assembler hands each row out.
  // The row next() is filling goes straight into its caller's b (no copy from the ring there).
  const auto sink = [this](int r, int c, std::span<const double> v) {
    const std::size_t at = static_cast<std::size_t>(c) * width_ + begin_;
    const double* add = source_.has_weights() ? dv_[r % kRing].data() + at : nullptr;
    T* to = r == direct_row_ ? direct_ : b_[r % kRing].data();
    scaled_rhs(v.data() + begin_, add, LevelOperator<T>::kScale, to + at, end_ - begin_);
    if (c == channels_ - 1) emitted_ = r + 1;
  };
  assembler_.push(j, row_, sink);
  if (read_ == height_) assembler_.finish(sink);
}

template <class T>
void InputRows<T>::next(std::span<T> u, std::span<T> b, std::span<T> w, std::span<T> d) {
  const int j = next_++;
  if (j >= height_) throw std::logic_error("InputRows::next past the last row");
  const bool ringed = emitted_ > j;  // made before this call (the last rows): in the ring
  direct_row_ = j;
  direct_ = b.data();
  while (emitted_ <= j) read_guidance();
  direct_row_ = -1;
  const int k = j % kRing;
  const bool weights = source_.has_weights();
  for (int c = 0; c < channels_ && ringed; ++c) {
    const std::size_t at = static_cast<std::size_t>(c) * width_;
    std::copy(b_[k].begin() + at + begin_, b_[k].begin() + at + end_, b.begin() + at + begin_);
  }
  if (weights)
    for (int i = begin_; i < end_; ++i) d[i] = static_cast<T>(d_[k][i]);
  // u: the starting guess, 0 where not finite; w: 1 where counted and every channel is finite.
  guess_and_weights(initial_[k].data() + begin_, width_, channels_, counted_[k].data() + begin_, u.data() + begin_,
                    w.data() + begin_, end_ - begin_);
  for (std::size_t r = 0; r < ranges_.size(); ++r) {
    const auto [a, e] = ranges_[r];
    for (int c = 0; c < channels_; ++c) {
      const std::size_t at = static_cast<std::size_t>(c) * width_;
      const T* bc = b.data() + at;
      totals_[r].weighted_sums[c] += row_dot(w.data() + a, u.data() + at + a, e - a);
      double& norm2 = totals_[r].rhs_norms2[c];
      // Pinned pixels' entries (kPinnedDiagonal * value) would swamp the norm that relative
      // residuals are measured against: they are left out of it.
      if (!weights) norm2 += row_squares(bc + a, e - a);
      else
        for (int i = a; i < e; ++i)
          if (d_[k][i] != LevelOperator<T>::kPinnedDiagonal) norm2 += static_cast<double>(bc[i]) * bc[i];
    }
    // A sum of ones and zeros, exact in any order: counted, then added.
    int ones = 0;
    for (int i = a; i < e; ++i) ones += w[i] != T(0);
    totals_[r].weight_total += ones;
  }
  if (!source_.start_from_initial())  // only the columns computed: other readers may fill the rest
    for (int c = 0; c < channels_; ++c)
      std::fill_n(u.begin() + static_cast<std::ptrdiff_t>(c) * width_ + begin_, end_ - begin_, T(0));
}

template class InputRows<float>;
template class InputRows<double>;

}  // namespace gdp::multigrid
