// The canvas sweep: layers opened and closed as rows pass, composite and across-seam rows from the label plane.
#include "blend/canvas_rows.h"
#include "blend/across_label.h"
#include "multigrid/masked.h"

#include <algorithm>
#include <exception>
#include <limits>
#include <numeric>

namespace gdp::blending {

CanvasSweep::CanvasSweep(const BlendPlan& plan, const LabelPlane& labels, bool wrap_x, bool across,
                         const KeptRows* kept)
    : plan_(plan), labels_(labels), kept_(kept), wrap_x_(wrap_x), with_across_(across), width_(plan.canvas.width),
      height_(plan.canvas.height), channels_(plan.colour_channels), order_(plan.layers.size()),
      slot_(plan.layers.size(), nullptr) {
  std::iota(order_.begin(), order_.end(), 0);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](int a, int b) { return footprint(plan, a).y0 < footprint(plan, b).y0; });
  for (auto& r : label_rows_) r.assign(width_, 0);
  none_.assign(width_, 0);
  edge_.assign(width_, 0);
  ring_.resize(kAhead);
  for (Row& r : ring_) {
    r.composite.assign(static_cast<std::size_t>(channels_) * width_, 0.0f);
    r.across.assign(across ? 2 * r.composite.size() : 0, std::numeric_limits<float>::quiet_NaN());
  }
}

CanvasSweep::~CanvasSweep() { restart(); }

void CanvasSweep::set_columns(int begin, int end) {
  if (columns_set_) {
    begin = std::min(begin, begin_);
    end = std::max(end, end_);
  }
  labels_.want_columns(begin, end);
  if (columns_set_ && begin == begin_ && end == end_) return;
  restart();  // before the producer's columns change
  begin_ = begin;
  end_ = end;
  columns_set_ = true;
}

void CanvasSweep::restart() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  if (producer_.joinable()) producer_.join();
}

const CanvasSweep::Row& CanvasSweep::row(int y) {
  if (y < held_) restart();
  std::unique_lock<std::mutex> lock(mutex_);
  if (!producer_.joinable()) {
    ready_ = -1;
    stop_ = false;
    error_ = nullptr;
    producer_ = std::thread([this] { produce(); });
  }
  held_ = y;
  changed_.notify_all();
  changed_.wait(lock, [&] { return ready_ >= y || error_; });
  if (ready_ < y) std::rethrow_exception(error_);
  return ring_[y % kAhead];
}

std::span<const float> CanvasSweep::composite(int y) { return row(y).composite; }

std::span<const float> CanvasSweep::across(int y) { return row(y).across; }

void CanvasSweep::produce() {
  open_.clear();
  std::fill(slot_.begin(), slot_.end(), nullptr);
  next_ = 0;
  row_ = -1;
  try {
    for (int y = 0; y < height_; ++y) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [&] { return stop_ || y < held_ + kAhead; });
        if (stop_) break;
      }
      advance(ring_[y % kAhead]);
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        ready_ = y;
      }
      changed_.notify_all();
    }
  } catch (...) {
    const std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  changed_.notify_all();
  open_.clear();  // the layers closed
}

void CanvasSweep::advance(Row& out) {
  const int y = ++row_, b = columns_set_ ? begin_ : 0, e = columns_set_ ? end_ : width_;
  if (y == 0) labels_.fill();  // deferred seams: before the layers open, so that they find those kept
  // Open the layers that start here and reach the columns wanted; close those that ended.
  for (; next_ < order_.size() && footprint(plan_, order_[next_]).y0 <= y; ++next_) {
    const int k = order_[next_];
    const Footprint f = footprint(plan_, k);
    if (f.y1 <= y || f.x1 <= b || f.x0 >= e) continue;
    auto o = std::make_unique<OpenLayer>(plan_, k, b, e, open_.size() < 8, kept_);
    slot_[k] = o.get();
    open_.push_back(std::move(o));
  }
  std::erase_if(open_, [&](const auto& o) {
    if (o->rows->where().y1 > y) return false;
    slot_[o->index] = nullptr;
    return true;
  });
  for (auto& o : open_) o->read(y);
  // Label rows y - 1, y, y + 1.
  if (y == 0) labels_.read_row(0, label_rows_[0]);
  if (y + 1 < height_) labels_.read_row(y + 1, label_rows_[(y + 1) % 3]);
  const std::span<const Label> here = label_rows_[y % 3];
  for (int x = b, run = b; x < e; x = run) {  // runs of one label: copied (or zeroed) per channel
    const Label l = here[x];
    while (run < e && here[run] == l) ++run;
    const OpenLayer* o = l ? slot_[l - 1] : nullptr;
    const int fx0 = o ? o->rows->where().x0 : 0, fw = o ? o->rows->where().width() : 0;
    for (int c = 0; c < channels_; ++c) {
      float* to = out.composite.data() + static_cast<std::size_t>(c) * width_;
      if (o) {
        const float* from = o->colour.data() + static_cast<std::size_t>(c) * fw - fx0;
        std::copy(from + x, from + run, to + x);
      } else {
        std::fill(to + x, to + run, 0.0f);
      }
    }
  }
  if (with_across_)
    compute_across(y > 0 ? std::span<const Label>(label_rows_[(y + 2) % 3]) : std::span<const Label>(),
                   here, y + 1 < height_ ? std::span<const Label>(label_rows_[(y + 1) % 3]) : std::span<const Label>(),
                   out);
}

