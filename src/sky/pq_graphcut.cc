// gdp sky --seams graphcut: the PQ rows of the plates as blend's graph-cut layers, and the cut.
#include "sky/pq_graphcut.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "blend/graphcut_seams.h"
#include "sky/mosaic_rows.h"

namespace gdp::sky {
namespace {

// The PQ window's rows as graph-cut layers: plate k is layer k. Rows are computed once per pass
// (MosaicRows) and kept while the window holds them; the first pass writes the distance labels.
class PqLayers final : public blending::SeamLayers {
 public:
  PqLayers(std::vector<Plate>& plates, PlatePixels& pixels, const PqWindow& window, const SeamSources* stars,
           const std::filesystem::path& temp_dir, std::size_t memory_limit, blending::LabelPlane& depth)
      : plates_(plates), pixels_(pixels), window_(window), stars_(stars), temp_dir_(temp_dir),
        memory_limit_(memory_limit), depth_(depth), patches_(plates.size()), pointers_(plates.size(), nullptr) {}
  ~PqLayers() override { release_all(); }

  int width() const override { return window_.width; }
  int height() const override { return window_.rows; }
  int channels() const override { return 1; }
  void restart() override {
    rows_.reset();
    release_all();
    rows_ = std::make_unique<MosaicRows>(plates_, pixels_, window_, stars_, temp_dir_, memory_limit_);
    kept_.clear();
    first_ = next_ = 0;
  }
  void slide(int top, int bottom) override {
    for (; next_ < bottom; ++next_) kept_.push_back(read(next_));
    for (; first_ < top; ++first_) kept_.pop_front();
    build(top, bottom);
  }
  const std::vector<const blending::Patch*>& layers() const override { return pointers_; }
  // The range of the values seen (the first pass sees them all): the largest disagreement.
  double uncovered_cost() const override { return hi_ > lo_ ? hi_ - lo_ : 1.0; }

 private:
  // A plate's values along a PQ row from column x0 (NaN: no value there).
  struct Segment {
    int plate = 0, x0 = 0;
    std::vector<float> value;
  };

  void release_all() {
    for (std::size_t k = 0; k < plates_.size(); ++k) pixels_.release(k);
  }

  std::vector<Segment> read(int j) {
    const MosaicRows::Row& r = rows_->row(j);
    const int w = window_.width;
    if (j == depth_rows_) {
      std::vector<blending::Label> labels(w);
      for (int i = 0; i < w; ++i) labels[i] = r.label[i] == kNoPlate ? 0 : static_cast<blending::Label>(r.label[i] - 1);
      depth_.write_row(j, labels);
      ++depth_rows_;
    }
    std::vector<int> at(plates_.size(), -1);
    std::vector<Segment> out;
    for (int i = 0; i < w; ++i)
      for (const PlateHit& h : r.hits[i]) {
        if (!h.valid || (r.preferred[i] >= 0 && h.plate != r.preferred[i])) continue;
        const Plate& p = plates_[h.plate];
        const float v = static_cast<float>(p.sample(h.x, h.y) - p.fade_to);
        if (!std::isfinite(v)) continue;
        lo_ = std::min(lo_, static_cast<double>(v));
        hi_ = std::max(hi_, static_cast<double>(v));
        if (at[h.plate] < 0) {
          at[h.plate] = static_cast<int>(out.size());
          out.push_back({h.plate, i, {}});
        }
        Segment& s = out[at[h.plate]];
        s.value.resize(i - s.x0 + 1, std::numeric_limits<float>::quiet_NaN());
        s.value[i - s.x0] = v;
      }
    return out;
  }

  // Every plate's Patch over the kept rows [top, bottom).
  void build(int top, int bottom) {
    std::vector<int> x0(plates_.size(), window_.width), x1(plates_.size(), 0);
    for (int j = top; j < bottom; ++j)
      for (const Segment& s : kept_[j - first_]) {
        x0[s.plate] = std::min(x0[s.plate], s.x0);
        x1[s.plate] = std::max(x1[s.plate], s.x0 + static_cast<int>(s.value.size()));
      }
    for (std::size_t k = 0; k < plates_.size(); ++k) {
      blending::Patch& p = patches_[k];
      pointers_[k] = x1[k] > x0[k] ? &p : nullptr;
      if (!pointers_[k]) continue;
      p.x0 = x0[k];
      p.w = x1[k] - x0[k];
      p.y0 = top;
      p.h = bottom - top;
      p.colour.assign(static_cast<std::size_t>(p.w) * p.h, 0.0f);
      p.covers.assign(p.colour.size(), 0);
    }
    for (int j = top; j < bottom; ++j)
      for (const Segment& s : kept_[j - first_]) {
        blending::Patch& p = patches_[s.plate];
        for (std::size_t n = 0; n < s.value.size(); ++n) {
          if (std::isnan(s.value[n])) continue;
          const std::size_t cell = static_cast<std::size_t>(j - top) * p.w + (s.x0 + n - p.x0);
          p.colour[cell] = s.value[n];
          p.covers[cell] = 1;
        }
      }
  }

  std::vector<Plate>& plates_;
  PlatePixels& pixels_;
  const PqWindow& window_;
  const SeamSources* stars_;
  std::filesystem::path temp_dir_;
  std::size_t memory_limit_;
  blending::LabelPlane& depth_;
  int depth_rows_ = 0;  // distance labels written
  std::unique_ptr<MosaicRows> rows_;
  std::deque<std::vector<Segment>> kept_;  // rows [first_, next_)
  int first_ = 0, next_ = 0;
  std::vector<blending::Patch> patches_;
  std::vector<const blending::Patch*> pointers_;
  double lo_ = std::numeric_limits<double>::infinity(), hi_ = -std::numeric_limits<double>::infinity();
};

}  // namespace

PqSeams graphcut_pq_seams(std::vector<Plate>& plates, PlatePixels& pixels, const PqWindow& window,
                          const SeamSources* stars, const std::filesystem::path& temp_dir, std::size_t memory_limit) {
  auto depth = std::make_unique<blending::LabelPlane>(temp_dir, window.width, window.rows);
  blending::GraphcutLabels cut;
  {
    PqLayers layers(plates, pixels, window, stars, temp_dir, memory_limit, *depth);
    cut = blending::graphcut_labels(layers, *depth, window.whole(), temp_dir, nullptr);
  }
  PqSeams out;
  out.depth_cost = cut.depth_cost;
  out.cost = cut.cost;
  out.labels = cut.labels ? std::move(cut.labels) : std::move(depth);
  return out;
}

}  // namespace gdp::sky
