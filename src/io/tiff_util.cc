// Per-handle libtiff message capture and TIFF sample conversion for the TIFF decoder and encoder.
#include "io/tiff_util.h"

#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "io/codec_util.h"

namespace gdp::io {
namespace {

// Called by libtiff (C frames): records and returns, never throws.
int on_error(TIFF*, void* user, const char* module, const char* format, va_list args) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, args);
  (void)module;
  static_cast<TiffMessages*>(user)->add(text);
  return 1;  // handled: the process-wide handler is not called
}

int on_warning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

}  // namespace

TiffMessages::TiffMessages() : options_(TIFFOpenOptionsAlloc()) {
  TIFFOpenOptionsSetErrorHandlerExtR(options_, on_error, this);
  TIFFOpenOptionsSetWarningHandlerExtR(options_, on_warning, this);
}

TiffMessages::~TiffMessages() { TIFFOpenOptionsFree(options_); }

void TiffMessages::add(const char* text) {
  if (text_.size() > 2000) return;
  if (!text_.empty()) text_ += "; ";
  text_ += text;
}

std::string TiffMessages::take() {
  std::string result = one_line(text_);
  text_.clear();
  return result;
}

std::size_t tiff_sample_bytes(TiffSample kind) {
  switch (kind) {
    case TiffSample::U8: return 1;
    case TiffSample::U16: return 2;
    case TiffSample::F16: return 2;
    case TiffSample::F32: return 4;
    case TiffSample::F64: return 8;
  }
  return 1;
}

void tiff_to_band(TiffSample kind, const unsigned char* src, std::size_t src_step, unsigned char* dst,
                  std::size_t dst_step, std::size_t count) {
  switch (kind) {
    case TiffSample::U8:
      for (std::size_t i = 0; i < count; ++i) dst[i * dst_step] = src[i * src_step];
      return;
    case TiffSample::U16: {
      for (std::size_t i = 0; i < count; ++i) std::memcpy(dst + i * dst_step * 2, src + i * src_step * 2, 2);
      return;
    }
    case TiffSample::F16:
      for (std::size_t i = 0; i < count; ++i) {
        _Float16 h;  // as the row stores convert halves (exact to float)
        std::memcpy(&h, src + i * src_step * 2, 2);
        const float f = h;
        std::memcpy(dst + i * dst_step * 4, &f, 4);
      }
      return;
    case TiffSample::F32:
      for (std::size_t i = 0; i < count; ++i) std::memcpy(dst + i * dst_step * 4, src + i * src_step * 4, 4);
      return;
    case TiffSample::F64:
      for (std::size_t i = 0; i < count; ++i) {
        double d;
        std::memcpy(&d, src + i * src_step * 8, 8);
        const float f = static_cast<float>(d);
        std::memcpy(dst + i * dst_step * 4, &f, 4);
      }
      return;
  }
}

}  // namespace gdp::io
