// The internal codec interface: decoders that deliver rows of interleaved samples, encoders that take them.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "gdp/image_io.h"

namespace gdp::io {

// A codec's failure. what() is the problem alone ("cannot read pixels: ..."); the reader and
// writer put the file's name in front and turn it into InputError / OutputError. Codecs may also
// throw anything derived from std::exception (the OpenImageIO module does, across dlopen()).
class CodecError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a decoder delivers.
struct ImageLayout {
  int width = 0, height = 0, channels = 0;
  SampleType stored = SampleType::Float;  // UInt8, UInt16 or Float: the samples read() delivers
  int tile_width = 0, tile_height = 0;    // tiled files: rows are best read in whole tile rows
  ImageFileInfo info;                     // the file's own sample type, format name, lossiness
};

// Decodes one image file. Rows are read in increasing order (a call's y0 is the previous call's
// y1), from one thread at a time.
class Decoder {
 public:
  virtual ~Decoder() = default;
  virtual const ImageLayout& layout() const = 0;
  // Rows [y0, y1), columns [x0, x1) into `out`: (y1 - y0) * (x1 - x0) * channels interleaved
  // samples of layout().stored. Throws on a decoding error.
  virtual void read(int y0, int y1, int x0, int x1, void* out) = 0;
};

// What to write.
struct EncodeSpec {
  int width = 0, height = 0, channels = 0;
  SampleType sample_type = SampleType::Float;  // asked for (io::choose_sample_type); the encoder may adjust it
  int jpeg_quality = 95;
  std::string compression;  // WriteOptions::compression: empty for the format's default
  int tile_size = 0;        // > 0: tiled, tiles of this size (TIFF and OpenEXR only)
  bool bigtiff = false;
  std::string fits_header;  // WriteOptions::fits_header
  std::optional<GeoReference> geo;  // TIFF: GeoTIFF tags
  std::optional<FramePlacement> frame;  // OpenEXR: data window at (x, y) of the display window
};

// Encodes one image file: chosen by the final name's extension, then opened on the temporary
// file. Rows come in increasing order, in whole tile rows when tiled, from one thread at a time.
class Encoder {
 public:
  virtual ~Encoder() = default;
  virtual std::string format_name() const = 0;          // "png", "tiff", "jpeg", "openexr", ...
  virtual void open(const std::string& path, const EncodeSpec& spec) = 0;
  virtual SampleType stored() const = 0;                // after open(): UInt8, UInt16 or Float samples to write()
  virtual bool integer_file() const = 0;                // after open(): the file stores integers (clamp floats)
  virtual void write(int y0, int y1, const void* rows) = 0;  // interleaved samples of stored()
  // Where row y (the next to write) may be put, as write() takes it, so that write(y, y + 1, it)
  // copies nothing: the encoder's own buffer (a TIFF strip being assembled). Null: none, write()
  // takes the caller's rows.
  virtual unsigned char* row_space(int /*y*/) { return nullptr; }
  virtual void close() = 0;                             // finishes the file; throws on failure
  // Empty when `compression` (--compression, e.g. "zip:6") suits this format, else the names it
  // accepts, for the message that refuses it.
  virtual std::string compression_refusal(const std::string& compression) const {
    (void)compression;
    return {};
  }
};

}  // namespace gdp::io
