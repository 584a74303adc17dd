// The depth seams: a forward chamfer pass per layer into scratch, a backward pass that picks the deepest layer per pixel.
#include "blend/seams.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "blend/layer_rows.h"
#include "gdp/errors.h"

namespace gdp::blending {
namespace {

constexpr float kInf = 1e30f;
constexpr float kA = 1.0f, kB = 1.41421356f, kC = 2.23606798f;
constexpr int kPad = 2;

// A row of distances with two padding columns on either side.
struct PaddedRow {
  std::vector<float> v;
  float* at() { return v.data() + kPad; }
  const float* at() const { return v.data() + kPad; }
};

// How a layer's distance rows meet what lies beyond them.
struct Edges {
  int width = 0;
  bool periodic = false;        // spans a horizontally wrapped canvas: the row wraps onto itself
  float left = 0, right = 0;    // beyond its first and last column: 0 (uncovered canvas) or kInf (no canvas)
  float above = 0, below = 0;   // beyond its first and last row
  void pad(PaddedRow& r) const {
    float* p = r.at();
    for (int k = 1; k <= kPad; ++k) {
      p[-k] = periodic ? p[width - k] : left;
      p[width - 1 + k] = periodic ? p[k - 1] : right;
    }
  }
  PaddedRow outside(bool top) const {
    PaddedRow r{std::vector<float>(width + 2 * kPad, top ? above : below)};
    return r;
  }
};

Edges edges_of(const Footprint& f, int canvas_w, int canvas_h, bool wrap_x) {
  Edges e;
  e.width = f.width();
  e.periodic = wrap_x && f.x0 == 0 && f.x1 == canvas_w;
  e.left = f.x0 > 0 || wrap_x ? 0.0f : kInf;
  e.right = f.x1 < canvas_w || wrap_x ? 0.0f : kInf;
  e.above = f.y0 > 0 ? 0.0f : kInf;
  e.below = f.y1 < canvas_h ? 0.0f : kInf;
  return e;
}

// One pass over a row: `near` the previous row in the pass's direction, `far` the one before;
// dir +1 scans left to right (forward pass), -1 right to left (backward). `base[x]` is 0 for an
// uncovered pixel (stays 0) or the starting value.
void chamfer_row(const Edges& e, int dir, const float* base, const PaddedRow& near, const PaddedRow& far,
                 PaddedRow& out) {
  const int w = e.width;
  float* d = out.at();
  const float* n = near.at();
  const float* f = far.at();
  d[-1] = e.periodic ? kInf : e.left;  // behind the first pixel scanned (a periodic row: the second lap)
  d[w] = e.periodic ? kInf : e.right;
  const int start = dir > 0 ? 0 : w - 1;
  for (int k = 0, x = start; k < w; ++k, x += dir) {
    if (base[x] <= 0.0f) {
      d[x] = 0.0f;
      continue;
    }
    float v = std::min({base[x], d[x - dir] + kA, n[x] + kA, n[x - 1] + kB, n[x + 1] + kB});
    v = std::min({v, n[x - 2] + kC, n[x + 2] + kC, f[x - 1] + kC, f[x + 1] + kC});
    d[x] = v;
  }
  if (e.periodic) {  // a second lap carries distances across the wrap
    for (int k = 0, x = start; k < w; ++k, x += dir) {
      const int behind = ((x - dir) % w + w) % w;
      const float v = std::min(d[x], d[behind] + kA);
      if (v == d[x]) break;
      d[x] = v;
    }
  }
  e.pad(out);
}

struct Active {
  int index;
  Footprint where;
  Edges edges;
  std::size_t base;  // byte offset of its first-pass rows in the scratch
  std::unique_ptr<LayerRows> rows;
  PaddedRow near, far, cur;
  std::vector<float> start;
  std::vector<unsigned char> covered;
  std::size_t offset(int y) const { return base + static_cast<std::size_t>(y - where.y0) * where.width() * sizeof(float); }
};

// The two passes over the canvas, sharing the layers' footprints and the distance scratch.
class SeamPasses {
 public:
  // Only the layers whose footprints meet columns [begin, end) take part.
  SeamPasses(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
             const std::function<void(double)>& progress, int begin, int end)
      : plan_(plan), wrap_x_(wrap_x), progress_(progress), n_(static_cast<int>(plan.layers.size())),
        W_(plan.canvas.width), H_(plan.canvas.height), where_(n_), base_(n_ + 1, 0) {
    for (int k = 0; k < n_; ++k) {
      where_[k] = footprint(plan, k);
      const bool meets = where_[k].x0 < end && where_[k].x1 > begin;
      if (meets) taking_part_.push_back(k);
      const std::size_t rows = meets ? where_[k].y1 - where_[k].y0 : 0;
      base_[k + 1] = base_[k] + static_cast<std::size_t>(where_[k].width()) * rows * sizeof(float);
    }
    distances_ = std::make_unique<Scratch>(temp_dir, base_[n_], "distances");
  }
  std::size_t scratch_bytes() const { return distances_->bytes(); }
  const std::vector<int>& taking_part() const { return taking_part_; }
  void forward();
  void backward(LabelPlane& labels, std::vector<signed char>& overlaps);

