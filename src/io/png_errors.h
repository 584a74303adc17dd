// libpng's error and warning callbacks, shared by gdp's PNG decoder, encoder and seam files.
#pragma once

#include <png.h>

#include <cstdio>

namespace gdp::io {

// The message of libpng's last error. A caller's libpng state derives from it and passes
// static_cast<PngErrors*>(&state) as the error pointer with png_error_callback/png_warning_callback.
// The error callback keeps the message and longjmp()s back to the guarded() call
// (io/guarded_call.h, with png_jmpbuf(png)) that started it.
struct PngErrors {
  char message[256] = {};
};

inline void png_error_callback(png_structp png, png_const_charp message) {
  auto* errors = static_cast<PngErrors*>(png_get_error_ptr(png));
  std::snprintf(errors->message, sizeof errors->message, "%s", message ? message : "libpng error");
  png_longjmp(png, 1);
}

// Warnings are benign (unknown chunks, sRGB profile notes): ignored.
inline void png_warning_callback(png_structp, png_const_charp) {}

}  // namespace gdp::io
