// Encoding TIFF with libtiff: strips or tiles, 8/16-bit unsigned or 32/64-bit float, compressed (deflate on two threads), through a checked file.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/output_file.h"
#include "io/tiff_strip_compressor.h"
#include "io/tiff_geo.h"
#include "io/tiff_util.h"

namespace gdp::io {
namespace {

constexpr int kCompressThreads = 2;
constexpr std::size_t kStripBytes = std::size_t{1} << 20;

// libtiff's I/O through an io::OutputFile (handle = the encoder's Io). Writes always "succeed";
// a failure is recorded in the file and reported by the encoder.
struct Io {
  OutputFile* file = nullptr;
  std::int64_t at = 0;
};

tmsize_t io_read(thandle_t h, void* data, tmsize_t size) {
  Io* io = static_cast<Io*>(h);
  const std::size_t n = io->file->read_at(io->at, data, static_cast<std::size_t>(size));
  io->at += static_cast<std::int64_t>(n);
  return static_cast<tmsize_t>(n);
}

tmsize_t io_write(thandle_t h, void* data, tmsize_t size) {
  Io* io = static_cast<Io*>(h);
  io->file->write_at(io->at, data, static_cast<std::size_t>(size));
  io->at += size;
  return size;
}

toff_t io_seek(thandle_t h, toff_t offset, int whence) {
  Io* io = static_cast<Io*>(h);
  const auto off = static_cast<std::int64_t>(offset);
  if (whence == SEEK_SET) io->at = off;
  else if (whence == SEEK_CUR) io->at += off;
  else io->at = io->file->size() + off;
  return static_cast<toff_t>(io->at);
}

int io_close(thandle_t) { return 0; }  // the encoder closes the file itself
toff_t io_size(thandle_t h) { return static_cast<toff_t>(static_cast<Io*>(h)->file->size()); }
int io_map(thandle_t, void**, toff_t*) { return 0; }
void io_unmap(thandle_t, void*, toff_t) {}

const CompressionName<std::uint16_t> kCompressions[] = {
    {"none", COMPRESSION_NONE}, {"lzw", COMPRESSION_LZW},   {"zip", COMPRESSION_ADOBE_DEFLATE},
    {"deflate", COMPRESSION_ADOBE_DEFLATE}, {"packbits", COMPRESSION_PACKBITS},
    {"jpeg", COMPRESSION_JPEG}, {"zstd", COMPRESSION_ZSTD}, {"lzma", COMPRESSION_LZMA}};

// WriteOptions::compression ("zip", "lzw:...", ...) as a libtiff code and a level (0: default).
// An empty or unavailable name gives zip (deflate), as OpenImageIO 2.4 did.
std::pair<std::uint16_t, int> compression_of(const std::string& text) {
  const CompressionSpec spec = split_compression(text);
  const int level = spec.level ? std::atoi(spec.level->c_str()) : 0;
  std::uint16_t code = compression_code(kCompressions, spec.name, std::uint16_t{COMPRESSION_ADOBE_DEFLATE});
  if (!TIFFIsCODECConfigured(code)) code = COMPRESSION_ADOBE_DEFLATE;
  return {code, level};
}

class TiffEncoder final : public Encoder {
 public:
  ~TiffEncoder() override {
    if (tif_) TIFFCleanup(tif_);  // abandoned: free without writing the directory
  }

  std::string format_name() const override { return "tiff"; }
  std::string compression_refusal(const std::string& compression) const override {
    return io::compression_refusal(kCompressions, compression, "(':LEVEL' after zip, zstd, lzma)");
  }

