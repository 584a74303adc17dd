// Palette PNG seam files (multiblend's format) read and written with libpng, errors turned into typed exceptions.
#include "blend/seam_png.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include <fmt/format.h>
#include <png.h>

#include "gdp/cleanup.h"
#include "gdp/errors.h"
#include "io/guarded_call.h"
#include "io/png_errors.h"
#include "io/temp_file.h"

namespace gdp::blending {
namespace {

// libpng state (errors: io/png_errors.h; libpng is called only through io/guarded_call.h's
// guarded()).
struct Png : io::PngErrors {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::FILE* file = nullptr;
  bool writing = false;
  ~Png() {
    if (png && writing) png_destroy_write_struct(&png, info ? &info : nullptr);
    else if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    if (file) std::fclose(file);
  }
};

bool guarded_header(Png* p) {
  return io::guarded(png_jmpbuf(p->png), [p] {
    png_init_io(p->png, p->file);
    png_read_info(p->png, p->info);
    if (png_get_bit_depth(p->png, p->info) < 8) png_set_packing(p->png);  // one index per byte
    png_read_update_info(p->png, p->info);
  });
}

bool guarded_write_header(Png* p, int w, int h, const png_color* palette) {
  return io::guarded(png_jmpbuf(p->png), [=] {
    png_init_io(p->png, p->file);
    png_set_IHDR(p->png, p->info, w, h, 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_set_PLTE(p->png, p->info, palette, 256);
    png_write_info(p->png, p->info);
  });
}

// A colour per layer, far apart in hue (golden-ratio steps); black for "none".
std::vector<png_color> layer_palette() {
  std::vector<png_color> palette(256, png_color{0, 0, 0});
  for (int i = 0; i < kPaletteNone; ++i) {
    const double h = std::fmod(i * 0.6180339887, 1.0) * 6.0, f = h - static_cast<int>(h);
    const double v[6][3] = {{1, f, 0}, {1 - f, 1, 0}, {0, 1, f}, {0, 1 - f, 1}, {f, 0, 1}, {1, 0, 1 - f}};
    const double* c = v[static_cast<int>(h) % 6];
    palette[i] = png_color{static_cast<png_byte>(55 + 200 * c[0]), static_cast<png_byte>(55 + 200 * c[1]),
                           static_cast<png_byte>(55 + 200 * c[2])};
  }
  return palette;
}

// The PNG written to `temp`; false on a failure (message in p.message or errno).
bool write_png(Png& p, const LabelPlane& labels) {
  const std::vector<png_color> palette = layer_palette();
  if (!guarded_write_header(&p, labels.width(), labels.height(), palette.data())) return false;
  std::vector<Label> row(labels.width());
  std::vector<png_byte> bytes(labels.width());
  for (int y = 0; y < labels.height(); ++y) {
    labels.read_row(y, row);
    for (int x = 0; x < labels.width(); ++x) bytes[x] = static_cast<png_byte>(row[x] ? row[x] - 1 : kPaletteNone);
    if (!io::guarded(png_jmpbuf(p.png), [&] { png_write_row(p.png, bytes.data()); })) return false;
  }
  return io::guarded(png_jmpbuf(p.png), [&] { png_write_end(p.png, p.info); }) && std::fflush(p.file) == 0 && !std::ferror(p.file);
}

}  // namespace

bool is_palette_png(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  unsigned char head[26] = {};
  const bool whole = std::fread(head, 1, sizeof head, f) == sizeof head;
  std::fclose(f);
  // The signature, then IHDR (length, type, width, height, bit depth, colour type).
  return whole && png_sig_cmp(head, 0, 8) == 0 && std::memcmp(head + 12, "IHDR", 4) == 0 && head[25] == PNG_COLOR_TYPE_PALETTE;
}

void write_palette_seams(const LabelPlane& labels, int layers, const std::string& path) {
  if (layers > kPaletteNone)
    throw UsageError(fmt::format("{}: a palette PNG holds at most {} layers, there are {}; save the seams as .tif",
                                 path, kPaletteNone, layers));
  std::string why;
  const std::filesystem::path temp = io::create_temp_file(path, why);
  if (temp.empty()) throw OutputError(fmt::format("{}: {}", path, why));
  const int handle = cleanup::track(temp.string());
  bool ok = false;
  {
    Png p;
    p.writing = true;
    p.file = std::fopen(temp.c_str(), "wb");
    p.png = io::png_writer(p);
    p.info = p.png ? png_create_info_struct(p.png) : nullptr;
    if (p.file && p.info) ok = write_png(p, labels);
    if (!ok && !p.message[0]) std::snprintf(p.message, sizeof p.message, "%s", std::strerror(errno));
    if (ok && std::fclose(p.file) != 0) ok = false;
    p.file = nullptr;
    why = p.message;
  }
  std::error_code ec;
  if (ok) std::filesystem::rename(temp, path, ec);
  if (!ok || ec) std::filesystem::remove(temp, ec);
  cleanup::untrack(handle);
  if (!ok) throw OutputError(fmt::format("{}: cannot write the seams: {}", path, why));
}

struct PaletteRows::State : Png {
  std::string path;
};

PaletteRows::PaletteRows(const std::string& path) : s_(std::make_unique<State>()) {
  s_->path = path;
  s_->file = std::fopen(path.c_str(), "rb");
  if (!s_->file) throw InputError(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  s_->png = io::png_reader(*s_);
  s_->info = s_->png ? png_create_info_struct(s_->png) : nullptr;
  if (!s_->info || !guarded_header(s_.get()))
    throw InputError(fmt::format("{}: not a readable PNG: {}", path, s_->message));
  if (png_get_color_type(s_->png, s_->info) != PNG_COLOR_TYPE_PALETTE ||
      png_get_interlace_type(s_->png, s_->info) != PNG_INTERLACE_NONE)
    throw InputError(fmt::format("{}: seams in a PNG must be a non-interlaced palette image (value = layer)", path));
}

PaletteRows::~PaletteRows() = default;
int PaletteRows::width() const { return static_cast<int>(png_get_image_width(s_->png, s_->info)); }
int PaletteRows::height() const { return static_cast<int>(png_get_image_height(s_->png, s_->info)); }

void PaletteRows::read_row(std::span<std::uint8_t> row) {
  if (!io::guarded(png_jmpbuf(s_->png), [&] { png_read_row(s_->png, row.data(), nullptr); }))
    throw InputError(fmt::format("{}: corrupt PNG: {}", s_->path, s_->message));
}

}  // namespace gdp::blending
