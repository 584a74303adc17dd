// Plate mosaic rows on the PQ sphere: directions of a row, each plate's pixel coordinates there, the seam rule.
#include "sky/mosaic_rows.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "blend/across_label.h"
#include "blend/scratch.h"
#include "blend/seams.h"
#include "sphere/vec3.h"

namespace gdp::sky {
namespace {

enum class Kind { Value, Label, Across };

// One of the three views of the shared rows.
class View final : public RowReader {
 public:
  View(MosaicRows& rows, Kind kind) : rows_(rows), kind_(kind) {}
  int width() const override { return rows_.window().width; }
  int height() const override { return rows_.window().rows; }
  int channels() const override { return kind_ == Kind::Across ? 2 : 1; }
  void read_row(int y, std::span<float> out) override {
    const std::vector<float>& v = kind_ == Kind::Across ? rows_.across_row(y)
                                  : kind_ == Kind::Label  ? rows_.row(y).label
                                                          : rows_.row(y).value;
    std::copy(v.begin(), v.end(), out.begin());
  }
  void rewind() override {}
  void set_columns(int begin, int end) override { rows_.want_columns(begin, end); }

 private:
  MosaicRows& rows_;
  Kind kind_;
};

// The index into `hits` of plate k's hit, or -1.
int plate_hit(const std::vector<PlateHit>& hits, int k) {
  for (std::size_t n = 0; n < hits.size(); ++n)
    if (hits[n].plate == k) return static_cast<int>(n);
  return -1;
}

}  // namespace

MosaicRows::MosaicRows(std::vector<Plate>& plates, PlatePixels& pixels, const PqWindow& window,
                       const SeamSources* sources, const std::filesystem::path& temp_dir, std::size_t memory_limit)
    : plates_(plates), pixels_(pixels), window_(window), released_(plates.size(), 0), sources_(sources),
      end_(window.width),
      coverage_(std::make_unique<blending::Scratch>(
          temp_dir, static_cast<std::size_t>(window.width) * window.rows * sizeof(float), "gdp-sky-coverage",
          memory_limit)) {
  none_.assign(static_cast<std::size_t>(window.width), kNoPlate);
  for (const Plate& p : plates) {
    sizes_.push_back(p.width);
    sizes_.push_back(p.height);
  }
  composite_ = std::make_unique<View>(*this, Kind::Value);
  labels_ = std::make_unique<View>(*this, Kind::Label);
  across_ = std::make_unique<View>(*this, Kind::Across);
}

MosaicRows::~MosaicRows() = default;

void MosaicRows::coverage_row(int j, std::span<float> out) const {
  const std::size_t w = window_.width;
  coverage_->read(static_cast<std::size_t>(j) * w * sizeof(float), out.data(), w * sizeof(float));
}

void MosaicRows::want_columns(int begin, int end) {
  if (!columns_set_) wanted_ = {begin, end};
  wanted_ = {std::min(begin, wanted_[0]), std::max(end, wanted_[1])};
  columns_set_ = true;
  begin_ = std::max(0, wanted_[0] - 1);
  end_ = std::min(window_.width, wanted_[1] + 1);
}

MosaicRows::Row& MosaicRows::fetch(int j) {
  auto it = cache_.find(j);
  if (it != cache_.end()) return it->second;
  if (j < released_below_)
    throw std::logic_error("gdp sky: PQ row " + std::to_string(j) + " asked for again after its plates were released");
  if (cache_.size() >= kCachedRows)  // the oldest row but those across_row() holds
    cache_.erase(std::find_if(cache_.begin(), cache_.end(),
                              [&](const auto& e) { return e.first < pinned_[0] || e.first > pinned_[1]; }));
  // Rows older than the cache are not asked for again: plates that end above them are done.
  released_below_ = std::max(released_below_, j - kReleaseLag);
  for (std::size_t k = 0; k < plates_.size(); ++k)
    if (pixels_.rows(k)[1] < released_below_ && !released_[k]) {
      pixels_.release(k);
      released_[k] = 1;
    }
  Row& r = cache_[j];
  compute(j, r);
  return r;
}

const std::vector<float>& MosaicRows::across_row(int j) {
  if (const auto it = cache_.find(j); it != cache_.end() && !it->second.across.empty()) return it->second.across;
  const int w = window_.width;
  pinned_ = {j - 1, j + 1};  // fetching one of these rows evicts none of the others
  const float* up = j > 0 ? fetch(j - 1).label.data() : none_.data();
  const float* down = j + 1 < window_.rows ? fetch(j + 1).label.data() : none_.data();
  Row& r = fetch(j);
  r.across.assign(2 * static_cast<std::size_t>(w), std::numeric_limits<float>::quiet_NaN());
  const auto other = [](float own, float n1, float n2) { return blending::across_label(own, n1, n2, kNoPlate); };
  for (int i = begin_; i < end_; ++i) {
    const float own = r.label[i];
    if (own == kNoPlate) continue;
    // The whole PQ image's rows are periodic (the stitch's right neighbour of the last column is column 0).
    const int left = i > 0 ? i - 1 : (window_.whole() ? w - 1 : i), right = i + 1 < w ? i + 1 : (window_.whole() ? 0 : i);
    const float across[2] = {other(own, r.label[left], r.label[right]), other(own, up[i], down[i])};
    for (int d = 0; d < 2; ++d)
      for (const PlateHit& h : r.hits[i])
        if (across[d] != kNoPlate && h.plate + 2 == static_cast<int>(across[d])) {
          const Plate& p = plates_[h.plate];
          r.across[static_cast<std::size_t>(d) * w + i] = p.extended(h.x, h.y, kExtension * std::max(p.width, p.height));
        }
  }
  return r.across;
}

void MosaicRows::compute(int j, Row& out) {
  const int w = window_.width;
  std::vector<sphere::Vec3> dirs(w);
  if (window_.whole()) {
    sphere::pq_row(sphere::SquareMap::Toast, window_.height, j, dirs);
  } else {
    for (int i = begin_; i < end_; ++i)
      dirs[i] = sphere::pq_pixel_direction(sphere::SquareMap::Toast, window_.height, window_.i0 + i, window_.j0 + j);
  }
  pixels_computed_ += end_ - begin_;
  // Every plate whose footprint reaches a pixel: that pixel's coordinates in the plate.
  std::vector<std::vector<PlateHit>>& hits = out.hits;
  hits.assign(w, {});
  std::vector<int> pixels;
  std::vector<double> sky, xy;
  std::vector<unsigned char> ok;
  for (std::size_t k = 0; k < plates_.size(); ++k) {
    const Plate& p = plates_[k];
    if (j < pixels_.rows(k)[0] || j > pixels_.rows(k)[1]) continue;  // the plate reaches no pixel of this row
    if (pixels_.columns(k)[1] < begin_ || pixels_.columns(k)[0] >= end_) continue;  // ... nor of the columns computed
    pixels_.hold(k);
    pixels.clear();
    for (int i = begin_; i < end_; ++i)
      if (sphere::dot(dirs[i], p.centre) >= p.cos_reach) pixels.push_back(i);
    if (pixels.empty()) continue;
    sky.resize(2 * pixels.size());
    xy.resize(2 * pixels.size());
    ok.resize(pixels.size());
    for (std::size_t n = 0; n < pixels.size(); ++n) lon_lat(dirs[pixels[n]], sky[2 * n], sky[2 * n + 1]);
    p.wcs->sky_to_pixel(sky, xy, ok);
    for (std::size_t n = 0; n < pixels.size(); ++n) {
      const double x = xy[2 * n], y = xy[2 * n + 1];
      const double margin = kExtension * std::max(p.width, p.height);
      const bool near = ok[n] && x >= -margin && x < p.width + margin && y >= -margin && y < p.height + margin;
      if (near) hits[pixels[n]].push_back({static_cast<int>(k), x, y, p.has_value(x, y)});
    }
  }
  out.value.assign(w, std::numeric_limits<float>::quiet_NaN());
  out.label.assign(w, kNoPlate);
  out.covered.assign(w, 0.0f);
  out.across.clear();
  out.preferred.assign(w, -1);
  std::vector<blending::Label> seam(seams_ ? w : 0);
  if (seams_) seams_->read_row(j, seam, begin_, end_);
  for (int i = begin_; i < end_; ++i) {
    const int preferred = sources_ && hits[i].size() >= 2 ? sources_->plate_at(dirs[i]) : -1;
    out.preferred[i] = preferred;
    int best = seams_ ? plate_hit(hits[i], seam[i] - 1) : -1;
    if (best < 0) best = choose_plate(hits[i], sizes_, preferred);
    if (best < 0) continue;
    const PlateHit& h = hits[i][best];
    const Plate& p = plates_[h.plate];
    out.value[i] = p.extended(h.x, h.y, kExtension * std::max(p.width, p.height));
    out.label[i] = static_cast<float>(h.plate + 2);
    out.covered[i] = depth_inside(h.x, h.y, p.width, p.height) > 0.0 ? out.label[i] : 0.0f;
  }
  coverage_->write(static_cast<std::size_t>(j) * w * sizeof(float), out.covered.data(), w * sizeof(float));
}

}  // namespace gdp::sky