  void open(const std::string& path, const EncodeSpec& spec) override {
    file_ = open_written(path);
    io_.file = file_.get();
    width_ = spec.width;
    height_ = spec.height;
    channels_ = spec.channels;
    tile_ = spec.tile_size;
    // Half is written as Float, as OpenImageIO 2.4 did.
    kind_ = spec.sample_type == SampleType::Half ? SampleType::Float : spec.sample_type;
    stored_ = band_type(kind_);
    tif_ = TIFFClientOpenExt(path.c_str(), spec.bigtiff ? "w8" : "w", &io_, io_read, io_write, io_seek, io_close,
                             io_size, io_map, io_unmap, messages_.options());
    if (!tif_) throw failure();
    const bool floating = kind_ == SampleType::Float || kind_ == SampleType::Double;
    const int bits = static_cast<int>(sample_bytes(kind_) * 8);
    auto [compression, level] = compression_of(spec.compression);
    if (compression == COMPRESSION_JPEG && !(kind_ == SampleType::UInt8 && channels_ == 3))
      compression = COMPRESSION_ADOBE_DEFLATE;  // JPEG holds 8-bit RGB only
    int photometric = channels_ >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK;
    TIFFSetField(tif_, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(width_));
    TIFFSetField(tif_, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(height_));
    TIFFSetField(tif_, TIFFTAG_SAMPLESPERPIXEL, static_cast<std::uint16_t>(channels_));
    TIFFSetField(tif_, TIFFTAG_BITSPERSAMPLE, static_cast<std::uint16_t>(bits));
    TIFFSetField(tif_, TIFFTAG_SAMPLEFORMAT, floating ? SAMPLEFORMAT_IEEEFP : SAMPLEFORMAT_UINT);
    TIFFSetField(tif_, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif_, TIFFTAG_ORIENTATION, ORIENTATION_TOPLEFT);
    TIFFSetField(tif_, TIFFTAG_COMPRESSION, compression);
    raw_ = compression == COMPRESSION_NONE;
    if (compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_LZW ||
        compression == COMPRESSION_ZSTD || compression == COMPRESSION_LZMA)
      TIFFSetField(tif_, TIFFTAG_PREDICTOR, floating ? PREDICTOR_FLOATINGPOINT : PREDICTOR_HORIZONTAL);
    if (compression == COMPRESSION_ADOBE_DEFLATE && level > 0) TIFFSetField(tif_, TIFFTAG_ZIPQUALITY, std::clamp(level, 1, 9));
    if (compression == COMPRESSION_ZSTD && level > 0) TIFFSetField(tif_, TIFFTAG_ZSTD_LEVEL, std::clamp(level, 1, 22));
    if (compression == COMPRESSION_LZMA && level > 0) TIFFSetField(tif_, TIFFTAG_LZMAPRESET, std::clamp(level, 0, 9));
    if (compression == COMPRESSION_JPEG) {
      TIFFSetField(tif_, TIFFTAG_JPEGQUALITY, std::clamp(level > 0 ? level : 95, 1, 100));
      photometric = PHOTOMETRIC_YCBCR;  // libjpeg converts from RGB: compresses much better
    }
    TIFFSetField(tif_, TIFFTAG_PHOTOMETRIC, photometric);
    if (compression == COMPRESSION_JPEG) TIFFSetField(tif_, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);
    if (channels_ == 2 || channels_ == 4) {
      const std::uint16_t extra[1] = {EXTRASAMPLE_UNASSALPHA};  // the last channel: alpha, kept as given
      TIFFSetField(tif_, TIFFTAG_EXTRASAMPLES, 1, extra);
    } else if (channels_ > 4) {
      std::vector<std::uint16_t> extra(static_cast<std::size_t>(channels_ - 3), EXTRASAMPLE_UNSPECIFIED);
      TIFFSetField(tif_, TIFFTAG_EXTRASAMPLES, static_cast<std::uint16_t>(extra.size()), extra.data());
    }
    if (spec.geo) write_geotiff(tif_, *spec.geo);
    const int deflate_level = level > 0 ? std::clamp(level, 1, 9) : 6;
    if (tile_ > 0) {
      TIFFSetField(tif_, TIFFTAG_TILEWIDTH, static_cast<std::uint32_t>(tile_));
      TIFFSetField(tif_, TIFFTAG_TILELENGTH, static_cast<std::uint32_t>(tile_));
      chunk_.resize(static_cast<std::size_t>(tile_) * tile_ * channels_ * sample_bytes(kind_));
      if (compression == COMPRESSION_ADOBE_DEFLATE)  // tiles' rows are tile_ pixels wide
        compressor_ = std::make_unique<StripCompressor>(
            StripFormat{tile_, channels_, sample_bytes(kind_), floating, deflate_level}, kCompressThreads);
    } else {
      // 32 rows (as OpenImageIO wrote them), fewer where a strip would exceed kStripBytes (wide
      // float images), so that the strips in flight stay small; JPEG needs multiples of 16.
      const std::size_t file_row = static_cast<std::size_t>(width_) * channels_ * sample_bytes(kind_);
      rows_per_strip_ = compression == COMPRESSION_JPEG
                            ? 64
                            : static_cast<int>(std::clamp<std::size_t>(kStripBytes / file_row, 1, 32));
      TIFFSetField(tif_, TIFFTAG_ROWSPERSTRIP, static_cast<std::uint32_t>(rows_per_strip_));
      chunk_.resize(static_cast<std::size_t>(rows_per_strip_) * width_ * channels_ * sample_bytes(kind_));
      // Deflated strips are compressed by gdp on two threads and written raw (same bytes a
      // reader expects: predictor, then a zlib stream); libtiff would deflate them one at a time.
      if (compression == COMPRESSION_ADOBE_DEFLATE)
        compressor_ = std::make_unique<StripCompressor>(
            StripFormat{width_, channels_, sample_bytes(kind_), floating, deflate_level}, kCompressThreads);
    }
    check_file();
  }

