// Per-handle libtiff message capture and TIFF sample conversion for the TIFF decoder and encoder.
#include "io/tiff_util.h"

#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include <Imath/half.h>

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

int on_warning(TIFF*, void* user, const char*, const char* format, va_list args) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, args);
  static_cast<TiffMessages*>(user)->warning(text);
  return 1;
}

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

void TiffMessages::warning(const char* text) {
  if (!warnings_are_errors_) return;
  add(text);
  warned_ = true;
}

std::string TiffMessages::take() {
  std::string result = one_line(text_);
  text_.clear();
  warned_ = false;
  return result;
}

void tiff_to_band(SampleType kind, const unsigned char* src, std::size_t src_step, unsigned char* dst,
                  std::size_t dst_step, std::size_t count) {
  switch (kind) {
    case SampleType::UInt8:
      for (std::size_t i = 0; i < count; ++i) dst[i * dst_step] = src[i * src_step];
      return;
    case SampleType::UInt16: {
      for (std::size_t i = 0; i < count; ++i) std::memcpy(dst + i * dst_step * 2, src + i * src_step * 2, 2);
      return;
    }
    case SampleType::Half:
      for (std::size_t i = 0; i < count; ++i) {
        std::uint16_t bits;  // Imath's half, not _Float16: clang before 15 (the fuzz build) lacks it on x86
        std::memcpy(&bits, src + i * src_step * 2, 2);
        const float f = Imath::half(Imath::half::FromBits, bits);
        std::memcpy(dst + i * dst_step * 4, &f, 4);
      }
      return;
    case SampleType::Float:
      for (std::size_t i = 0; i < count; ++i) std::memcpy(dst + i * dst_step * 4, src + i * src_step * 4, 4);
      return;
    case SampleType::Double:
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
