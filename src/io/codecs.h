// Choosing a codec: by the file's signature for reading, by the file name's extension for writing.
#pragma once

#include <memory>
#include <string>

#include "io/codec.h"
#include "io/output_file.h"

namespace gdp::io {

// PNG, TIFF, JPEG, OpenEXR and FITS files are decoded by gdp's own codecs (libpng, libtiff,
// libjpeg, OpenEXR, cfitsio), chosen by their first bytes; variants those do not handle (CMYK JPEG, palette TIFF,
// ...) and every other format go to OpenImageIO's module (io/oiio_backend.h). Throws
// std::exception's with the problem.
// `page` > 0 selects a later page (directory) of a multi-page TIFF (gdp's TIFF decoder only).
std::unique_ptr<Decoder> open_decoder(const std::string& path, int page = 0);

// True when the file starts with a TIFF or BigTIFF signature.
bool is_tiff_file(const std::string& path);
// True when the file starts with OpenEXR's magic number.
bool is_exr_file(const std::string& path);

// .png, .tif/.tiff, .jpg/.jpeg/.jpe/.jfif/.jif/.jfi, .exr and .fits/.fit/.fts are written by gdp's own encoders,
// the rest through OpenImageIO's module.
std::unique_ptr<Encoder> create_encoder(const std::string& path);

// Decoders and encoders of gdp's own codecs; a decoder returns nullptr for a variant it leaves
// to OpenImageIO.
std::unique_ptr<Decoder> open_png_decoder(const std::string& path);
std::unique_ptr<Decoder> open_tiff_decoder(const std::string& path, int page = 0);
std::unique_ptr<Decoder> open_jpeg_decoder(const std::string& path);
std::unique_ptr<Decoder> open_exr_decoder(const std::string& path);  // never nullptr: throws instead
std::unique_ptr<Decoder> open_fits_decoder(const std::string& path);
// FITS by the first bytes of the file (`head`, n of them), or a .fits.gz/.fit.gz/.fts.gz name.
bool is_fits(const std::string& path, const unsigned char* head, std::size_t n);
std::unique_ptr<Encoder> create_png_encoder();
std::unique_ptr<Encoder> create_tiff_encoder();
std::unique_ptr<Encoder> create_jpeg_encoder();
std::unique_ptr<Encoder> create_exr_encoder();
std::unique_ptr<Encoder> create_fits_encoder();

// The write errors of gdp's own encoders: the file's recorded failure (no space, ...), which a
// codec library's own message would only follow from, else the library's message.
inline void check_written(const OutputFile& file) {
  if (file.failed()) throw CodecError("cannot write: " + file.problem());
}
inline CodecError write_error(const OutputFile* file, const std::string& library_message) {
  if (file && file->failed()) return CodecError("cannot write: " + file->problem());
  return CodecError("cannot write: " + library_message);
}
// An encoder's checked file, opened (a failure to open thrown at once) and closed.
inline std::unique_ptr<OutputFile> open_written(const std::string& path) {
  auto file = std::make_unique<OutputFile>(path);
  check_written(*file);
  return file;
}
inline void close_written(OutputFile& file) {
  file.close();
  check_written(file);
}

// Tiles decoded by gdp's TIFF and OpenEXR decoders in this process so far (tests check column
// windows with them).
long tiff_tiles_decoded();
long exr_tiles_decoded();
}  // namespace gdp::io