  SampleType stored() const override { return stored_; }
  // Strips are assembled in chunk_: a row put at its place there is not copied again. (Doubles
  // are widened from the floats written, so they take the copy.)
  unsigned char* row_space(int) override {
    if (tile_ > 0 || kind_ == SampleType::Double) return nullptr;
    return chunk_.data() + static_cast<std::size_t>(filled_) * width_ * channels_ * sample_bytes(kind_);
  }
  bool integer_file() const override { return kind_ == SampleType::UInt8 || kind_ == SampleType::UInt16; }

  void write(int y0, int y1, const void* rows) override {
    const auto* src = static_cast<const unsigned char*>(rows);
    const std::size_t row_bytes = static_cast<std::size_t>(width_) * channels_ * sample_bytes(stored_);
    if (tile_ > 0) {
      write_tiles(y0, y1, src, row_bytes);
    } else {
      write_strips(y0, y1, src, row_bytes);
    }
    check_file();
  }

  void close() override {
    if (compressor_) compressor_->finish(sink());
    const bool flushed = TIFFFlush(tif_) == 1;
    check_file();
    if (!flushed) throw failure();
    TIFFClose(tif_);
    tif_ = nullptr;
    close_written(*file_);
  }

 private:
  static void to_double(const unsigned char* src, unsigned char* dst, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
      float f;
      std::memcpy(&f, src + i * 4, 4);
      const double d = f;
      std::memcpy(dst + i * 8, &d, 8);
    }
  }

  // Rows collect in chunk_ (a whole strip's room; filled_ rows so far, put there by the caller
  // through row_space() or copied) until a strip is whole (or the image ends), which is then
  // encoded in one call: libtiff deflates whole strips with libdeflate, rows one by one with zlib
  // (~2x slower).
  void write_strips(int y0, int y1, const unsigned char* src, std::size_t row_bytes) {
    const std::size_t count = static_cast<std::size_t>(width_) * channels_;
    const std::size_t file_row = count * sample_bytes(kind_);
    for (int y = y0; y < y1; ++y) {
      const unsigned char* row = src + (y - y0) * row_bytes;
      unsigned char* at = chunk_.data() + static_cast<std::size_t>(filled_) * file_row;
      if (kind_ == SampleType::Double) to_double(row, at, count);
      else if (row != at) std::memcpy(at, row, file_row);
      ++filled_;
      if (filled_ == rows_per_strip_ || y + 1 == height_) {
        const tstrile_t strip = static_cast<tstrile_t>(y / rows_per_strip_);
        const std::size_t size = static_cast<std::size_t>(filled_) * file_row;
        filled_ = 0;
        if (compressor_) {
          std::vector<unsigned char> rows = compressor_->buffer();
          rows.swap(chunk_);
          chunk_.resize(rows.size());  // (a recycled strip's buffer: already this size)
          compressor_->submit(static_cast<int>(strip), std::move(rows), size, sink());
          continue;
        }
        // Uncompressed strips are their bytes as they are: written raw, libtiff copies none.
        if ((raw_ ? TIFFWriteRawStrip(tif_, strip, chunk_.data(), static_cast<tmsize_t>(size))
                  : TIFFWriteEncodedStrip(tif_, strip, chunk_.data(), static_cast<tmsize_t>(size))) < 0)
          throw failure();
      }
    }
  }

