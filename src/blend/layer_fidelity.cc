// Per-layer fidelity rows: each pixel's layer's weight or pin, combined with a canvas image's.
#include "blend/layer_fidelity.h"

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::blending {

LayerFidelityReader::LayerFidelityReader(const LabelPlane& labels, std::vector<float> per_layer, RowReader* image,
                                         const std::string& image_name, bool either)
    : labels_(labels), per_layer_(std::move(per_layer)), image_(image), either_(either), labels_row_(labels.width()) {
  if (image_ && (image_->width() != labels.width() || image_->height() != labels.height()))
    throw InputError(fmt::format("{}: {}x{}, but the canvas is {}x{}", image_name, image_->width(), image_->height(),
                                 labels.width(), labels.height()));
  if (image_) image_row_.resize(static_cast<std::size_t>(image_->channels()) * image_->width());
}

void LayerFidelityReader::set_columns(int begin, int end) {
  begin_ = begin;
  end_ = end;
  labels_.want_columns(begin, end);
  if (image_) image_->set_columns(begin, end);
}

void LayerFidelityReader::read_row(int y, std::span<float> out) {
  const int b = begin_, e = end_ < 0 ? labels_.width() : end_;
  labels_.read_row(y, labels_row_, b, e);
  if (image_) image_->read_row(y, image_row_);
  const int layers = static_cast<int>(per_layer_.size());
  for (int x = b; x < e; ++x) {
    const Label l = labels_row_[x];
    const float mine = l != 0 && l <= layers ? per_layer_[l - 1] : 0.0f;
    const float theirs = image_ ? image_row_[x] : 0.0f;
    out[x] = either_ ? (mine > 0.5f || theirs > 0.5f ? 1.0f : 0.0f) : mine + theirs;
  }
}

}  // namespace gdp::blending
