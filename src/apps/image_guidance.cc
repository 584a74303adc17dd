// Differences of streamed image rows as guidance; non-finite samples (FITS blanks) give no guidance.
#include "apps/image_guidance.h"

#include <algorithm>
#include <cmath>

#include "multigrid/masked.h"
#include "multigrid/row_kernels.h"

namespace gdp::apps {

ImageGuidance::ImageGuidance(RowReader& source, double alpha, double beta, bool start_from_source)
    : src_(source), width_(source.width()), height_(source.height()), channels_(source.channels()), alpha_(alpha),
      beta_(beta), start_(start_from_source) {
  set_slots(2);
}

void ImageGuidance::set_columns(int begin, int end) {
  src_.set_columns(begin, std::min(end + 1, width()));
  begin_ = begin;
  end_ = end;
}

void ImageGuidance::set_slots(int slots) {
  rows_.assign(slots, std::vector<float>(static_cast<std::size_t>(channels()) * width(), 0.0f));
}

void ImageGuidance::decode(int y) {
  src_.read_row(y, rows_[slot(y)]);
  on_source_row(y, rows_[slot(y)]);
}

void ImageGuidance::read_row(int j, GuidanceRow& out) {
  if (j == 0) decode(0);
  if (j + 1 < height()) decode(j + 1);
  compute(j, out, column_begin(), column_end());
}

namespace {

// The indices i in [begin, end) where keep[i] (and mark[i] unless mark is empty) are set, into
// `at`: offsets are asked at these edges only, a list made once per row for every channel. The
// sparser flags (the marks where there are any) are walked, eight clear ones at a time.
void edges_to_ask(std::span<const unsigned char> keep, std::span<const unsigned char> mark, int begin, int end,
                  std::vector<int>& at) {
  at.clear();
  multigrid::for_each_set(mark.empty() ? keep.data() : mark.data(), begin, end, [&](int i) {
    if (keep[i] && (mark.empty() || mark[i])) at.push_back(i);
  });
}

}  // namespace

void ImageGuidance::compute(int j, GuidanceRow& out, int x0, int x1) const {
  const int w = width(), h = height(), e = out.x_edges;
  const bool fold_top = out.spherical && j == 0, fold_bottom = out.spherical && j + 1 == h;
  // Per-edge flags in out.edges: right, down, up (above), and where offsets are asked, right and down.
  out.edges.resize(static_cast<std::size_t>(5) * w);
  const auto flags = [&](int k, int n) {
    return std::span<unsigned char>(out.edges.data() + static_cast<std::size_t>(k) * w, n);
  };
  const std::span<unsigned char> right = flags(0, w), down = flags(1, w), up = flags(2, fold_top ? w : 0);
  const std::span<unsigned char> offset_right = flags(3, w), offset_down = flags(4, w);
  std::fill(right.begin() + x0, right.begin() + x1, 1);
  std::fill(down.begin() + x0, down.begin() + x1, j + 1 < h || fold_bottom ? 1 : 0);
  std::fill(up.begin(), up.end(), 1);
  keep_edges(j, x0, x1, right, down, up);
  // Horizontal edges [x0, ex): to the row's last where the columns reach its end.
  const int ex = x1 == w ? e : std::min(e, x1 - 1);
  // The edges whose offset is asked (per thread: rows are computed on several at once).
  thread_local std::vector<int> ask_right, ask_down;
  ask_right.clear();
  ask_down.clear();
  if (has_offsets()) {
    std::fill(offset_right.begin() + x0, offset_right.begin() + x1, 0);
    std::fill(offset_down.begin() + x0, offset_down.begin() + x1, 0);
    const bool marked = offset_edges(j, x0, x1, offset_right, offset_down);  // else: at every kept edge
    edges_to_ask(right, marked ? offset_right : std::span<unsigned char>(), x0, ex, ask_right);
    if (j + 1 < h) edges_to_ask(down, marked ? offset_down : std::span<unsigned char>(), x0, x1, ask_down);
  }
  const std::span<const float> here = source_row(j);
  for (int c = 0; c < channels(); ++c) {
    const float* row = here.data() + static_cast<std::size_t>(c) * w;
    double* gx = out.gx.data() + static_cast<std::size_t>(c) * e;
    const int inner = std::min(ex, w - 1);  // edges to the next column; a periodic row's last wraps
    if (x0 < inner) multigrid::kept_differences(row + x0, row + x0 + 1, right.data() + x0, beta_, gx + x0, inner - x0);
    for (int i = std::max(x0, inner); i < ex; ++i)
      multigrid::kept_differences(row + i, row, right.data() + i, beta_, gx + i, 1);
    for (const int i : ask_right)
      if (std::isfinite(double(row[i + 1 < w ? i + 1 : 0]) - row[i])) gx[i] -= offset(c, i, j, true);
    if (j + 1 < h) {
      const float* next = source_row(j + 1).data() + static_cast<std::size_t>(c) * w;
      double* gy = out.gy.data() + static_cast<std::size_t>(c) * w;
      multigrid::kept_differences(row + x0, next + x0, down.data() + x0, beta_, gy + x0, x1 - x0);
      for (const int i : ask_down)
        if (std::isfinite(double(next[i]) - row[i])) gy[i] -= offset(c, i, j, false);
    }
    // Across the folded edges of a spherical domain (no offsets: a per-label ramp has no
    // direction there).
    const auto fold = [&](double* g, std::span<const unsigned char> keep, auto partner, bool into_row) {
      for (int i = 0; i < w; ++i) {
        const double d = into_row ? double(row[i]) - row[partner(i)] : double(row[partner(i)]) - row[i];
        g[i] = std::isfinite(d) && keep[i] ? beta_ * d : 0.0;
      }
    };
    if (fold_bottom) fold(out.gy.data() + static_cast<std::size_t>(c) * w, down, [&](int i) { return below(i, j); }, false);
    if (fold_top) fold(out.gy_above.data() + static_cast<std::size_t>(c) * w, up, [&](int i) { return above(i); }, true);
    if (alpha_ != 0.0)
      for (int i = x0; i < x1; ++i) out.value[c * w + i] = std::isfinite(row[i]) ? row[i] : 0.0;
    std::copy(row + x0, row + x1, out.initial.begin() + static_cast<std::ptrdiff_t>(c) * w + x0);
  }
}

}  // namespace gdp::apps
