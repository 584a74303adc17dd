// Encoding OpenEXR with OpenEXR's C++ library: half or float channels, scanline blocks or tiles, through a checked file.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfTiledOutputFile.h>
#include <Imath/half.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/exr_util.h"
#include "io/output_file.h"

namespace gdp::io {
namespace {

// OpenEXR's output through an io::OutputFile: writes always "succeed", a failure is recorded in
// the file and reported by the encoder.
class Stream final : public Imf::OStream {
 public:
  Stream(const std::string& path, OutputFile& file) : Imf::OStream(path.c_str()), file_(file) {}
  void write(const char c[], int n) override {
    file_.write_at(at_, c, static_cast<std::size_t>(n));
    at_ += static_cast<std::uint64_t>(n);
  }
  std::uint64_t tellp() override { return at_; }
  void seekp(std::uint64_t pos) override { at_ = pos; }

 private:
  OutputFile& file_;
  std::uint64_t at_ = 0;
};

// WriteOptions::compression ("zip", "dwaa:45", ...) into the header; a level after ':' applies to
// zip, zips, dwaa and dwab (other names: check_compression refuses them). Empty gives piz (lossless wavelet, 32-row blocks):
// on photographs a third of zip's CPU time (OpenEXR's and OpenImageIO's default; zlib, one
// thread) and smaller files, for half and float alike (docs/formats.md).
const CompressionName<Imf::Compression> kCompressions[] = {
    {"none", Imf::NO_COMPRESSION}, {"rle", Imf::RLE_COMPRESSION},   {"zips", Imf::ZIPS_COMPRESSION},
    {"zip", Imf::ZIP_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION},   {"pxr24", Imf::PXR24_COMPRESSION},
    {"b44", Imf::B44_COMPRESSION}, {"b44a", Imf::B44A_COMPRESSION}, {"dwaa", Imf::DWAA_COMPRESSION},
    {"dwab", Imf::DWAB_COMPRESSION}};

void set_compression(Imf::Header& header, const std::string& text) {
  const auto [name, level] = split_compression(text);
  header.compression() = compression_code(kCompressions, name, Imf::PIZ_COMPRESSION);
  if (!level) return;
  const Imf::Compression c = header.compression();
  if (c == Imf::ZIP_COMPRESSION || c == Imf::ZIPS_COMPRESSION)
    header.zipCompressionLevel() = std::clamp(std::atoi(level->c_str()), 1, 9);
  if ((c == Imf::DWAA_COMPRESSION || c == Imf::DWAB_COMPRESSION) && std::atof(level->c_str()) > 0)
    header.dwaCompressionLevel() = static_cast<float>(std::atof(level->c_str()));
}

class ExrEncoder final : public Encoder {
 public:
  std::string format_name() const override { return "openexr"; }
  std::string compression_refusal(const std::string& compression) const override {
    return io::compression_refusal(kCompressions, compression, "(':LEVEL' after zip, zips, dwaa, dwab)");
  }

  void open(const std::string& path, const EncodeSpec& spec) override {
    file_ = open_written(path);
    stream_ = std::make_unique<Stream>(path, *file_);
    width_ = spec.width;
    channels_ = spec.channels;
    tile_ = spec.tile_size;
    // Float and Double as 32-bit floats, everything else as half (as OpenImageIO 2.4 did).
    half_ = spec.sample_type != SampleType::Float && spec.sample_type != SampleType::Double;
    Imf::Header header(spec.width, spec.height);
    if (spec.frame) {  // the data window where it lies in the display window (a cropped layer)
      const FramePlacement& f = *spec.frame;
      header.displayWindow() =
          Imath::Box2i({f.frame_x, f.frame_y}, {f.frame_x + f.frame_width - 1, f.frame_y + f.frame_height - 1});
      header.dataWindow() = Imath::Box2i({f.x, f.y}, {f.x + spec.width - 1, f.y + spec.height - 1});
      origin_x_ = f.x;
      origin_y_ = f.y;
    }
    set_compression(header, spec.compression);
    names_ = exr_channel_names(spec.channels);
    for (const std::string& name : names_) header.channels().insert(name, Imf::Channel(half_ ? Imf::HALF : Imf::FLOAT));
    guarded([&] {
      if (tile_ > 0) {
        header.setTileDescription(Imf::TileDescription(tile_, tile_, Imf::ONE_LEVEL));
        tiles_ = std::make_unique<Imf::TiledOutputFile>(*stream_, header, exr_threads(true));
      } else {
        lines_ = std::make_unique<Imf::OutputFile>(*stream_, header, exr_threads(false));
      }
    });
  }

  SampleType stored() const override { return SampleType::Float; }
  bool integer_file() const override { return false; }

  // Whole tile rows when tiled: y0 is a multiple of the tile size, y1 too or the height.
  void write(int y0, int y1, const void* rows) override {
    const std::size_t samples = static_cast<std::size_t>(y1 - y0) * width_ * channels_;
    const char* base = static_cast<const char*>(rows);
    if (half_) {
      halves_.resize(samples);
      const float* from = static_cast<const float*>(rows);
      // Rounded to nearest even, as _Float16 would be, in less than half its time.
      for (std::size_t i = 0; i < samples; ++i) halves_[i] = Imath::half(from[i]);
      base = reinterpret_cast<const char*>(halves_.data());
    }
    const std::size_t sample = half_ ? 2 : 4, xs = sample * channels_, ys = xs * width_;
    Imf::FrameBuffer frame;
    for (int c = 0; c < channels_; ++c)
      frame.insert(names_[c], Imf::Slice::Make(half_ ? Imf::HALF : Imf::FLOAT, base + c * sample, Imath::V2i(origin_x_, origin_y_ + y0),
                                               width_, y1 - y0, xs, ys));
    guarded([&] {
      if (tiles_) {
        tiles_->setFrameBuffer(frame);
        tiles_->writeTiles(0, tiles_->numXTiles() - 1, y0 / tile_, (y1 - 1) / tile_);
      } else {
        lines_->setFrameBuffer(frame);
        lines_->writePixels(y1 - y0);
      }
    });
    check_written(*file_);
  }

  // OpenEXR writes the table of block offsets when its file object is destroyed.
  void close() override {
    guarded([&] {
      lines_.reset();
      tiles_.reset();
    });
    close_written(*file_);
  }

 private:
  // Runs an OpenEXR call; its exceptions become write errors (the file's own failure first).
  template <class F>
  void guarded(F&& call) {
    try {
      call();
    } catch (const std::exception& e) {
      throw write_error(file_.get(), one_line(e.what()));
    }
  }

  std::unique_ptr<OutputFile> file_;             // declared before the OpenEXR files:
  std::unique_ptr<Stream> stream_;               // outlives them (they write when destroyed)
  std::unique_ptr<Imf::OutputFile> lines_;       // scanline files
  std::unique_ptr<Imf::TiledOutputFile> tiles_;  // tiled files
  std::vector<std::string> names_;
  std::vector<Imath::half> halves_;
  int width_ = 0, channels_ = 0, tile_ = 0;
  int origin_x_ = 0, origin_y_ = 0;  // the data window's top-left pixel
  bool half_ = true;
};

}  // namespace

std::unique_ptr<Encoder> create_exr_encoder() { return std::make_unique<ExrEncoder>(); }

}  // namespace gdp::io
