// The depth seams: a forward chamfer pass per layer into scratch, a backward pass that picks the deepest layer per pixel.
#include "blend/seams.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>

#include <fmt/format.h>

#include "blend/layer_rows.h"
#include "blend/scratch.h"
#include "gdp/errors.h"
#include "util/workers.h"

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
// uncovered pixel (stays 0) or the starting value. First the paths through the rows before, for
// the whole row at once (vectorised), then the one along the row, pixel after pixel: the same
// minimum of the same sums as taking all nine terms per pixel, so the same floats.
void chamfer_row(const Edges& e, int dir, const float* base, const PaddedRow& near, const PaddedRow& far,
                 PaddedRow& out) {
  const int w = e.width;
  float* __restrict d = out.at();
  const float* __restrict n = near.at();
  const float* __restrict f = far.at();
  for (int x = 0; x < w; ++x) {
    float v = std::min({base[x], n[x] + kA, n[x - 1] + kB, n[x + 1] + kB});
    v = std::min({v, n[x - 2] + kC, n[x + 2] + kC, f[x - 1] + kC, f[x + 1] + kC});
    d[x] = base[x] <= 0.0f ? 0.0f : v;
  }
  // Behind the first pixel scanned (a periodic row: the second lap). An uncovered pixel stays 0:
  // what comes along the row is at least kA.
  float behind = e.periodic ? kInf : dir > 0 ? e.left : e.right;
  const int start = dir > 0 ? 0 : w - 1;
  for (int k = 0, x = start; k < w; ++k, x += dir) behind = d[x] = std::min(d[x], behind + kA);
  if (e.periodic) {  // a second lap carries distances across the wrap
    for (int k = 0, x = start; k < w; ++k, x += dir) {
      const int back = ((x - dir) % w + w) % w;
      const float v = std::min(d[x], d[back] + kA);
      if (v == d[x]) break;
      d[x] = v;
    }
  }
  e.pad(out);
}

// Runs body(worker, i) for i in [0, n) on up to `threads` workers, each taking the next i; the
// first failure sets `stop` (bodies may watch it), no more are taken, and it is rethrown here.
void parallel_for(int threads, int n, std::atomic<bool>& stop, const std::function<void(int, int)>& body) {
  if (n <= 0) return;
  std::atomic<int> next{0};
  util::run_workers(
      std::clamp(threads, 1, n),
      [&](int t) {
        for (int i = 0; !stop.load(std::memory_order_relaxed) && (i = next.fetch_add(1)) < n;) body(t, i);
      },
      [&](int, const std::string&) { stop = true; });
}

// A layer in the backward pass: its chamfer rows and its final distances for the current block.
struct Active {
  int index;
  Footprint where;
  Edges edges;
  PaddedRow near, far, cur;  // the pass's rows before the current one, and the current one
  std::vector<float> block;  // rows [block_lo, ...) of the block, first-pass then final distances
  int block_lo = 0;
  const float* final_row(int y) const { return block.data() + static_cast<std::size_t>(y - block_lo) * where.width(); }
};

// What the forward pass keeps of a layer for the backward pass, which goes through the rows in
// blocks from the bottom: its coverage, a bit a pixel, and at each block's first row the pass's
// two rows before it (its state there). The backward pass computes a block's first-pass distances
// again from them, the same floats as the forward pass's, so that 4 bytes a pixel of distances
// need not be written and read back (a bit a pixel plus two rows a block, 1/16 of it at 64 rows).
class ForwardKept {
  static_assert(std::endian::native == std::endian::little, "flags are packed eight at a time as one integer");

