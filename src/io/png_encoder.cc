// Encoding PNG with libpng: 8 or 16 bits, 1-4 channels (gray, gray+alpha, RGB, RGBA), through a checked file.
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "io/codecs.h"
#include "io/output_file.h"
#include "io/png_errors.h"

namespace gdp::io {
namespace {

// The encoder's libpng state (errors: io/png_errors.h; they longjmp() back into the guarded
// functions, which hold no C++ objects with destructors).
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
  if (setjmp(png_jmpbuf(s->png))) return false;
  png_set_write_fn(s->png, s, on_write, on_flush);
  png_set_IHDR(s->png, s->info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), depth, color,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(s->png, s->info);
  if (depth == 16) png_set_swap(s->png);  // samples come in the machine's (little-endian) order
  return true;
}

bool guarded_rows(PngWriteState* s, const unsigned char* rows, std::size_t row_bytes, int count) {
  if (setjmp(png_jmpbuf(s->png))) return false;
  for (int i = 0; i < count; ++i) png_write_row(s->png, rows + i * row_bytes);
  return true;
}

bool guarded_end(PngWriteState* s) {
  if (setjmp(png_jmpbuf(s->png))) return false;
  png_write_end(s->png, s->info);
  return true;
}

class PngEncoder final : public Encoder {
 public:
  std::string format_name() const override { return "png"; }
  std::string compression_refusal(const std::string&) const override { return "none: PNG is always deflated"; }

  void open(const std::string& path, const EncodeSpec& spec) override {
    if (spec.channels > 4) throw CodecError(fmt::format("cannot write: PNG holds 1 to 4 channels, not {}", spec.channels));
    stored_ = spec.sample_type == SampleType::UInt16 ? SampleType::UInt16 : SampleType::UInt8;
    file_ = std::make_unique<OutputFile>(path);
    check_file();
    s_.file = file_.get();
    s_.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, static_cast<PngErrors*>(&s_), png_error_callback,
                                    png_warning_callback);
    if (s_.png) s_.info = png_create_info_struct(s_.png);
    if (!s_.png || !s_.info) throw CodecError("cannot write: out of memory for the PNG encoder");
    static const int colors[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGB_ALPHA};
    const int depth = stored_ == SampleType::UInt16 ? 16 : 8;
    row_bytes_ = static_cast<std::size_t>(spec.width) * spec.channels * (depth / 8);
    if (!guarded_header(&s_, spec.width, spec.height, depth, colors[spec.channels - 1])) throw error();
    check_file();
  }

  SampleType stored() const override { return stored_; }
  bool integer_file() const override { return true; }

  void write(int y0, int y1, const void* rows) override {
    if (!guarded_rows(&s_, static_cast<const unsigned char*>(rows), row_bytes_, y1 - y0)) throw error();
    check_file();
  }

  void close() override {
    if (!guarded_end(&s_)) throw error();
    file_->close();
    check_file();
  }

 private:
  void check_file() const { check_written(*file_); }
  CodecError error() const { return write_error(file_.get(), s_.message); }

  std::unique_ptr<OutputFile> file_;  // before s_: destroyed after libpng's state
  PngWriteState s_;
  SampleType stored_ = SampleType::UInt8;
  std::size_t row_bytes_ = 0;
};

}  // namespace

std::unique_ptr<Encoder> create_png_encoder() { return std::make_unique<PngEncoder>(); }

}  // namespace gdp::io