// Per pixel two across values: of the layer its left and right neighbours carry (plane 0) and of
// the one its upper and lower neighbours carry (plane 1), so that where three layers meet each
// seam edge still finds the layer across it. NaN elsewhere: the ring's row is NaN but at the
// columns it was given last time (out.set), which are reset first.
void CanvasSweep::compute_across(std::span<const Label> up, std::span<const Label> here, std::span<const Label> down,
                                 Row& out) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::size_t plane = static_cast<std::size_t>(channels_) * width_;
  const int b = columns_set_ ? begin_ : 0, e = columns_set_ ? end_ : width_;
  for (const int x : out.set)
    for (int c = 0; c < 2 * channels_; ++c) out.across[static_cast<std::size_t>(c) * width_ + x] = nan;
  out.set.clear();
  const auto neighbour = [&](int x) -> Label {  // beyond the canvas's sides: none, unless it wraps
    return x >= 0 && x < width_ ? here[x] : wrap_x_ ? here[(x + width_) % width_] : Label{0};
  };
  const Label* u = up.empty() ? none_.data() : up.data();  // no row: no label
  const Label* d = down.empty() ? none_.data() : down.data();
  const Label* h = here.data();
  unsigned char* edge = edge_.data();
  // Whether pixel x, its left and right neighbours `l` and `r`, has another label beside it.
  const auto is_edge = [h, u, d](int x, Label l, Label r) {
    const auto other_than = [a = h[x]](Label n) { return static_cast<unsigned char>((n != 0) & (n != a)); };
    return static_cast<unsigned char>(static_cast<unsigned char>(h[x] != 0) &
                                      (other_than(l) | other_than(r) | other_than(u[x]) | other_than(d[x])));
  };
  // Vectorised; the first and last columns by neighbour(). The bounds are locals: the flags'
  // stores could alias the members.
  for (int x = std::max(b, 1), x_end = std::min(e, width_ - 1); x < x_end; ++x) edge[x] = is_edge(x, h[x - 1], h[x + 1]);
  for (const int x : {0, width_ - 1})
    if (x >= b && x < e) edge[x] = is_edge(x, neighbour(x - 1), neighbour(x + 1));
  const auto other = [](Label a, Label n1, Label n2) { return across_label(a, n1, n2, Label{0}); };
  multigrid::for_each_set(edge, b, e, [&](int x) {  // beside a seam (inside a layer's part: NaN)
    const Label across[2] = {other(h[x], neighbour(x - 1), neighbour(x + 1)), other(h[x], u[x], d[x])};
    for (int k = 0; k < 2; ++k) {
      const OpenLayer* o = across[k] ? slot_[across[k] - 1] : nullptr;
      const int fx0 = o ? o->rows->where().x0 : 0, fw = o ? o->rows->where().width() : 0;
      if (!o || x < fx0 || x >= fx0 + fw || !o->covered[x - fx0]) continue;
      if (out.set.empty() || out.set.back() != x) out.set.push_back(x);
      for (int c = 0; c < channels_; ++c)
        out.across[k * plane + static_cast<std::size_t>(c) * width_ + x] = o->colour[static_cast<std::size_t>(c) * fw + x - fx0];
    }
  });
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
