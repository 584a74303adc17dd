// Decoding OpenEXR with OpenEXR's C++ library: scanline blocks as rows are asked for, tiles only where the column window needs them.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfVersion.h>
#include <OpenEXR/ImfTiledInputPart.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "gdp/size_check.h"
#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/exr_util.h"

namespace gdp::io {
namespace {

std::atomic<long> tiles_decoded{0};

class ExrDecoder final : public Decoder {
 public:
  // The header, gdp's size check (io/size_check.h), then the first part's reader, which
  // allocates block buffers.
  explicit ExrDecoder(const std::string& path) {
    const std::string problem = "not an OpenEXR file OpenEXR can read";
    library(problem, [&] { read_header(path); });
    check_image_size(width_, height_, static_cast<int>(channels_.size()));
    library(problem, [&] { open_part(path); });
  }

  const ImageLayout& layout() const override { return layout_; }

  // Rows [y0, y1) of the tile columns covering [x0, x1) (scanline files: of every column),
  // decoded straight into `out` when that is the window, else a piece at a time into scratch_.
  void read(int y0, int y1, int x0, int x1, void* out) override {
    const int tw = layout_.tile_width, th = layout_.tile_height;
    const int rx0 = tiled_ ? x0 / tw * tw : 0;
    const int rx1 = tiled_ ? std::min(layout_.width, (x1 + tw - 1) / tw * tw) : layout_.width;
    const bool whole_tile_rows = !tiled_ || (y0 % th == 0 && (y1 % th == 0 || y1 == layout_.height));
    auto* dst = static_cast<unsigned char*>(out);
    library(fmt::format("cannot read pixels of rows {} to {}", y0, y1 - 1), [&] {
      if (rx0 == x0 && rx1 == x1 && whole_tile_rows) {
        decode(y0, y1, rx0, rx1, dst);
        return;
      }
      // Pieces of a tile row, or of about kBandSamples samples (at least one block) for scanlines.
      const std::size_t region_row = static_cast<std::size_t>(rx1 - rx0) * pixel_bytes();
      const std::size_t out_row = static_cast<std::size_t>(x1 - x0) * pixel_bytes();
      const int piece = tiled_ ? th : std::max<int>(lines_per_block_, static_cast<int>(kBandSamples * 4 / region_row));
      for (int y = y0; y < y1;) {
        const int p0 = tiled_ ? y / th * th : y;
        const int p1 = std::min(layout_.height, tiled_ ? p0 + th : std::min(y1, y + piece));
        scratch_.resize(static_cast<std::size_t>(p1 - p0) * region_row);
        decode(p0, p1, rx0, rx1, scratch_.data());
        for (; y < std::min(y1, p1); ++y)
          std::memcpy(dst + (y - y0) * out_row,
                      scratch_.data() + (y - p0) * region_row + static_cast<std::size_t>(x0 - rx0) * pixel_bytes(),
                      out_row);
      }
    });
  }

 private:
  std::size_t pixel_bytes() const { return static_cast<std::size_t>(layout_.channels) * 4; }

  // Runs OpenEXR calls: the library's exceptions become CodecErrors "problem: message"; gdp's own
  // errors and std::bad_alloc pass as they are.
  template <class F>
  static void library(const std::string& problem, F&& call) {
    try {
      call();
    } catch (const CodecError&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw CodecError(fmt::format("{}: {}", problem, one_line(e.what())));
    }
  }

  // The first part's header (as OpenImageIO reads it): size, channels, layout. Read on its own,
  // before OpenEXR's file reader reads the table of blocks.
  void read_header(const std::string& path) {
    const ExrHeader read = read_exr_header(path);
    const Imf::Header& header = read.header;
    const int version = read.version;
    const std::string type = header.hasType()      ? header.type()
                             : Imf::isTiled(version) ? Imf::TILEDIMAGE
                                                     : Imf::SCANLINEIMAGE;
    if (Imf::isDeepData(type)) throw CodecError("deep OpenEXR images are not supported");
    tiled_ = Imf::isTiled(type);
    const Imath::Box2i window = header.dataWindow();
    origin_x_ = window.min.x;
    origin_y_ = window.min.y;
    width_ = std::int64_t{window.max.x} - window.min.x + 1;
    height_ = std::int64_t{window.max.y} - window.min.y + 1;
    std::vector<std::string> names;
    std::vector<Imf::PixelType> types;
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
      if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
        throw CodecError(fmt::format("subsampled channels are not supported (channel \"{}\" is sampled {} x {})",
                                     c.name(), c.channel().xSampling, c.channel().ySampling));
      names.emplace_back(c.name());
      types.push_back(c.channel().type);
    }
    if (names.empty()) throw CodecError("no channels");
    bool all_half = true;
    for (int i : exr_channel_order(names)) {
      channels_.push_back({names[i], types[i]});
      all_half = all_half && types[i] == Imf::HALF;
    }
    layout_.info = {all_half ? SampleType::Half : SampleType::Float, "openexr", false};
  }

