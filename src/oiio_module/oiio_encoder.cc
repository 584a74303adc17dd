// Encoding through OpenImageIO: the formats gdp does not encode itself, written through a checked file.
#include <algorithm>
#include <filesystem>
#include <string_view>

#include <fmt/format.h>

#include "io/codec_util.h"
#include "oiio_module/checked_file.h"
#include "oiio_module/oiio_module.h"
#include "oiio_module/oiio_types.h"

namespace gdp::io {
namespace {

class OiioEncoder final : public Encoder {
 public:
  explicit OiioEncoder(const std::string& path) : output_(OIIO::ImageOutput::create(path)) {
    if (output_) return;
    OIIO::geterror();  // clear OpenImageIO's pending message; ours names the cause
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext.empty()) throw CodecError("cannot write: no file extension to choose an image format by");
    throw CodecError(fmt::format("cannot write: no image format for extension '{}'", ext));
  }

  ~OiioEncoder() override {
    output_.reset();  // before the file it writes through
    file_.reset();
  }

  std::string format_name() const override { return output_->format_name(); }

  void open(const std::string& path, const EncodeSpec& request) override {
    const std::string format = format_name();
    OIIO::ImageSpec spec(request.width, request.height, request.channels, type_desc_of(request.sample_type));
    spec.attribute("oiio:UnassociatedAlpha", 1);  // write alpha as given, never un-premultiply it
    // OpenImageIO 2.4 takes the quality as "Compression" = "CODEC:Q" (jpeg and webp also accept
    // "CompressionQuality"; heif does not); without it JPEG is written at quality 98.
    if (format == "jpeg" || format == "webp" || format == "heif") {
      const std::string codec = format == "heif" ? "heic" : format;
      spec.attribute("Compression", fmt::format("{}:{}", codec, std::clamp(request.jpeg_quality, 1, 100)));
    }
    if (!request.compression.empty()) spec.attribute("Compression", request.compression);
    if (format == "tiff" && request.bigtiff) spec.attribute("tiff:bigtiff", 1);
    if (request.tile_size > 0) spec.tile_width = spec.tile_height = request.tile_size;
    tiled_ = request.tile_size > 0;
    width_ = request.width;
    // OpenImageIO 2.4's JPEG writer keeps the whole compressed file in memory when it writes
    // through a proxy: accept that up to kJpegBufferBytes of 8-bit pixels (some 10-100 MB of
    // JPEG); larger JPEGs stream to the file, where a failed write makes libjpeg exit() the
    // process (the temporary file is still removed, by gdp::cleanup's exit handler).
    const double pixel_bytes = static_cast<double>(request.width) * request.height * request.channels;
    const bool buffers_whole_file = format == "jpeg";
    if (output_->supports("ioproxy") && (!buffers_whole_file || pixel_bytes <= kJpegBufferBytes)) {
      file_ = std::make_unique<CheckedFile>(path);
      if (!output_->set_ioproxy(file_.get())) file_.reset();
    }
    if (!output_->open(path, spec)) {
      const std::string problem = one_line(output_->geterror());
      throw CodecError("cannot write: " + (file_ && file_->file().failed() ? file_->file().problem() : problem));
    }
    integer_file_ = !output_->spec().format.is_floating_point();
    stored_ = band_type_of(output_->spec());
    type_ = type_desc_of(stored_);
  }

  SampleType stored() const override { return stored_; }
  bool integer_file() const override { return integer_file_; }

  void write(int y0, int y1, const void* rows) override {
    const bool ok = tiled_ ? output_->write_tiles(0, width_, y0, y1, 0, 1, type_, rows)
                           : output_->write_scanlines(y0, y1, 0, type_, rows);
    // A failed write to the file itself explains more than the codec's message, if it has one.
    if (file_ && file_->file().failed()) throw CodecError("cannot write: " + file_->file().problem());
    if (!ok) throw CodecError("cannot write: " + one_line(output_->geterror()));
  }

  void close() override {
    const bool closed = output_->close();
    if (file_) {
      file_->close();
      if (file_->file().failed()) throw CodecError("cannot write: " + file_->file().problem());
    }
    if (!closed) throw CodecError("cannot write: " + one_line(output_->geterror()));
  }

 private:
  std::unique_ptr<CheckedFile> file_;  // declared before output_, but output_ is reset first (destructor)
  std::unique_ptr<OIIO::ImageOutput> output_;
  bool tiled_ = false, integer_file_ = false;
  int width_ = 0;
  SampleType stored_ = SampleType::Float;
  OIIO::TypeDesc type_ = OIIO::TypeFloat;
};

}  // namespace

std::unique_ptr<Encoder> create_oiio_encoder(const std::string& path) { return std::make_unique<OiioEncoder>(path); }

}  // namespace gdp::io
