// Decoding through OpenImageIO: the formats gdp does not decode itself (Radiance HDR, FITS, WebP, ...).
#include <algorithm>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "io/codec_util.h"
#include "oiio_module/oiio_module.h"
#include "oiio_module/oiio_types.h"

namespace gdp::io {
namespace {

class OiioDecoder final : public Decoder {
 public:
  explicit OiioDecoder(const std::string& path) {
    // Keep alpha as stored (no premultiplication): gdp treats every channel as plain data.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    input_ = OIIO::ImageInput::open(path, &config);
    if (!input_) throw CodecError(fmt::format("not an image file OpenImageIO can read ({})", one_line(OIIO::geterror())));
    // FITS files often keep only a header in the primary HDU: use the first subimage with pixels.
    while (input_->spec().width <= 0 || input_->spec().height <= 0) {
      if (!input_->seek_subimage(subimage_ + 1, 0)) break;
      ++subimage_;
    }
    spec_ = input_->spec();
    if (spec_.depth > 1) throw CodecError("volume images (depth > 1) are not supported");
    layout_.width = spec_.width;
    layout_.height = spec_.height;
    layout_.channels = spec_.nchannels;
    layout_.tile_width = spec_.tile_width;
    layout_.tile_height = spec_.tile_width > 0 ? spec_.tile_height : 0;
    layout_.info.sample_type = sample_type_of(spec_.format);
    layout_.info.format_name = input_->format_name();
    layout_.info.lossy = is_lossy_format(layout_.info.format_name);
    layout_.stored = band_type_of(spec_);
    stored_ = type_desc_of(layout_.stored);
  }

  const ImageLayout& layout() const override { return layout_; }

  // Tiled files are read by whole tiles (read_scanlines() on a tiled TIFF crashes OpenImageIO
  // 2.4 with SIGFPE): the tile columns covering [x0, x1), then the window copied out.
  void read(int y0, int y1, int x0, int x1, void* out) override {
    const int ch = spec_.nchannels;
    const std::size_t pixel = static_cast<std::size_t>(ch) * stored_.size();
    int rx0 = 0, rx1 = spec_.width;
    if (spec_.tile_width > 0) {
      rx0 = x0 / spec_.tile_width * spec_.tile_width;
      rx1 = std::min(spec_.width, (x1 + spec_.tile_width - 1) / spec_.tile_width * spec_.tile_width);
    }
    const bool direct = rx0 == x0 && rx1 == x1;
    unsigned char* target = static_cast<unsigned char*>(out);
    if (!direct) {
      buffer_.resize(static_cast<std::size_t>(y1 - y0) * (rx1 - rx0) * pixel);
      target = buffer_.data();
    }
    const bool ok = spec_.tile_width > 0
                        ? input_->read_tiles(subimage_, 0, spec_.x + rx0, spec_.x + rx1, spec_.y + y0, spec_.y + y1,
                                             spec_.z, spec_.z + 1, 0, ch, stored_, target)
                        : input_->read_scanlines(subimage_, 0, spec_.y + y0, spec_.y + y1, spec_.z, 0, ch, stored_,
                                                 target);
    if (!ok) throw CodecError("cannot read pixels: " + one_line(input_->geterror()));
    if (direct) return;
    const std::size_t in_row = static_cast<std::size_t>(rx1 - rx0) * pixel, out_row = (x1 - x0) * pixel;
    for (int y = 0; y < y1 - y0; ++y)
      std::memcpy(static_cast<unsigned char*>(out) + y * out_row, buffer_.data() + y * in_row + (x0 - rx0) * pixel,
                  out_row);
  }

 private:
  std::unique_ptr<OIIO::ImageInput> input_;
  int subimage_ = 0;
  OIIO::ImageSpec spec_;
  OIIO::TypeDesc stored_;
  ImageLayout layout_;
  std::vector<unsigned char> buffer_;
};

}  // namespace

std::unique_ptr<Decoder> open_oiio_decoder(const std::string& path) { return std::make_unique<OiioDecoder>(path); }

}  // namespace gdp::io