  void open_part(const std::string& path) {
    file_ = std::make_unique<Imf::MultiPartInputFile>(path.c_str(), exr_threads(tiled_));
    layout_.width = static_cast<int>(width_);
    layout_.height = static_cast<int>(height_);
    layout_.channels = static_cast<int>(channels_.size());
    layout_.stored = SampleType::Float;
    if (tiled_) {
      tiles_ = std::make_unique<Imf::TiledInputPart>(*file_, 0);
      layout_.tile_width = static_cast<int>(tiles_->tileXSize());  // level 0 of MIP/RIP maps
      layout_.tile_height = static_cast<int>(tiles_->tileYSize());
    } else {
      lines_ = std::make_unique<Imf::InputPart>(*file_, 0);
      lines_per_block_ = lines_per_block(file_->header(0).compression());
    }
  }

  static int lines_per_block(Imf::Compression compression) {
    switch (compression) {
      case Imf::ZIP_COMPRESSION: case Imf::PXR24_COMPRESSION: return 16;
      case Imf::PIZ_COMPRESSION: case Imf::B44_COMPRESSION: case Imf::B44A_COMPRESSION:
      case Imf::DWAA_COMPRESSION: return 32;
      case Imf::DWAB_COMPRESSION: return 256;
      default: return 1;
    }
  }

  // Rows [y0, y1), columns [x0, x1) (whole tiles, or whole rows of a scanline file) into `to`:
  // interleaved floats; unsigned integer channels as OpenImageIO converts them (v / 2^32).
  void decode(int y0, int y1, int x0, int x1, unsigned char* to) {
    const std::size_t xs = pixel_bytes(), ys = static_cast<std::size_t>(x1 - x0) * xs;
    const Imath::V2i origin(origin_x_ + x0, origin_y_ + y0);
    Imf::FrameBuffer frame;
    bool integers = false;
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      const bool uint = channels_[c].type == Imf::UINT;
      integers = integers || uint;
      frame.insert(channels_[c].name, Imf::Slice::Make(uint ? Imf::UINT : Imf::FLOAT, to + c * 4, origin, x1 - x0,
                                                         y1 - y0, xs, ys));
    }
    if (tiled_) {
      const int tw = layout_.tile_width, th = layout_.tile_height;
      tiles_->setFrameBuffer(frame);
      tiles_->readTiles(x0 / tw, (x1 - 1) / tw, y0 / th, (y1 - 1) / th);
      tiles_decoded.fetch_add(static_cast<long>((x1 - 1) / tw - x0 / tw + 1) * ((y1 - 1) / th - y0 / th + 1),
                              std::memory_order_relaxed);
    } else {
      lines_->setFrameBuffer(frame);
      lines_->readPixels(origin_y_ + y0, origin_y_ + y1 - 1);
    }
    if (!integers) return;
    const std::size_t pixels = static_cast<std::size_t>(y1 - y0) * (x1 - x0);
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      if (channels_[c].type != Imf::UINT) continue;
      for (std::size_t i = 0; i < pixels; ++i) {
        std::uint32_t v;
        std::memcpy(&v, to + i * xs + c * 4, 4);
        const float f = static_cast<float>(v) * (1.0f / static_cast<float>(std::numeric_limits<std::uint32_t>::max()));
        std::memcpy(to + i * xs + c * 4, &f, 4);
      }
    }
  }

  struct Channel {
    std::string name;
    Imf::PixelType type;
  };

  std::unique_ptr<Imf::MultiPartInputFile> file_;  // before the parts: outlives them
  std::unique_ptr<Imf::InputPart> lines_;
  std::unique_ptr<Imf::TiledInputPart> tiles_;
  std::vector<Channel> channels_;  // in OpenImageIO's order
  ImageLayout layout_;
  bool tiled_ = false;
  int origin_x_ = 0, origin_y_ = 0;  // of the data window
  long long width_ = 0, height_ = 0;  // of the data window, before gdp's size check
  int lines_per_block_ = 1;
  std::vector<unsigned char> scratch_;
};

}  // namespace

std::unique_ptr<Decoder> open_exr_decoder(const std::string& path) { return std::make_unique<ExrDecoder>(path); }

long exr_tiles_decoded() { return tiles_decoded.load(std::memory_order_relaxed); }

}  // namespace gdp::io