  // Whole tile rows: each tile gathered from the band (zeros past the image's edges), then encoded.
  void write_tiles(int y0, int y1, const unsigned char* src, std::size_t row_bytes) {
    const std::size_t in = sample_bytes(stored_), out = sample_bytes(kind_);
    for (int ty = y0; ty < y1; ty += tile_) {
      for (int tx = 0; tx < width_; tx += tile_) {
        std::fill(chunk_.begin(), chunk_.end(), 0);
        const int rows = std::min({tile_, y1 - ty}), cols = std::min(tile_, width_ - tx);
        for (int r = 0; r < rows; ++r) {
          const unsigned char* from = src + static_cast<std::size_t>(ty - y0 + r) * row_bytes + tx * channels_ * in;
          unsigned char* to = chunk_.data() + static_cast<std::size_t>(r) * tile_ * channels_ * out;
          const std::size_t count = static_cast<std::size_t>(cols) * channels_;
          if (kind_ == SampleType::Double) to_double(from, to, count);
          else std::memcpy(to, from, count * in);
        }
        const ttile_t index = TIFFComputeTile(tif_, static_cast<std::uint32_t>(tx), static_cast<std::uint32_t>(ty), 0, 0);
        if (compressor_) {  // tiles come in index order: row of tiles by row of tiles, left to right
          std::vector<unsigned char> tile = compressor_->buffer();
          tile.assign(chunk_.begin(), chunk_.end());
          compressor_->submit(static_cast<int>(index), std::move(tile), chunk_.size(), sink());
          continue;
        }
        const auto size = static_cast<tmsize_t>(chunk_.size());
        if ((raw_ ? TIFFWriteRawTile(tif_, index, chunk_.data(), size)
                  : TIFFWriteEncodedTile(tif_, index, chunk_.data(), size)) < 0)
          throw failure();
      }
    }
  }

  StripCompressor::Sink sink() {
    return [this](int index, std::span<const unsigned char> data) {
      auto* bytes = const_cast<unsigned char*>(data.data());
      const auto size = static_cast<tmsize_t>(data.size());
      const tmsize_t written = tile_ > 0 ? TIFFWriteRawTile(tif_, static_cast<ttile_t>(index), bytes, size)
                                         : TIFFWriteRawStrip(tif_, static_cast<tstrile_t>(index), bytes, size);
      if (written < 0) throw failure();
    };
  }

  void check_file() const { check_written(*file_); }
  CodecError failure() { return write_error(file_.get(), messages_.take()); }

  std::unique_ptr<OutputFile> file_;
  Io io_;
  TiffMessages messages_;
  TIFF* tif_ = nullptr;  // last: cleaned up first
  SampleType kind_ = SampleType::Float;
  SampleType stored_ = SampleType::Float;
  int width_ = 0, height_ = 0, channels_ = 0, tile_ = 0, rows_per_strip_ = 32;
  int filled_ = 0;  // rows of the strip being assembled in chunk_
  bool raw_ = false;  // uncompressed
  std::vector<unsigned char> chunk_;  // a tile, or room for the strip being filled
  std::unique_ptr<StripCompressor> compressor_;  // deflated strips and tiles only
};

}  // namespace

std::unique_ptr<Encoder> create_tiff_encoder() { return std::make_unique<TiffEncoder>(); }

}  // namespace gdp::io
