// Encoding PNG with libpng: 8 or 16 bits, 1-4 channels (gray, gray+alpha, RGB, RGBA), through a checked file.
#include <png.h>

#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "io/codecs.h"
#include "io/guarded_call.h"
#include "io/output_file.h"
#include "io/png_errors.h"

namespace gdp::io {
namespace {

// The encoder's libpng state (errors: io/png_errors.h; libpng is called only through
// io/guarded_call.h's guarded()).
struct PngWriteState : PngErrors {
  png_structp png = nullptr;
  png_infop info = nullptr;
  OutputFile* file = nullptr;
  std::int64_t at = 0;
  PngWriteState() = default;
  PngWriteState(const PngWriteState&) = delete;
  PngWriteState& operator=(const PngWriteState&) = delete;
  ~PngWriteState() {
    if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
  }
};

void on_write(png_structp png, png_bytep data, png_size_t size) {
  auto* state = static_cast<PngWriteState*>(png_get_io_ptr(png));
  state->file->write_at(state->at, data, size);
  state->at += static_cast<std::int64_t>(size);
}

void on_flush(png_structp) {}

bool guarded_header(PngWriteState* s, int width, int height, int depth, int color) {
  return guarded(png_jmpbuf(s->png), [=] {
    png_set_write_fn(s->png, s, on_write, on_flush);
    png_set_IHDR(s->png, s->info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), depth, color,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(s->png, s->info);
    if (depth == 16) png_set_swap(s->png);  // samples come in the machine's (little-endian) order
  });
}

class PngEncoder final : public Encoder {
 public:
  std::string format_name() const override { return "png"; }
  std::string compression_refusal(const std::string&) const override { return "none: PNG is always deflated"; }

  void open(const std::string& path, const EncodeSpec& spec) override {
    if (spec.channels > 4) throw CodecError(fmt::format("cannot write: PNG holds 1 to 4 channels, not {}", spec.channels));
    stored_ = spec.sample_type == SampleType::UInt16 ? SampleType::UInt16 : SampleType::UInt8;
    file_ = open_written(path);
    s_.file = file_.get();
    s_.png = png_writer(s_);
    if (s_.png) s_.info = png_create_info_struct(s_.png);
    if (!s_.png || !s_.info) throw CodecError("cannot write: out of memory for the PNG encoder");
    static const int colors[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGB_ALPHA};
    const int depth = stored_ == SampleType::UInt16 ? 16 : 8;
    row_bytes_ = static_cast<std::size_t>(spec.width) * spec.channels * (depth / 8);
    if (!guarded_header(&s_, spec.width, spec.height, depth, colors[spec.channels - 1])) throw error();
    check_written(*file_);
  }

  SampleType stored() const override { return stored_; }
  bool integer_file() const override { return true; }

  void write(int y0, int y1, const void* rows) override {
    const auto* bytes = static_cast<const unsigned char*>(rows);
    const auto write_rows = [&] {
      for (int i = 0; i < y1 - y0; ++i) png_write_row(s_.png, bytes + i * row_bytes_);
    };
    if (!guarded(png_jmpbuf(s_.png), write_rows)) throw error();
    check_written(*file_);
  }

  void close() override {
    if (!guarded(png_jmpbuf(s_.png), [this] { png_write_end(s_.png, s_.info); })) throw error();
    close_written(*file_);
  }

 private:
  CodecError error() const { return write_error(file_.get(), s_.message); }

  std::unique_ptr<OutputFile> file_;  // before s_: destroyed after libpng's state
  PngWriteState s_;
  SampleType stored_ = SampleType::UInt8;
  std::size_t row_bytes_ = 0;
};

}  // namespace

std::unique_ptr<Encoder> create_png_encoder() { return std::make_unique<PngEncoder>(); }

}  // namespace gdp::io
