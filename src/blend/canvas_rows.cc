// The canvas sweep: layers opened and closed as rows pass, composite and across-seam rows from the label plane.
#include "blend/canvas_rows.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace gdp::blending {

struct CanvasSweep::Open {
  int index;
  std::unique_ptr<LayerRows> rows;
  std::vector<float> colour;
  std::vector<unsigned char> covered;
};

CanvasSweep::CanvasSweep(const BlendPlan& plan, const LabelPlane& labels, bool wrap_x, bool across)
    : plan_(plan), labels_(labels), wrap_x_(wrap_x), with_across_(across), width_(plan.canvas.width),
      height_(plan.canvas.height), channels_(plan.colour_channels), order_(plan.layers.size()),
      slot_(plan.layers.size(), nullptr) {
  std::iota(order_.begin(), order_.end(), 0);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](int a, int b) { return footprint(plan, a).y0 < footprint(plan, b).y0; });
  for (auto& r : label_rows_) r.assign(width_, 0);
  composite_.assign(static_cast<std::size_t>(channels_) * width_, 0.0f);
  if (across) across_.assign(2 * composite_.size(), std::numeric_limits<float>::quiet_NaN());
}

CanvasSweep::~CanvasSweep() = default;

void CanvasSweep::set_columns(int begin, int end) {
  if (columns_set_) {
    begin = std::min(begin, begin_);
    end = std::max(end, end_);
  }
  labels_.want_columns(begin, end);
  if (columns_set_ && begin == begin_ && end == end_) return;
  begin_ = begin;
  end_ = end;
  columns_set_ = true;
  restart();
}

void CanvasSweep::restart() {
  open_.clear();
  std::fill(slot_.begin(), slot_.end(), nullptr);
  next_ = 0;
  row_ = -1;
}

std::span<const float> CanvasSweep::composite(int y) {
  if (y < row_) restart();
  while (row_ < y) advance();
  return composite_;
}

std::span<const float> CanvasSweep::across(int y) {
  composite(y);
  return across_;
}

void CanvasSweep::advance() {
  const int y = ++row_, b = columns_set_ ? begin_ : 0, e = columns_set_ ? end_ : width_;
  // Open the layers that start here and reach the columns wanted; close those that ended.
  for (; next_ < order_.size() && footprint(plan_, order_[next_]).y0 <= y; ++next_) {
    const int k = order_[next_];
    const Footprint f = footprint(plan_, k);
    if (f.y1 <= y || f.x1 <= b || f.x0 >= e) continue;
    auto o = std::make_unique<Open>();
    o->index = k;
    o->rows = std::make_unique<LayerRows>(plan_, k, b, e, open_.size() < 8);
    o->colour.resize(static_cast<std::size_t>(channels_) * f.width());
    o->covered.resize(f.width());
    slot_[k] = o.get();
    open_.push_back(std::move(o));
  }
  std::erase_if(open_, [&](const auto& o) {
    if (o->rows->where().y1 > y) return false;
    slot_[o->index] = nullptr;
    return true;
  });
  for (auto& o : open_) o->rows->read(y, o->colour, o->covered);
  // Label rows y - 1, y, y + 1.
  if (y == 0) labels_.read_row(0, label_rows_[0]);
  if (y + 1 < height_) labels_.read_row(y + 1, label_rows_[(y + 1) % 3]);
  const std::span<const Label> here = label_rows_[y % 3];
  for (int x = b; x < e; ++x) {
    const Label l = here[x];
    const Open* o = l ? slot_[l - 1] : nullptr;
    const int fx0 = o ? o->rows->where().x0 : 0, fw = o ? o->rows->where().width() : 0;
    for (int c = 0; c < channels_; ++c)
      composite_[static_cast<std::size_t>(c) * width_ + x] = o ? o->colour[static_cast<std::size_t>(c) * fw + x - fx0] : 0.0f;
  }
  if (with_across_)
    compute_across(y > 0 ? std::span<const Label>(label_rows_[(y + 2) % 3]) : std::span<const Label>(),
                   here, y + 1 < height_ ? std::span<const Label>(label_rows_[(y + 1) % 3]) : std::span<const Label>());
}

// Per pixel two across values: of the layer its left and right neighbours carry (plane 0) and of
// the one its upper and lower neighbours carry (plane 1), so that where three layers meet each
// seam edge still finds the layer across it. Only seam pixels are written; those of the row
// before are reset to NaN first.
void CanvasSweep::compute_across(std::span<const Label> up, std::span<const Label> here, std::span<const Label> down) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::size_t plane = static_cast<std::size_t>(channels_) * width_;
  for (const int x : across_written_)
    for (int c = 0; c < 2 * channels_; ++c) across_[static_cast<std::size_t>(c) * width_ + x] = nan;
  across_written_.clear();
  const int b = columns_set_ ? begin_ : 0, e = columns_set_ ? end_ : width_;
  // The one label other than `a` (and not 0) among two neighbours; 0 if none or two different.
  const auto other = [](Label a, Label n1, Label n2) -> Label {
    const bool o1 = n1 != 0 && n1 != a, o2 = n2 != 0 && n2 != a;
    if (o1 && o2) return n1 == n2 ? n1 : Label{0};
    return o1 ? n1 : o2 ? n2 : Label{0};
  };
  for (int x = b; x < e; ++x) {
    const Label a = here[x];
    if (a == 0) continue;
    const Label left = x > 0 || wrap_x_ ? here[x > 0 ? x - 1 : width_ - 1] : Label{0};
    const Label right = x + 1 < width_ || wrap_x_ ? here[x + 1 < width_ ? x + 1 : 0] : Label{0};
    const Label h = other(a, left, right), v = other(a, up.empty() ? Label{0} : up[x], down.empty() ? Label{0} : down[x]);
    if (h == 0 && v == 0) continue;
    across_written_.push_back(x);
    const Label across[2] = {h, v};
    for (int d = 0; d < 2; ++d) {
      const Open* o = across[d] ? slot_[across[d] - 1] : nullptr;
      const int fx0 = o ? o->rows->where().x0 : 0, fw = o ? o->rows->where().width() : 0;
      if (!o || x < fx0 || x >= fx0 + fw || !o->covered[x - fx0]) continue;
      for (int c = 0; c < channels_; ++c)
        across_[d * plane + static_cast<std::size_t>(c) * width_ + x] = o->colour[static_cast<std::size_t>(c) * fw + x - fx0];
    }
  }
}

void SweepReader::read_row(int y, std::span<float> out) {
  const std::span<const float> row = across_ ? sweep_.across(y) : sweep_.composite(y);
  std::copy(row.begin(), row.end(), out.begin());
}

void LabelReader::read_row(int y, std::span<float> out) {
  const int b = begin_, e = end_ < 0 ? labels_.width() : end_;
  labels_.read_row(y, row_, b, e);
  for (int x = b; x < e; ++x) out[x] = row_[x] ? -static_cast<float>(row_[x]) : 1.0f;
}

}  // namespace gdp::blending
