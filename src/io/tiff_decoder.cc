// Decoding TIFF: strips row by row (uncompressed: the window's bytes only), tiles only where the window needs them; chunky or planar.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "gdp/size_check.h"
#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/tiff_util.h"
#include "io/drop_behind.h"
#include "util/exact_io.h"

namespace gdp::io {
namespace {

std::atomic<long> tiles_decoded{0};

// Separate-plane strips are decoded whole (one cached per plane); above this many bytes for all
// planes together the file is left to OpenImageIO instead.
constexpr std::size_t kMaxPlaneStripBytes = std::size_t{64} << 20;
constexpr std::uint64_t kMaxTileBytes = std::uint64_t{64} << 20;  // one tile's bytes
// Files at least this large, read front to back in chunky strips, leave the page cache a window behind
// the reader (io/drop_behind.h): a 3.2 GB input would otherwise take 3.2 GB of fresh cache
// pages, at several times the system time of reading into recycled ones (docs/scaling.md).
constexpr off_t kDropBehindFrom = off_t{256} << 20;

class TiffDecoder final : public Decoder {
 public:
  ~TiffDecoder() override {
    if (tif_) TIFFClose(tif_);
  }

  // False for a variant left to OpenImageIO (palette, CMYK, 1-bit, signed integers, ...).
  bool open(const std::string& path, int page) {
    // "m": no memory mapping, whose touched pages would count as resident memory (the whole file).
    tif_ = TIFFOpenExt(path.c_str(), "rm", messages_.options());
    if (!tif_) throw CodecError(fmt::format("not a TIFF file libtiff can read ({})", messages_.take()));
    if (page > 0 && !TIFFSetDirectory(tif_, static_cast<tdir_t>(page)))
      throw CodecError(fmt::format("has no page {} ({} page(s))", page, static_cast<int>(TIFFNumberOfDirectories(tif_))));
    std::uint32_t width = 0, height = 0;
    std::uint16_t spp = 1, bits = 1, format = SAMPLEFORMAT_UINT, photometric = 0, planar = PLANARCONFIG_CONTIG;
    std::uint16_t compression = COMPRESSION_NONE;
    TIFFGetField(tif_, TIFFTAG_IMAGEWIDTH, &width);
    TIFFGetField(tif_, TIFFTAG_IMAGELENGTH, &height);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_SAMPLESPERPIXEL, &spp);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_SAMPLEFORMAT, &format);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_PLANARCONFIG, &planar);
    TIFFGetFieldDefaulted(tif_, TIFFTAG_COMPRESSION, &compression);
    if (!TIFFGetField(tif_, TIFFTAG_PHOTOMETRIC, &photometric)) return false;
    if (!TIFFIsCODECConfigured(compression)) return false;
    if (photometric == PHOTOMETRIC_YCBCR && compression == COMPRESSION_JPEG && spp == 3) {
      TIFFSetField(tif_, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);  // libjpeg converts to RGB
    } else if (photometric != PHOTOMETRIC_MINISBLACK && !(photometric == PHOTOMETRIC_RGB && spp >= 3)) {
      return false;
    }
    if (format == SAMPLEFORMAT_UINT && bits == 8) kind_ = SampleType::UInt8;
    else if (format == SAMPLEFORMAT_UINT && bits == 16) kind_ = SampleType::UInt16;
    else if (format == SAMPLEFORMAT_IEEEFP && bits == 16) kind_ = SampleType::Half;
    else if (format == SAMPLEFORMAT_IEEEFP && bits == 32) kind_ = SampleType::Float;
    else if (format == SAMPLEFORMAT_IEEEFP && bits == 64) kind_ = SampleType::Double;
    else return false;
    check_image_size(width, height, spp);
    messages_.warn_as_errors();  // from here on libtiff decodes pixels
    planar_ = planar == PLANARCONFIG_SEPARATE && spp > 1;
    layout_.width = static_cast<int>(width);
    layout_.height = static_cast<int>(height);
    layout_.channels = spp;
    layout_.info = {kind_, "tiff", false};
    layout_.stored = band_type(kind_);
    if (TIFFIsTiled(tif_)) {
      std::uint32_t tw = 0, th = 0;
      TIFFGetField(tif_, TIFFTAG_TILEWIDTH, &tw);
      TIFFGetField(tif_, TIFFTAG_TILELENGTH, &th);
      if (tw == 0 || th == 0) return false;
      // The header's tile size is allocated (and zeroed) before any pixel is read: a tiny file
      // declaring 65536x65536 tiles took gigabytes. Real tiles are far below this bound.
      const std::uint64_t tile = TIFFTileSize64(tif_);
      if (tile == 0 || tile > kMaxTileBytes)
        throw CodecError(fmt::format("tiles of {}x{} ({} bytes each) are not what gdp reads (at most {} MB)", tw, th,
                                     tile, kMaxTileBytes >> 20));
      layout_.tile_width = static_cast<int>(tw);
      layout_.tile_height = static_cast<int>(th);
      chunk_.resize(static_cast<std::size_t>(tile));
    } else if (planar_) {
      std::uint32_t rows = 0;
      TIFFGetFieldDefaulted(tif_, TIFFTAG_ROWSPERSTRIP, &rows);
      rows_per_strip_ = static_cast<int>(std::min<std::uint32_t>(std::max<std::uint32_t>(rows, 1), height));
      const std::size_t strip = static_cast<std::size_t>(TIFFStripSize(tif_));
      if (strip * spp > kMaxPlaneStripBytes) return false;
      chunk_.resize(strip * spp);
      cached_strip_.assign(spp, -1);
    } else {
      chunk_.resize(static_cast<std::size_t>(TIFFScanlineSize(tif_)));
      raw_ = compression == COMPRESSION_NONE && raw_strips(bits);
    }
    struct stat st{};
    if (!TIFFIsTiled(tif_) && !planar_ && ::fstat(TIFFFileno(tif_), &st) == 0 && st.st_size >= kDropBehindFrom)
      drop_behind_ = DropBehind(kDropBehindWindow);
    return true;
  }

  const ImageLayout& layout() const override { return layout_; }

  void read(int y0, int y1, int x0, int x1, void* out) override {
    if (layout_.tile_width > 0) read_tiles(y0, y1, x0, x1, static_cast<unsigned char*>(out));
    else if (planar_) read_plane_strips(y0, y1, x0, x1, static_cast<unsigned char*>(out));
    else if (raw_) read_raw(y0, y1, x0, x1, static_cast<unsigned char*>(out));
    else read_scanlines(y0, y1, x0, x1, static_cast<unsigned char*>(out));
  }

 private:
  // Whether uncompressed chunky strips can be read as bytes of the file: every strip holds its
  // rows whole, the samples in the machine's order and bits (as libtiff would hand them out).
  // Then only a column window's bytes are read (a rank of a distributed solve reads its columns).
  bool raw_strips(int bits) {
    std::uint16_t fill = FILLORDER_MSB2LSB;
    TIFFGetFieldDefaulted(tif_, TIFFTAG_FILLORDER, &fill);
    if (fill != FILLORDER_MSB2LSB || (TIFFIsByteSwapped(tif_) && bits > 8)) return false;
    std::uint32_t rows = 0;
    TIFFGetFieldDefaulted(tif_, TIFFTAG_ROWSPERSTRIP, &rows);
    rows_per_strip_ = static_cast<int>(std::min<std::uint32_t>(std::max<std::uint32_t>(rows, 1), layout_.height));
    const std::uint64_t line = chunk_.size();
    const std::uint32_t strips = TIFFNumberOfStrips(tif_);
    if (strips != static_cast<std::uint32_t>((layout_.height + rows_per_strip_ - 1) / rows_per_strip_)) return false;
    strip_offsets_.resize(strips);
    for (std::uint32_t s = 0; s < strips; ++s) {
      const std::uint64_t first = std::uint64_t{s} * rows_per_strip_;
      const std::uint64_t n = std::min<std::uint64_t>(rows_per_strip_, layout_.height - first);
      strip_offsets_[s] = TIFFGetStrileOffset(tif_, s);
      if (strip_offsets_[s] == 0 || TIFFGetStrileByteCount(tif_, s) < n * line) return false;
    }
    return true;
  }

  // Uncompressed chunky strips: the window's bytes of each row with one pread (rows whose windows
  // follow each other in the file, as whole rows of a strip do, with one), straight into the band
  // where the file's samples are the band's, else through a scanline buffer.
  void read_raw(int y0, int y1, int x0, int x1, unsigned char* out) {
    const std::size_t in = sample_bytes(kind_), count = static_cast<std::size_t>(x1 - x0) * layout_.channels;
    const std::size_t bytes = count * in, line = chunk_.size(), out_row = count * band_bytes();
    const bool direct = kind_ == layout_.stored;
    const int fd = TIFFFileno(tif_);
    const auto row_at = [&](int y) {  // where row y starts in the file
      return strip_offsets_[y / rows_per_strip_] + static_cast<std::uint64_t>(y % rows_per_strip_) * line;
    };
    std::uint64_t end = 0;
    for (int y = y0; y < y1;) {
      const std::uint64_t at = row_at(y) + static_cast<std::uint64_t>(x0) * layout_.channels * in;
      int n = 1;  // rows in this read
      if (direct)
        while (y + n < y1 && bytes == line && row_at(y + n) == at + n * line) ++n;
      unsigned char* dst = direct ? out + (y - y0) * out_row : chunk_.data();
      const util::Transfer t = util::pread_full(fd, dst, bytes * n, at);
      if (t.done != bytes * n)
        throw CodecError(fmt::format("cannot read pixels at row {}: {}", y,
                                     t.error ? std::generic_category().message(t.error) : "the file ends early"));
      if (!direct) tiff_to_band(kind_, chunk_.data(), 1, out + (y - y0) * out_row, 1, count);
      end = std::max(end, at + bytes * n);
      y += n;
    }
    drop_behind_.read(fd, static_cast<std::size_t>(end));
  }

  std::size_t band_bytes() const { return sample_bytes(layout_.stored); }
  CodecError error(int y) { return CodecError(fmt::format("cannot read pixels at row {}: {}", y, messages_.take())); }

  // Chunky strips, a row at a time (libtiff decodes within a strip as it goes: memory O(row)).
  void read_scanlines(int y0, int y1, int x0, int x1, unsigned char* out) {
    const int ch = layout_.channels;
    const std::size_t count = static_cast<std::size_t>(x1 - x0) * ch, in = sample_bytes(kind_);
    for (int y = y0; y < y1; ++y) {
      if (TIFFReadScanline(tif_, chunk_.data(), static_cast<std::uint32_t>(y), 0) < 0 || messages_.warned())
        throw error(y);
      tiff_to_band(kind_, chunk_.data() + static_cast<std::size_t>(x0) * ch * in, 1,
                   out + (y - y0) * count * band_bytes(), 1, count);
    }
    read_up_to_here();
  }

  // What libtiff has read so far (its reads go front to back through the strips) can leave the cache.
  void read_up_to_here() {
    const int fd = TIFFFileno(tif_);
    const off_t at = ::lseek(fd, 0, SEEK_CUR);
    if (at > 0) drop_behind_.read(fd, static_cast<std::size_t>(at));
  }

  // Separate planes in strips: each plane's strip decoded whole and kept while rows need it.
  void read_plane_strips(int y0, int y1, int x0, int x1, unsigned char* out) {
    const int ch = layout_.channels;
    const std::size_t strip_bytes = chunk_.size() / ch, in = sample_bytes(kind_);
    const std::size_t row_in = static_cast<std::size_t>(layout_.width) * in;
    const std::size_t out_row = static_cast<std::size_t>(x1 - x0) * ch * band_bytes();
    for (int y = y0; y < y1; ++y) {
      const int strip = y / rows_per_strip_;
      for (int c = 0; c < ch; ++c) {
        unsigned char* buffer = chunk_.data() + c * strip_bytes;
        if (cached_strip_[c] != strip) {
          const tstrile_t index = TIFFComputeStrip(tif_, static_cast<std::uint32_t>(y), static_cast<std::uint16_t>(c));
          if (TIFFReadEncodedStrip(tif_, index, buffer, static_cast<tmsize_t>(strip_bytes)) < 0 || messages_.warned())
            throw error(y);
          cached_strip_[c] = strip;
        }
        const unsigned char* src = buffer + (y - strip * rows_per_strip_) * row_in + x0 * in;
        tiff_to_band(kind_, src, 1, out + (y - y0) * out_row + c * band_bytes(), ch, static_cast<std::size_t>(x1 - x0));
      }
    }
  }

  // Tiles overlapping rows [y0, y1) and columns [x0, x1) only.
  void read_tiles(int y0, int y1, int x0, int x1, unsigned char* out) {
    const int ch = layout_.channels, tw = layout_.tile_width, th = layout_.tile_height;
    const int planes = planar_ ? ch : 1, per_tile = planar_ ? 1 : ch;
    const std::size_t in = sample_bytes(kind_), bb = band_bytes();
    const std::size_t out_row = static_cast<std::size_t>(x1 - x0) * ch * bb;
    for (int ty = y0 / th * th; ty < y1; ty += th) {
      for (int tx = x0 / tw * tw; tx < x1; tx += tw) {
        const int ya = std::max(ty, y0), yb = std::min({ty + th, y1, layout_.height});
        const int xa = std::max(tx, x0), xb = std::min({tx + tw, x1, layout_.width});
        for (int p = 0; p < planes; ++p) {
          const ttile_t index = TIFFComputeTile(tif_, static_cast<std::uint32_t>(tx), static_cast<std::uint32_t>(ty), 0,
                                                static_cast<std::uint16_t>(p));
          if (TIFFReadEncodedTile(tif_, index, chunk_.data(), static_cast<tmsize_t>(chunk_.size())) < 0 ||
              messages_.warned())
            throw error(ty);
          tiles_decoded.fetch_add(1, std::memory_order_relaxed);
          for (int y = ya; y < yb; ++y) {
            const unsigned char* src =
                chunk_.data() + ((static_cast<std::size_t>(y - ty) * tw + (xa - tx)) * per_tile) * in;
            unsigned char* dst = out + (y - y0) * out_row + (static_cast<std::size_t>(xa - x0) * ch + p) * bb;
            if (planar_) tiff_to_band(kind_, src, 1, dst, ch, static_cast<std::size_t>(xb - xa));
            else tiff_to_band(kind_, src, 1, dst, 1, static_cast<std::size_t>(xb - xa) * ch);
          }
        }
      }
    }
  }

  TiffMessages messages_;  // before tif_: outlives the handle that reports to it
  TIFF* tif_ = nullptr;
  ImageLayout layout_;
  SampleType kind_ = SampleType::UInt8;
  bool planar_ = false;
  int rows_per_strip_ = 1;
  std::vector<unsigned char> chunk_;  // a scanline, a tile, or one strip per plane
  std::vector<int> cached_strip_;
  bool raw_ = false;  // uncompressed chunky strips, read as bytes (raw_strips())
  std::vector<std::uint64_t> strip_offsets_;
  DropBehind drop_behind_;  // a large strip file's pages out of the cache behind the reader
};

}  // namespace

std::unique_ptr<Decoder> open_tiff_decoder(const std::string& path, int page) {
  auto decoder = std::make_unique<TiffDecoder>();
  if (!decoder->open(path, page)) return nullptr;
  return decoder;
}

long tiff_tiles_decoded() { return tiles_decoded.load(std::memory_order_relaxed); }

}  // namespace gdp::io