 public:
  // Blocks of `rows` rows end at the canvas's height `height` (the last block may be shorter).
  ForwardKept(const std::vector<Footprint>& where, const std::vector<int>& taking_part, int height, int rows,
              const std::filesystem::path& temp_dir)
      : where_(where), height_(height), rows_(rows), bits_at_(where.size(), 0), states_at_(where.size(), 0) {
    std::size_t bits = 0, states = 0;
    for (const int k : taking_part) {
      bits_at_[k] = bits;
      states_at_[k] = states;
      const Footprint& f = where[k];
      bits += row_bits(k) * static_cast<std::size_t>(f.y1 - f.y0);
      states += 2 * padded(k) * sizeof(float) * static_cast<std::size_t>(states_in(k));
    }
    bits_ = std::make_unique<Scratch>(temp_dir, bits, "coverage");
    states_ = std::make_unique<Scratch>(temp_dir, states, "forward states");
  }
  std::size_t bytes() const { return bits_->bytes() + states_->bytes(); }
  // Whether a block starts at row y of layer k below its first row (the pass's state is kept there).
  bool block_starts(int k, int y) const { return y > where_[k].y0 && (height_ - y) % rows_ == 0; }
  // Layer k's coverage of row y (a 0 or 1 per pixel) kept.
  void write_coverage(int k, int y, const unsigned char* covered, std::vector<unsigned char>& packed) const {
    const int w = where_[k].width();
    packed.assign(row_bits(k), 0);
    for (int i = 0; i < w / 8; ++i) {  // eight flags (bytes 0 or 1) into the bits of one byte
      std::uint64_t v;
      std::memcpy(&v, covered + 8 * i, 8);
      packed[i] = static_cast<unsigned char>((v * 0x0102040810204080u) >> 56);
    }
    for (int x = w / 8 * 8; x < w; ++x) packed[x >> 3] |= static_cast<unsigned char>(covered[x] << (x & 7));
    bits_->write(bits_at_[k] + row_bits(k) * static_cast<std::size_t>(y - where_[k].y0), packed.data(), packed.size());
  }
  // Rows [y, y + n) of layer k's coverage, packed.
  void read_coverage(int k, int y, int n, std::vector<unsigned char>& packed) const {
    packed.resize(row_bits(k) * static_cast<std::size_t>(n));
    bits_->read(bits_at_[k] + row_bits(k) * static_cast<std::size_t>(y - where_[k].y0), packed.data(), packed.size());
  }
  // Row r of `packed` (rows of w pixels) as flags 0 or 1, into covered[0, w rounded up to 8).
  static void unpack_row(const std::vector<unsigned char>& packed, int w, int r, unsigned char* covered) {
    const unsigned char* bits = packed.data() + static_cast<std::size_t>(r) * ((w + 7) / 8);
    for (int i = 0; i < (w + 7) / 8; ++i) {  // the bits of one byte into eight bytes 0 or 1
      const std::uint64_t v = ((bits[i] * 0x0101010101010101u & 0x8040201008040201u) + 0x7f7f7f7f7f7f7f7fu) >> 7 &
                              0x0101010101010101u;
      std::memcpy(covered + 8 * i, &v, 8);
    }
  }
  // The pass's state (rows near and far) before row y, where a block starts.
  void write_state(int k, int y, const PaddedRow& near, const PaddedRow& far) const {
    const std::size_t at = state_offset(k, y), n = padded(k) * sizeof(float);
    states_->write(at, near.v.data(), n);
    states_->write(at + n, far.v.data(), n);
  }
  void read_state(int k, int y, PaddedRow& near, PaddedRow& far) const {
    const std::size_t at = state_offset(k, y), n = padded(k) * sizeof(float);
    near.v.resize(padded(k));
    far.v.resize(padded(k));
    states_->read(at, near.v.data(), n);
    states_->read(at + n, far.v.data(), n);
  }

 private:
  std::size_t row_bits(int k) const { return static_cast<std::size_t>(where_[k].width() + 7) / 8; }
  std::size_t padded(int k) const { return static_cast<std::size_t>(where_[k].width()) + 2 * kPad; }
  // The block start rows in (y0, y1) of layer k: the first, and how many.
  int first_state(int k) const {
    const int y0 = where_[k].y0;
    return height_ - ((height_ - y0 - 1) / rows_) * rows_;  // the lowest height - j * rows above y0
  }
  int states_in(int k) const {
    const int first = first_state(k), y1 = where_[k].y1;
    return first < y1 ? (y1 - 1 - first) / rows_ + 1 : 0;
  }
  std::size_t state_offset(int k, int y) const {
    return states_at_[k] + static_cast<std::size_t>((y - first_state(k)) / rows_) * 2 * padded(k) * sizeof(float);
  }

