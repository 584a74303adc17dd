// Opening a layer: its file (or page, or in-memory image) and mask read in canvas order, coverage from alpha and mask.
#include "blend/layer_rows.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/image_stream.h"

namespace gdp::blending {

Footprint footprint(const BlendPlan& plan, int index) {
  const PlacedLayer& l = plan.layers[index];
  const CanvasRect& c = plan.canvas;
  const long long left = l.x - c.x, top = l.y - c.y;
  Footprint f;
  f.x0 = static_cast<int>(std::clamp<long long>(left, 0, c.width));
  f.x1 = static_cast<int>(std::clamp<long long>(left + l.width, 0, c.width));
  f.y0 = static_cast<int>(std::clamp<long long>(top, 0, c.height));
  f.y1 = static_cast<int>(std::clamp<long long>(top + l.height, 0, c.height));
  f.skip_x = static_cast<int>(f.x0 - left);
  f.skip_y = static_cast<int>(f.y0 - top);
  return f;
}

OpenLayer::OpenLayer(const BlendPlan& plan, int k, int begin, int end, bool prefetch, const KeptRows* read_from)
    : index(k), rows(std::make_unique<LayerRows>(plan, k, begin, end, prefetch, nullptr, read_from)),
      colour(static_cast<std::size_t>(plan.colour_channels) * rows->where().width()), covered(rows->where().width()) {}

LayerRows::LayerRows(const BlendPlan& plan, int index, int begin, int end, bool prefetch, KeptRows* keep_into,
                     const KeptRows* read_from)
    : where_(footprint(plan, index)), name_(plan.layers[index].name), calibration_(plan, index) {
  if (!plan.images.empty()) {
    const ImageLayer& l = plan.images[index];
    image_ = std::make_unique<ImageRowReader>(*l.image);
    if (l.mask) mask_ = std::make_unique<ImageRowReader>(*l.mask);
  } else {
    const LayerSource& s = plan.sources[index];
    offset_ = s.offset;
    background_ = s.background;
    mask_scale_ = s.mask_scale;
    auto file = std::make_unique<ImageFileReader>(s.image, prefetch, ColumnRange{}, plan.pages[index]);
    const int rows = where_.y1 - where_.y0 + where_.skip_y;  // the layer's rows read: down to the canvas's last
    if (keep_into) keep_ = keep_into->writer(index, file->info().sample_type, file->channels(), file->width(), rows);
    if (read_from) kept_ = read_from->reader(index, rows);
    image_ = std::move(file);
    if (!s.mask.empty()) mask_ = std::make_unique<ImageFileReader>(s.mask, prefetch);
  }
  channels_ = image_->channels();
  colour_ = plan.colour_channels;
  own_ = colour_channels_of(channels_);
  // The layer's own columns that are wanted: canvas [begin, end) within the footprint.
  const int a = std::max(begin, where_.x0) - where_.x0 + where_.skip_x;
  const int b = std::min(end, where_.x1) - where_.x0 + where_.skip_x;
  if (a < b && (a > 0 || b < image_->width())) {
    image_->set_columns(a, b);
    if (mask_) mask_->set_columns(a, b);
  }
  row_.assign(static_cast<std::size_t>(channels_) * image_->width(), 0.0f);
  if (mask_) mask_row_.assign(static_cast<std::size_t>(mask_->channels()) * mask_->width(), 0.0f);
}

LayerRows::~LayerRows() = default;

// Decodes the layer's rows up to the one on canvas row y (rows above the canvas are read and
// dropped); returns that row's index in the layer.
int LayerRows::seek(int y) {
  const int r = y - where_.y0 + where_.skip_y;
  for (; next_ <= r; ++next_) {
    if (kept_) kept_->read(row_);
    else image_->read_row(next_, row_);
    if (keep_) keep_->write(row_);
    if (mask_) mask_->read_row(next_, mask_row_);
  }
  return r;
}

void LayerRows::coverage(int y, std::span<unsigned char> covered) {
  seek(y);
  const int w = where_.width(), lw = image_->width();
  std::fill(covered.begin(), covered.begin() + w, 1);
  // Finite colour (v - v == 0 exactly when v is finite: vectorised, std::isfinite is not).
  for (int c = 0; c < own_; ++c) {
    const float* in = row_.data() + static_cast<std::size_t>(c) * lw + where_.skip_x;
    for (int i = 0; i < w; ++i) covered[i] &= static_cast<unsigned char>(in[i] - in[i] == 0.0f);
  }
  const auto cover = [&](const float* in, float scale) {
    for (int i = 0; i < w; ++i) covered[i] &= static_cast<unsigned char>(in[i] * scale >= kCovered);
  };
  if (channels_ == own_ + 1) cover(row_.data() + static_cast<std::size_t>(own_) * lw + where_.skip_x, 1.0f);
  if (mask_) cover(mask_row_.data() + where_.skip_x, mask_scale_);
}

void LayerRows::subtract_background(int row, int x0, int w, float* out) const {
  const LayerBackground& b = background_;
  const double v = (row + 0.5 - b.cy) / b.scale, row_part = b.constant + b.slope_v * v + b.radial * v * v;
  for (int i = 0; i < w; ++i) {
    const double u = (x0 + i + 0.5 - b.cx) / b.scale;
    out[i] = static_cast<float>(out[i] - (row_part + b.slope_u * u + b.radial * u * u));
  }
}

void LayerRows::read(int y, std::span<float> colour, std::span<unsigned char> covered) {
  coverage(y, covered);
  const int r = y - where_.y0 + where_.skip_y, w = where_.width(), lw = image_->width();
  const float offset = offset_;
  for (int c = 0; c < colour_; ++c) {
    const float* in = row_.data() + static_cast<std::size_t>(own_ == 1 ? 0 : c) * lw + where_.skip_x;
    float* out = colour.data() + static_cast<std::size_t>(c) * w;
    for (int i = 0; i < w; ++i) out[i] = in[i] + offset;
    if (background_.active()) subtract_background(r, where_.skip_x, w, out);
  }
  if (calibration_.active()) calibration_.apply(r, where_.skip_x, w, colour_, colour.data());
}

}  // namespace gdp::blending
