// Decoding JPEG with libjpeg: gray or RGB (from YCbCr) rows in order; CMYK is left to OpenImageIO.
#include <cstdio>
// jpeglib.h needs FILE and size_t declared first.
#include <jerror.h>
#include <jpeglib.h>

#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "gdp/size_check.h"
#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/guarded_call.h"
#include "io/jpeg_errors.h"

namespace gdp::io {
namespace {

// The decoder's libjpeg state (errors: io/jpeg_errors.h). Damaged data is an error too (libjpeg
// itself only warns, "Corrupt JPEG data: ...", and fills in gray or garbage): every warning once
// decoding has started, but a file missing only its end marker and stray bytes before it.
struct JpegState : JpegErrors {
  jpeg_decompress_struct cinfo{};
  std::FILE* file = nullptr;
  bool created = false;
  bool decoding = false;  // past the header: a warning means lost pixels
  JpegState() = default;
  JpegState(const JpegState&) = delete;
  JpegState& operator=(const JpegState&) = delete;
  ~JpegState() {
    if (created) jpeg_destroy_decompress(&cinfo);
    if (file) std::fclose(file);
  }
};

JpegState* state_of(j_common_ptr cinfo) { return static_cast<JpegState*>(cinfo->client_data); }

// Stray bytes before the end marker that some cameras' files have; more are what is left of
// damaged data that decoded into fewer bits than it holds.
constexpr int kStrayBytes = 8;

// A warning while decoding is fatal, with two exceptions that lose nothing: the file ending
// within the last row of MCUs (which libjpeg reads ahead of the rows it returns) of a sequential
// file, where only the end marker is missing (were data missing, libjpeg would go on to warn that
// it hit the marker it puts in its place), and a few stray bytes before the end marker.
// Warnings while reading the header (metadata: JFIF version, ICC profile) are ignored.
void on_message(j_common_ptr cinfo, int level) {
  if (level >= 0 || !cinfo->is_decompressor || !state_of(cinfo)->decoding) return;
  const auto* d = reinterpret_cast<j_decompress_ptr>(cinfo);
  const int code = cinfo->err->msg_code;
  if (code == JWRN_EXTRANEOUS_DATA && cinfo->err->msg_parm.i[1] == 0xd9 && cinfo->err->msg_parm.i[0] <= kStrayBytes)
    return;
  if (code == JWRN_JPEG_EOF) {
    const JDIMENSION last_mcu_rows = static_cast<JDIMENSION>(d->max_v_samp_factor * DCTSIZE);
    if (d->output_height > 0 && d->output_scanline + last_mcu_rows >= d->output_height && !d->progressive_mode)
      return;
  }
  jpeg_error_exit(cinfo);
}

// Reads the header; false on a libjpeg error.
bool guarded_header(JpegState* s) {
  return guarded(s->jump, [s] {
    jpeg_create_decompress(&s->cinfo);
    s->created = true;
    jpeg_stdio_src(&s->cinfo, s->file);
    jpeg_read_header(&s->cinfo, TRUE);
  });
}

bool guarded_start(JpegState* s, J_COLOR_SPACE out) {
  return guarded(s->jump, [s, out] {
    s->cinfo.out_color_space = out;
    s->decoding = true;  // a progressive file is decoded here, whole
    jpeg_start_decompress(&s->cinfo);
  });
}

bool guarded_rows(JpegState* s, unsigned char* const* rows, int count) {
  return guarded(s->jump, [=] {
    if (!all_scanlines(*s, rows, count, [s](JSAMPARRAY at, JDIMENSION n) { return jpeg_read_scanlines(&s->cinfo, at, n); }))
      return false;
    // After the last row, read on to the end marker: data that decoded into fewer bits than the
    // file holds (damage) shows only there.
    if (s->cinfo.output_scanline == s->cinfo.output_height) jpeg_finish_decompress(&s->cinfo);
    return true;
  });
}

class JpegDecoder final : public Decoder {
 public:
  // False when the colour space is one gdp leaves to OpenImageIO (CMYK, YCCK).
  bool open(const std::string& path) {
    s_.file = std::fopen(path.c_str(), "rb");
    if (!s_.file) throw CodecError("cannot open");
    s_.cinfo.err = jpeg_errors(s_, on_message);
    s_.cinfo.client_data = &s_;
    if (!guarded_header(&s_)) throw error();
    J_COLOR_SPACE out;
    if (s_.cinfo.num_components == 1) out = JCS_GRAYSCALE;
    else if (s_.cinfo.num_components == 3 && (s_.cinfo.jpeg_color_space == JCS_YCbCr || s_.cinfo.jpeg_color_space == JCS_RGB))
      out = JCS_RGB;
    else
      return false;
    check_image_size(s_.cinfo.image_width, s_.cinfo.image_height, out == JCS_GRAYSCALE ? 1 : 3);
    if (!guarded_start(&s_, out)) throw error();
    layout_.width = static_cast<int>(s_.cinfo.output_width);
    layout_.height = static_cast<int>(s_.cinfo.output_height);
    layout_.channels = s_.cinfo.output_components;
    layout_.stored = SampleType::UInt8;
    layout_.info = {SampleType::UInt8, "jpeg", true};
    return true;
  }

  const ImageLayout& layout() const override { return layout_; }

  void read(int y0, int y1, int x0, int x1, void* out) override {
    const std::size_t pixel = static_cast<std::size_t>(layout_.channels);
    if (!decode_rows(y1 - y0, pixel * layout_.width, pixel * x0, pixel * (x1 - x0), static_cast<unsigned char*>(out),
                     scratch_, [&](unsigned char** rows, int count) { return guarded_rows(&s_, rows, count); }))
      throw error();
  }

 private:
  CodecError error() const { return CodecError(fmt::format("cannot read JPEG: {}", s_.message)); }

  JpegState s_;
  ImageLayout layout_;
  std::vector<unsigned char> scratch_;
};

}  // namespace

std::unique_ptr<Decoder> open_jpeg_decoder(const std::string& path) {
  auto decoder = std::make_unique<JpegDecoder>();
  if (!decoder->open(path)) return nullptr;
  return decoder;
}

}  // namespace gdp::io