  const std::vector<Footprint>& where_;
  int height_, rows_;
  std::vector<std::size_t> bits_at_, states_at_;
  std::unique_ptr<Scratch> bits_, states_;
};

// Per worker of the backward pass's merge: one row's deepest distance, label and cover count, and
// the layers it saw overlapped.
struct MergeRow {
  std::vector<float> best;
  std::vector<Label> label;
  std::vector<unsigned char> count;
  std::vector<signed char> overlaps;
};

// The two passes over the canvas, sharing the layers' footprints and the distance scratch. Both
// run on `threads` workers and give the one-thread result bit for bit: the forward pass takes
// whole layers (independent of each other), the backward pass blocks of rows, first each layer's
// final distances (layers in parallel), then the deepest layer per pixel (rows in parallel, the
// layers in index order as one thread takes them).
class SeamPasses {
 public:
  // Only the layers whose footprints meet columns [begin, end) take part.
  SeamPasses(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
             const std::function<void(double)>& progress, int begin, int end, int threads, KeptRows* keep)
      : plan_(plan), keep_(keep), wrap_x_(wrap_x), progress_(progress), n_(static_cast<int>(plan.layers.size())),
        W_(plan.canvas.width), H_(plan.canvas.height), threads_(std::max(1, threads)), where_(n_) {
    for (int k = 0; k < n_; ++k) {
      where_[k] = footprint(plan, k);
      if (where_[k].x0 < end && where_[k].x1 > begin) taking_part_.push_back(k);
    }
    R_ = block_rows();
    kept_ = std::make_unique<ForwardKept>(where_, taking_part_, H_, R_, temp_dir);
  }
  std::size_t scratch_bytes() const { return kept_->bytes(); }
  const std::vector<int>& taking_part() const { return taking_part_; }
  void forward();
  void backward(LabelPlane& labels, std::vector<signed char>& overlaps);

