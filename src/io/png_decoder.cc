// Decoding PNG with libpng: rows in order, palette/gray/low bit depths and tRNS expanded as OpenImageIO does.
#include <png.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "gdp/size_check.h"
#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/guarded_call.h"
#include "io/png_errors.h"

namespace gdp::io {
namespace {

constexpr std::size_t kReadBuffer = std::size_t{1} << 18;  // 256 kB: a few hundred read()s for a large PNG

// The decoder's libpng state (errors: io/png_errors.h; libpng is called only through
// io/guarded_call.h's guarded()).
struct PngState : PngErrors {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::FILE* file = nullptr;
  std::unique_ptr<char[]> buffer;  // the file's stdio buffer (outlives it: fclose() is first)
  PngState() = default;
  PngState(const PngState&) = delete;
  PngState& operator=(const PngState&) = delete;
  ~PngState() {
    if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    if (file) std::fclose(file);
  }
};

// Reads the header; false on a libpng error.
bool guarded_header(PngState* s) {
  return guarded(png_jmpbuf(s->png), [s] {
    png_init_io(s->png, s->file);
    png_read_info(s->png, s->info);
  });
}

// Channels once expanded (palette to RGB, transparency to alpha).
int expanded_channels(PngState* s) {
  const int color = png_get_color_type(s->png, s->info);
  const int alpha = png_get_valid(s->png, s->info, PNG_INFO_tRNS) ? 1 : 0;
  return color == PNG_COLOR_TYPE_PALETTE ? 3 + alpha : png_get_channels(s->png, s->info) + alpha;
}

// Sets the expansions (allocating the row buffers); false on a libpng error.
bool guarded_start(PngState* s) {
  return guarded(png_jmpbuf(s->png), [s] {
    const int color = png_get_color_type(s->png, s->info);
    const int depth = png_get_bit_depth(s->png, s->info);
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(s->png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(s->png);
    if (png_get_valid(s->png, s->info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(s->png);
    if (depth == 16) png_set_swap(s->png);  // to the machine's (little-endian) order
    if (png_get_interlace_type(s->png, s->info) != PNG_INTERLACE_NONE) png_set_interlace_handling(s->png);
    png_read_update_info(s->png, s->info);
  });
}

class PngDecoder final : public Decoder {
 public:
  explicit PngDecoder(const std::string& path) {
    s_.file = std::fopen(path.c_str(), "rb");
    if (!s_.file) throw CodecError("cannot open");
    // libpng asks stdio for a few kB at a time: with stdio's own 4 kB buffer that was one read()
    // per 4 kB of file (16,000 system calls for a 66 MB PNG), with this one per 256 kB.
    s_.buffer.reset(new char[kReadBuffer]);
    std::setvbuf(s_.file, s_.buffer.get(), _IOFBF, kReadBuffer);
    s_.png = png_reader(s_);
    if (s_.png) s_.info = png_create_info_struct(s_.png);
    if (!s_.png || !s_.info) throw CodecError("out of memory for the PNG decoder");
    // gdp's own limits apply (1-4 channels, memory per band), not libpng's default 1M-pixel rows.
    png_set_user_limits(s_.png, 0x7fffffff, 0x7fffffff);
    // Chunks gdp does not use and libpng would allocate whole, as long as their header says (a
    // 93-byte file whose text chunk claimed 1.5 GB made it allocate that), are skipped unread.
    static const png_byte unused[] = "tEXt\0zTXt\0iTXt\0iCCP\0sPLT\0eXIf\0pCAL\0sCAL";
    png_set_keep_unknown_chunks(s_.png, PNG_HANDLE_CHUNK_NEVER, unused, 8);
    // The zlib stream's Adler-32 is not computed (about 5 % of decoding: docs/formats.md, "PNG
    // checksums"): every byte of it is already under a chunk's CRC-32, which libpng still checks.
    png_set_option(s_.png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
    if (!guarded_header(&s_)) throw error();
    check_image_size(png_get_image_width(s_.png, s_.info), png_get_image_height(s_.png, s_.info),
                     expanded_channels(&s_));
    if (!guarded_start(&s_)) throw error();
    layout_.width = static_cast<int>(png_get_image_width(s_.png, s_.info));
    layout_.height = static_cast<int>(png_get_image_height(s_.png, s_.info));
    layout_.channels = png_get_channels(s_.png, s_.info);
    const bool sixteen = png_get_bit_depth(s_.png, s_.info) == 16;
    layout_.stored = sixteen ? SampleType::UInt16 : SampleType::UInt8;
    layout_.info = {layout_.stored, "png", false};
    row_bytes_ = png_get_rowbytes(s_.png, s_.info);
    interlaced_ = png_get_interlace_type(s_.png, s_.info) != PNG_INTERLACE_NONE;
  }

  const ImageLayout& layout() const override { return layout_; }

  void read(int y0, int y1, int x0, int x1, void* out) override {
    const std::size_t pixel = row_bytes_ / static_cast<std::size_t>(layout_.width);
    const std::size_t out_row = static_cast<std::size_t>(x1 - x0) * pixel;
    auto* dst = static_cast<unsigned char*>(out);
    if (interlaced_) {
      // Interlaced rows are complete only after the last pass: decode the whole image once.
      if (whole_.empty()) {
        whole_.resize(row_bytes_ * static_cast<std::size_t>(layout_.height));
        std::vector<unsigned char*> rows(static_cast<std::size_t>(layout_.height));
        for (int y = 0; y < layout_.height; ++y) rows[y] = whole_.data() + y * row_bytes_;
        if (!guarded(png_jmpbuf(s_.png), [&] { png_read_image(s_.png, rows.data()); })) throw error();
      }
      for (int y = y0; y < y1; ++y)
        std::memcpy(dst + (y - y0) * out_row, whole_.data() + y * row_bytes_ + x0 * pixel, out_row);
      return;
    }
    const auto read_rows = [&](unsigned char** rows, int count) {
      return guarded(png_jmpbuf(s_.png), [&] {
        for (int i = 0; i < count; ++i) png_read_row(s_.png, rows[i], nullptr);
      });
    };
    if (!decode_rows(y1 - y0, row_bytes_, pixel * x0, out_row, dst, scratch_, read_rows)) throw error();
  }

 private:
  CodecError error() const { return CodecError(fmt::format("cannot read PNG: {}", s_.message)); }

  PngState s_;
  ImageLayout layout_;
  std::size_t row_bytes_ = 0;
  bool interlaced_ = false;
  std::vector<unsigned char> whole_, scratch_;
};

}  // namespace

std::unique_ptr<Decoder> open_png_decoder(const std::string& path) { return std::make_unique<PngDecoder>(path); }

}  // namespace gdp::io