 private:
  // Layer k's state for a pass that starts beyond its top (forward) or bottom row.
  std::unique_ptr<Active> start(int k, bool top) const {
    auto a = std::make_unique<Active>();
    a->index = k;
    a->where = where_[k];
    a->edges = edges_of(where_[k], W_, H_, wrap_x_);
    a->base = base_[k];
    a->near = a->far = a->edges.outside(top);
    a->cur.v.assign(where_[k].width() + 2 * kPad, 0.0f);
    a->start.resize(where_[k].width());
    return a;
  }
  // Layers taking part by the row a pass meets them first.
  std::vector<int> order(bool top) const {
    std::vector<int> o = taking_part_;
    std::stable_sort(o.begin(), o.end(),
                     [&](int a, int b) { return top ? where_[a].y0 < where_[b].y0 : where_[a].y1 > where_[b].y1; });
    return o;
  }
  void report(double f) const {
    if (progress_) progress_(f);
  }

  const BlendPlan& plan_;
  bool wrap_x_;
  const std::function<void(double)>& progress_;
  int n_, W_, H_;
  std::vector<Footprint> where_;
  std::vector<std::size_t> base_;
  std::vector<int> taking_part_;
  std::unique_ptr<Scratch> distances_;
};

// Top to bottom: each layer opened at its first row, its forward distances into the scratch,
// closed after its last row.
void SeamPasses::forward() {
  const std::vector<int> by_top = order(true);
  std::vector<std::unique_ptr<Active>> active;
  std::size_t next = 0;
  for (int y = 0; y < H_; ++y) {
    for (; next < by_top.size() && where_[by_top[next]].y0 == y; ++next) {
      auto a = start(by_top[next], true);
      a->rows = std::make_unique<LayerRows>(plan_, a->index, 0, W_, active.size() < 8);
      a->covered.resize(a->where.width());
      active.push_back(std::move(a));
    }
    for (auto& a : active) {
      const int w = a->where.width();
      a->rows->coverage(y, a->covered);  // the depth needs only where the layer is
      for (int x = 0; x < w; ++x) a->start[x] = a->covered[x] ? kInf : 0.0f;
      chamfer_row(a->edges, 1, a->start.data(), a->near, a->far, a->cur);
      distances_->write(a->offset(y), a->cur.at(), w * sizeof(float));
      std::swap(a->far, a->near);
      std::swap(a->near, a->cur);
    }
    std::erase_if(active, [&](const auto& a) { return a->where.y1 == y + 1; });
    report(0.5 * (y + 1) / H_);
  }
}

// Bottom to top: final distances, the deepest layer per pixel into `labels`; `overlaps` marks
// layers some of whose pixels another layer covers too.
void SeamPasses::backward(LabelPlane& labels, std::vector<signed char>& overlaps) {
  const std::vector<int> by_bottom = order(false);
  std::vector<std::unique_ptr<Active>> active;  // by layer index: ties go to the earlier layer
  std::size_t next = 0;
  std::vector<float> best(W_);
  std::vector<Label> label(W_);
  std::vector<unsigned char> count(W_);
  for (int y = H_ - 1; y >= 0; --y) {
    for (; next < by_bottom.size() && where_[by_bottom[next]].y1 == y + 1; ++next) {
      auto a = start(by_bottom[next], false);
      const auto at = std::upper_bound(active.begin(), active.end(), a->index,
                                       [](int v, const auto& b) { return v < b->index; });
      active.insert(at, std::move(a));
    }
    std::fill(best.begin(), best.end(), 0.0f);
    std::fill(label.begin(), label.end(), Label{0});
    std::fill(count.begin(), count.end(), 0);
    for (auto& a : active) {
      const int w = a->where.width(), x0 = a->where.x0;
      distances_->read(a->offset(y), a->start.data(), w * sizeof(float));
      chamfer_row(a->edges, -1, a->start.data(), a->near, a->far, a->cur);
      const float* d = a->cur.at();
      for (int x = 0; x < w; ++x) {
        if (d[x] <= 0.0f) continue;
        count[x0 + x] = static_cast<unsigned char>(std::min(2, count[x0 + x] + 1));
        if (d[x] > best[x0 + x]) {
          best[x0 + x] = d[x];
          label[x0 + x] = static_cast<Label>(a->index + 1);
        }
      }
      std::swap(a->far, a->near);
      std::swap(a->near, a->cur);
    }
    for (auto& a : active) {
      const float* d = a->near.at();  // this row's final distances
      for (int x = 0; x < a->where.width() && !overlaps[a->index]; ++x)
        if (d[x] > 0.0f && count[a->where.x0 + x] > 1) overlaps[a->index] = 1;
    }
    labels.write_row(y, label);
    std::erase_if(active, [&](const auto& a) { return a->where.y0 == y; });
    report(0.5 + 0.5 * (H_ - y) / H_);
  }
}

}  // namespace

LabelPlane::LabelPlane(const std::filesystem::path& dir, int width, int height)
    : width_(width), height_(height),
      scratch_(dir, static_cast<std::size_t>(width) * height * sizeof(Label), "labels") {}

void LabelPlane::write_row(int y, std::span<const Label> row) {
  scratch_.write(static_cast<std::size_t>(y) * width_ * sizeof(Label), row.data(), width_ * sizeof(Label));
}

void LabelPlane::read_row(int y, std::span<Label> row, int begin, int end) const {
  fill();
  if (end < 0) end = width_;
  scratch_.read((static_cast<std::size_t>(y) * width_ + begin) * sizeof(Label), row.data() + begin,
                static_cast<std::size_t>(end - begin) * sizeof(Label));
}

void LabelPlane::want_columns(int begin, int end) const {
  if (end < 0) end = width_;
  if (want_end_ == 0) {
    want_begin_ = begin;
    want_end_ = end;
  }
  want_begin_ = std::min(want_begin_, begin);
  want_end_ = std::max(want_end_, end);
}

void LabelPlane::fill() const {
  if (filled_.load(std::memory_order_acquire)) return;
  const std::lock_guard<std::mutex> lock(fill_mutex_);
  if (filled_.load(std::memory_order_relaxed) || !fill_) return;
  const Fill f = std::move(fill_);
  fill_ = nullptr;
  f(const_cast<LabelPlane&>(*this), want_end_ > 0 ? want_begin_ : 0, want_end_ > 0 ? want_end_ : width_);
  filled_.store(true, std::memory_order_release);
}

SeamColumns compute_seam_columns(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                                 const std::function<void(double)>& progress, int begin, int end, LabelPlane& labels,
                                 std::vector<signed char>& overlaps) {
  const int n = static_cast<int>(plan.layers.size());
  if (n > kMaxLayers) throw UsageError(fmt::format("{} layers; gdp blend takes at most {}", n, kMaxLayers));
  SeamPasses passes(plan, wrap_x, temp_dir, progress, begin, end);
  overlaps.assign(n, 0);
  passes.forward();
  passes.backward(labels, overlaps);
  // A layer taking part is checked against every layer meeting the columns: where it reaches
  // outside them a layer that did not take part may overlap it there (gather_overlaps then asks
  // the processes solving those columns).
  std::vector<char> part(n, 0);
  for (const int k : passes.taking_part()) part[k] = 1;
  for (int k = 0; k < n; ++k)
    if (!part[k]) overlaps[k] = -1;
  return {static_cast<int>(passes.taking_part().size()), passes.scratch_bytes()};
}

SeamResult compute_seams(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                         const std::function<void(double)>& progress) {
  SeamResult result;
  result.labels = std::make_unique<LabelPlane>(temp_dir, plan.canvas.width, plan.canvas.height);
  const SeamColumns done =
      compute_seam_columns(plan, wrap_x, temp_dir, progress, 0, plan.canvas.width, *result.labels, result.overlaps);
  result.layers_read = done.layers_read;
  result.scratch_bytes = done.distance_bytes + result.labels->bytes();
  return result;
}

}  // namespace gdp::blending