 private:
  void forward_layer(int k, bool reports);
  void backward_block(Active& a, int lo, int hi) const;
  void merge_row(int y, const std::vector<std::unique_ptr<Active>>& active, MergeRow& m, LabelPlane& labels) const;
  int block_rows() const;
  // Layer k's state for a pass that starts beyond its top (forward) or bottom row.
  std::unique_ptr<Active> start(int k, bool top) const {
    auto a = std::make_unique<Active>();
    a->index = k;
    a->where = where_[k];
    a->edges = edges_of(where_[k], W_, H_, wrap_x_);
    a->near = a->far = a->edges.outside(top);
    a->cur.v.assign(where_[k].width() + 2 * kPad, 0.0f);
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
  KeptRows* keep_;
  bool wrap_x_;
  const std::function<void(double)>& progress_;
  int n_, W_, H_, threads_;
  int R_ = 1;  // rows per block of the backward pass
  std::vector<Footprint> where_;
  std::vector<int> taking_part_;
  std::unique_ptr<ForwardKept> kept_;
  std::atomic<long long> rows_done_{0};
  long long rows_total_ = 1;
  std::atomic<bool> stop_{false};  // a worker failed
};

// Whole layers in the order they start, each opened, its forward distances computed top to bottom
// (what the backward pass needs to compute them again kept: ForwardKept), and closed: as many open
// at once as there are workers.
void SeamPasses::forward() {
  const std::vector<int> by_top = order(true);
  rows_total_ = 1;
  for (const int k : by_top) rows_total_ += where_[k].y1 - where_[k].y0;
  rows_done_ = 0;
  parallel_for(threads_, static_cast<int>(by_top.size()), stop_,
               [&](int t, int i) { forward_layer(by_top[i], t == 0); });
}

void SeamPasses::forward_layer(int k, bool reports) {
  const std::unique_ptr<Active> a = start(k, true);
  LayerRows rows(plan_, k, 0, W_, true, keep_);
  const int w = a->where.width();
  std::vector<unsigned char> covered(w), packed;
  std::vector<float> base(w);
  for (int y = a->where.y0; y < a->where.y1 && !stop_.load(std::memory_order_relaxed); ++y) {
    rows.coverage(y, covered);  // the depth needs only where the layer is
    kept_->write_coverage(k, y, covered.data(), packed);
    if (kept_->block_starts(k, y)) kept_->write_state(k, y, a->near, a->far);
    for (int x = 0; x < w; ++x) base[x] = covered[x] ? kInf : 0.0f;
    chamfer_row(a->edges, 1, base.data(), a->near, a->far, a->cur);
    std::swap(a->far, a->near);
    std::swap(a->near, a->cur);
    const long long done = rows_done_.fetch_add(1) + 1;
    if (reports) report(0.5 * static_cast<double>(done) / rows_total_);
  }
}
// Rows per block of the backward pass: its layers' final distances for the block stay in memory
// (4 bytes a pixel), about 16 MiB at the widest rows, 8 to 64 rows.
int SeamPasses::block_rows() const {
  std::vector<std::pair<int, long long>> events;  // (row, width change) where layers start and end
  for (const int k : taking_part_) {
    events.emplace_back(where_[k].y0, where_[k].width());
    events.emplace_back(where_[k].y1, -where_[k].width());
  }
  std::sort(events.begin(), events.end());
  long long widest = 1, now = 0;
  for (const auto& [y, dw] : events) widest = std::max(widest, now += dw);
  return static_cast<int>(std::clamp<long long>((std::size_t{4} << 20) / widest, 8, 64));
}

// Layer a's final distances for its rows in [lo, hi) into a.block: first-pass distances computed
// again top to bottom (from the state kept where the block starts, or the layer's top edge), then
// the backward pass over them bottom to top.
void SeamPasses::backward_block(Active& a, int lo, int hi) const {
  const int top = std::max(lo, a.where.y0), bottom = std::min(hi, a.where.y1), w = a.where.width();
  a.block_lo = top;
  a.block.resize(static_cast<std::size_t>(bottom - top) * w);
  PaddedRow near, far, cur{std::vector<float>(w + 2 * kPad)};
  if (top == a.where.y0) near = far = a.edges.outside(true);
  else kept_->read_state(a.index, top, near, far);
  std::vector<unsigned char> packed, covered((w + 7) / 8 * 8);
  kept_->read_coverage(a.index, top, bottom - top, packed);
  std::vector<float> base(w);
  for (int y = top; y < bottom; ++y) {
    ForwardKept::unpack_row(packed, w, y - top, covered.data());
    for (int x = 0; x < w; ++x) base[x] = covered[x] ? kInf : 0.0f;
    chamfer_row(a.edges, 1, base.data(), near, far, cur);
    std::copy(cur.at(), cur.at() + w, a.block.data() + static_cast<std::size_t>(y - top) * w);
    std::swap(far, near);
    std::swap(near, cur);
  }
  for (int y = bottom - 1; y >= top; --y) {
    float* row = a.block.data() + static_cast<std::size_t>(y - top) * w;
    chamfer_row(a.edges, -1, row, a.near, a.far, a.cur);
    std::copy(a.cur.at(), a.cur.at() + w, row);
    std::swap(a.far, a.near);
    std::swap(a.near, a.cur);
  }
}

// Row y's deepest layer per pixel (the layers in index order: ties go to the earlier) into
// `labels`; marks in m.overlaps the layers some of whose pixels here another layer covers too.
void SeamPasses::merge_row(int y, const std::vector<std::unique_ptr<Active>>& active, MergeRow& m,
                           LabelPlane& labels) const {
  std::fill(m.best.begin(), m.best.end(), 0.0f);
  std::fill(m.label.begin(), m.label.end(), Label{0});
  std::fill(m.count.begin(), m.count.end(), 0);
  const auto crosses = [y](const Active& a) { return a.where.y0 <= y && y < a.where.y1; };
  for (const auto& a : active) {
    if (!crosses(*a)) continue;
    const int w = a->where.width(), x0 = a->where.x0;
    const float* __restrict d = a->final_row(y);
    float* __restrict best = m.best.data() + x0;
    Label* __restrict label = m.label.data() + x0;
    unsigned char* __restrict count = m.count.data() + x0;
    const Label mine = static_cast<Label>(a->index + 1);
    for (int x = 0; x < w; ++x) {  // without branches (vectorised); best >= 0, so deeper means covered
      const bool deeper = d[x] > best[x];
      count[x] = static_cast<unsigned char>(count[x] + (d[x] > 0.0f && count[x] < 2));
      best[x] = deeper ? d[x] : best[x];
      label[x] = deeper ? mine : label[x];
    }
  }
  for (const auto& a : active) {
    if (!crosses(*a)) continue;
    const float* d = a->final_row(y);
    for (int x = 0; x < a->where.width() && !m.overlaps[a->index]; ++x)
      if (d[x] > 0.0f && m.count[a->where.x0 + x] > 1) m.overlaps[a->index] = 1;
  }
  labels.write_row(y, m.label);
}

// Bottom to top in blocks of rows: final distances, the deepest layer per pixel into `labels`;
// `overlaps` marks layers some of whose pixels another layer covers too.
void SeamPasses::backward(LabelPlane& labels, std::vector<signed char>& overlaps) {
  const std::vector<int> by_bottom = order(false);
  std::vector<std::unique_ptr<Active>> active;  // by layer index: ties go to the earlier layer
  std::size_t next = 0;
  const int R = R_;
  std::vector<MergeRow> merge(threads_);
  for (MergeRow& m : merge) {
    m.best.resize(W_);
    m.label.resize(W_);
    m.count.resize(W_);
    m.overlaps.assign(n_, 0);
  }
  // On workers kept for the whole pass: per block, the layers it meets join (in one worker while
  // the others wait), then the workers take its layers, then its rows.
  int lo = H_, hi = H_;
  bool layers = false;  // the current step takes the block's layers (else its rows)
  const auto next_step = [&]() -> int {
    if (layers) {
      layers = false;
      return hi - lo;
    }
    if (lo < hi) {  // the block just merged: the layers starting in it are done
      std::erase_if(active, [&](const auto& a) { return a->where.y0 >= lo; });
      report(0.5 + 0.5 * (H_ - lo) / H_);
    }
    if (lo == 0) return -1;
    hi = lo;
    lo = std::max(0, hi - R);
    for (; next < by_bottom.size() && where_[by_bottom[next]].y1 > lo; ++next) {
      auto a = start(by_bottom[next], false);
      const auto at = std::upper_bound(active.begin(), active.end(), a->index,
                                       [](int v, const auto& b) { return v < b->index; });
      active.insert(at, std::move(a));
    }
    layers = true;
    return static_cast<int>(active.size());
  };
  util::run_steps(threads_, next_step, [&](int t, int i) {
    if (layers)
      backward_block(*active[i], lo, hi);
    else
      merge_row(hi - 1 - i, active, merge[t], labels);
  });
  for (const MergeRow& m : merge)
    for (int k = 0; k < n_; ++k) overlaps[k] |= m.overlaps[k];
}

}  // namespace

SeamColumns compute_seam_columns(const BlendPlan& plan, bool wrap_x, const std::filesystem::path& temp_dir,
                                 const std::function<void(double)>& progress, int begin, int end, LabelPlane& labels,
                                 std::vector<signed char>& overlaps, int threads, KeptRows* keep) {
  const int n = static_cast<int>(plan.layers.size());
  if (n > kMaxLayers) throw UsageError(fmt::format("{} layers; gdp blend takes at most {}", n, kMaxLayers));
  SeamPasses passes(plan, wrap_x, temp_dir, progress, begin, end, threads, keep);
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
                         const std::function<void(double)>& progress, int threads) {
  SeamResult result;
  result.labels = std::make_unique<LabelPlane>(temp_dir, plan.canvas.width, plan.canvas.height);
  const SeamColumns done =
      compute_seam_columns(plan, wrap_x, temp_dir, progress, 0, plan.canvas.width, *result.labels, result.overlaps,
                           threads);
  result.layers_read = done.layers_read;
  result.scratch_bytes = done.distance_bytes + result.labels->bytes();
  return result;
}

}  // namespace gdp::blending
