// The codec registry: file signatures and extensions to gdp's own codecs (PNG, TIFF, JPEG, OpenEXR) or OpenImageIO's module.
#include "io/codecs.h"

#include <cstdio>
#include <cstring>

#include <fmt/format.h>

#include "io/codec_util.h"
#include "io/oiio_backend.h"

namespace gdp::io {
namespace {

enum class Kind { Png, Tiff, Jpeg, Exr, Fits, Other };

Kind sniff(const std::string& path) {
  unsigned char head[8] = {};
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return Kind::Other;  // the caller checked it opens; let OpenImageIO explain
  const std::size_t n = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  // The first 4 bytes: damage in the other 4 ("corrupted by ASCII conversion") is for libpng to
  // say through gdp's handlers (OpenImageIO's libpng would print it on stderr too).
  if (n >= 4 && std::memcmp(head, png, 4) == 0) return Kind::Png;
  // Classic TIFF (42) and BigTIFF (43), little- and big-endian.
  if (n >= 4 && head[0] == 'I' && head[1] == 'I' && (head[2] == 42 || head[2] == 43) && head[3] == 0) return Kind::Tiff;
  if (n >= 4 && head[0] == 'M' && head[1] == 'M' && head[2] == 0 && (head[3] == 42 || head[3] == 43)) return Kind::Tiff;
  if (n >= 3 && head[0] == 0xff && head[1] == 0xd8 && head[2] == 0xff) return Kind::Jpeg;
  if (n >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01) return Kind::Exr;
  if (is_fits(path, head, n)) return Kind::Fits;
  return Kind::Other;
}

}  // namespace

bool is_tiff_file(const std::string& path) { return sniff(path) == Kind::Tiff; }
bool is_exr_file(const std::string& path) { return sniff(path) == Kind::Exr; }

std::unique_ptr<Decoder> open_decoder(const std::string& path, int page) {
  std::unique_ptr<Decoder> decoder;
  const Kind kind = sniff(path);
  if (page > 0 && kind != Kind::Tiff) throw CodecError(fmt::format("page {}: only TIFF files have pages", page));
  switch (kind) {
    case Kind::Png: decoder = open_png_decoder(path); break;
    case Kind::Tiff: decoder = open_tiff_decoder(path, page); break;
    case Kind::Jpeg: decoder = open_jpeg_decoder(path); break;
    case Kind::Exr: decoder = open_exr_decoder(path); break;
    case Kind::Fits: decoder = open_fits_decoder(path); break;
    case Kind::Other: break;
  }
  if (decoder) return decoder;
  if (page > 0) throw CodecError(fmt::format("page {}: a TIFF variant gdp reads only through OpenImageIO, first page only", page));
  return oiio_backend().open_decoder(path);
}

std::unique_ptr<Encoder> create_encoder(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == "png") return create_png_encoder();
  if (ext == "tif" || ext == "tiff") return create_tiff_encoder();
  if (ext == "jpg" || ext == "jpeg" || ext == "jpe" || ext == "jfif" || ext == "jif" || ext == "jfi")
    return create_jpeg_encoder();
  if (ext == "exr") return create_exr_encoder();
  if (ext == "fits" || ext == "fit" || ext == "fts") return create_fits_encoder();
  return oiio_backend().create_encoder(path);
}

}  // namespace gdp::io
