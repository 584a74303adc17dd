// Differences of streamed image rows as guidance; non-finite samples (FITS blanks) give no guidance.
#include "apps/image_guidance.h"

#include <algorithm>
#include <cmath>

namespace gdp::apps {

ImageGuidance::ImageGuidance(RowReader& source, double alpha, double beta, bool start_from_source)
    : src_(source), width_(source.width()), height_(source.height()), channels_(source.channels()), alpha_(alpha),
      beta_(beta), start_(start_from_source) {
  for (auto& r : rows_) r.assign(static_cast<std::size_t>(source.channels()) * source.width(), 0.0f);
}

void ImageGuidance::set_columns(int begin, int end) {
  src_.set_columns(begin, std::min(end + 1, width()));
  begin_ = begin;
  end_ = end;
}

void ImageGuidance::read_source(int y) {
  src_.read_row(y, rows_[y % 2]);
  on_source_row(y, rows_[y % 2]);
}

void ImageGuidance::read_row(int j, GuidanceRow& out) {
  const int w = width(), h = height(), e = out.x_edges;
  if (j == 0) read_source(0);
  if (j + 1 < h) read_source(j + 1);
  const bool fold_top = out.spherical && j == 0, fold_bottom = out.spherical && j + 1 == h;
  right_.assign(w, 1);
  down_.assign(w, j + 1 < h || fold_bottom ? 1 : 0);
  above_.assign(fold_top ? w : 0, 1);
  keep_edges(j, right_, down_, above_);
  const bool offsets = has_offsets();
  bool marked = false;  // offsets only at the edges offset_edges marks
  if (offsets) {
    offset_right_.assign(w, 0);
    offset_down_.assign(w, 0);
    marked = offset_edges(j, offset_right_, offset_down_);
  }
  const auto ask = [&](const std::vector<unsigned char>& keep, const std::vector<unsigned char>& mark, int i) {
    return keep[i] && (!marked || mark[i]);
  };
  const std::span<const float> here = source_row(j);
  // The columns computed: [x0, x1) of values and vertical edges, [x0, ex) of horizontal ones.
  const int x0 = column_begin(), x1 = column_end(), ex = end_ < 0 ? e : std::min(e, end_ - 1);
  for (int c = 0; c < channels(); ++c) {
    const float* row = here.data() + static_cast<std::size_t>(c) * w;
    double* gx = out.gx.data() + static_cast<std::size_t>(c) * e;
    // d - d == 0 exactly when d is finite: a test the compiler vectorises (std::isfinite is not).
    const auto kept = [&](double d, unsigned char keep) { return d - d == 0.0 && keep ? beta_ * d : 0.0; };
    const int inner = std::min(ex, w - 1);  // edges to the next column; a periodic row's last wraps
    for (int i = x0; i < inner; ++i) gx[i] = kept(double(row[i + 1]) - row[i], right_[i]);
    for (int i = std::max(x0, inner); i < ex; ++i) gx[i] = kept(double(row[0]) - row[i], right_[i]);
    if (offsets)
      for (int i = x0; i < ex; ++i)
        if (ask(right_, offset_right_, i) && std::isfinite(double(row[i + 1 < w ? i + 1 : 0]) - row[i]))
          gx[i] -= offset(c, i, j, true);
    if (j + 1 < h) {
      const float* next = source_row(j + 1).data() + static_cast<std::size_t>(c) * w;
      double* gy = out.gy.data() + static_cast<std::size_t>(c) * w;
      for (int i = x0; i < x1; ++i) gy[i] = kept(double(next[i]) - row[i], down_[i]);
      if (offsets)
        for (int i = x0; i < x1; ++i)
          if (ask(down_, offset_down_, i) && std::isfinite(double(next[i]) - row[i])) gy[i] -= offset(c, i, j, false);
    }
    // Across the folded edges of a spherical domain (no offsets: a per-label ramp has no
    // direction there).
    const auto fold = [&](double* g, const std::vector<unsigned char>& keep, auto partner, bool into_row) {
      for (int i = 0; i < w; ++i) {
        const double d = into_row ? double(row[i]) - row[partner(i)] : double(row[partner(i)]) - row[i];
        g[i] = std::isfinite(d) && keep[i] ? beta_ * d : 0.0;
      }
    };
    if (fold_bottom) fold(out.gy.data() + static_cast<std::size_t>(c) * w, down_, [&](int i) { return below(i, j); }, false);
    if (fold_top) fold(out.gy_above.data() + static_cast<std::size_t>(c) * w, above_, [&](int i) { return above(i); }, true);
    if (alpha_ != 0.0)
      for (int i = x0; i < x1; ++i) out.value[c * w + i] = std::isfinite(row[i]) ? row[i] : 0.0;
    std::copy(row + x0, row + x1, out.initial.begin() + static_cast<std::ptrdiff_t>(c) * w + x0);
  }
}

}  // namespace gdp::apps
