// Image files read and written row by row, with decoding and encoding on background threads.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>

#include "gdp/image_io.h"
#include "gdp/rows.h"

namespace gdp {

// Reads an image file in bands of rows (whole tile rows for tiled files), never the whole
// image: memory is O(width * band rows) whatever the height (except where the codec itself
// holds the whole image: interlaced PNG, progressive JPEG). 8- and 16-bit samples stay so in
// the bands and become floats in read_row(). With prefetch, a background thread decodes the
// next bands while the caller uses the current one (at most four bands exist; more after read_ahead()). Errors (also
// the decoder thread's, rethrown by read_row()) are InputError naming the file; rows out of
// order throw std::logic_error. rewind() reopens the file unless one band holds the image.
//
// PNG, TIFF and JPEG are decoded by gdp itself (libpng, libtiff, libjpeg); other formats by
// OpenImageIO, loaded from its module (libgdp_oiio.so) only when such a file is opened.
//
// A column window reads columns [begin, end) only: width() stays the file's width, and
// read_row() fills channels x window_width() samples (channel-major, stride window_width()).
// Tiled files then decode only the tiles the window overlaps; others decode whole rows.
struct ColumnRange {
  int begin = 0;
  int end = -1;  // -1: the image's width
};

class ImageFileReader final : public RowReader {
 public:
  explicit ImageFileReader(const std::filesystem::path& path, bool prefetch = true);
  // Throws InputError when the window is empty or outside the image. `page` > 0 reads that page
  // (0-based) of a multi-page TIFF instead of the first (InputError for other formats).
  ImageFileReader(const std::filesystem::path& path, bool prefetch, ColumnRange columns, int page = 0);
  ~ImageFileReader() override;
  const ImageFileInfo& info() const;
  int window_begin() const;
  int window_width() const;
  int width() const override;
  int height() const override;
  int channels() const override;
  void read_row(int y, std::span<float> out) override;
  void rewind() override;
  // With prefetch: starts decoding now rather than at the first read_row(), so that the first
  // bands are ready when the caller, still setting up, reads (a set_columns() after this decodes
  // afresh from the top: the bands decoded until then are wasted), and from then on decodes up to
  // `bytes` of bands ahead of the caller (at least two bands, at most 64; else two): the decoding
  // thread keeps going while its caller is busy elsewhere, as a streamed solve is between bursts
  // of rows, and fills a core that the caller's setup leaves idle. For callers with few inputs:
  // 8 MiB is 340 rows of an 8192-wide 8-bit RGB image.
  static constexpr std::size_t kAheadBytes = std::size_t{8} << 20;
  void read_ahead(std::size_t bytes = kAheadBytes);
  // Rows decoded so far in this pass (by the decoding thread, ahead of read_row(), or by it).
  int decoded_rows() const;
  // RowReader's hint, before the first row: decodes only columns [begin, end) from then on (as
  // a window does) but read_row() fills them in at their place in a full-width row and leaves
  // the other samples of `out` as they are.
  void set_columns(int begin, int end) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes an image file row by row to a temporary name next to it, a band of rows at a time
// (whole tile rows with WriteOptions::tiled, which needs .tif or .exr); commit() finishes it
// and renames it into place. With write_behind, a background thread encodes full bands while
// the caller fills the next one (at most three bands exist). Destroyed without commit(), it
// stops that thread and deletes the temporary file: nothing is left behind. Integer outputs are
// clamped to [0, 1]. Errors, also the encoder's and failed writes to the disk (full, say), are
// OutputError naming the final file, thrown by the constructor, write_row() or commit(); rows
// out of order throw std::logic_error. PNG, TIFF and JPEG are encoded by gdp itself, other formats
// through OpenImageIO's module (loaded only then).
class ImageFileWriter final : public RowWriter {
 public:
  ImageFileWriter(const std::filesystem::path& path, int width, int height, int channels, const WriteOptions& options,
                  bool write_behind = true);
  ~ImageFileWriter() override;
  void write_row(int y, std::span<const float> row) override;
  void commit() override;
  int stored_levels() override;  // 255 or 65535 for 8- or 16-bit files, else 0; opens the codec

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gdp
