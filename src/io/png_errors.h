// libpng's error and warning callbacks, shared by gdp's PNG decoder, encoder and seam files.
#pragma once

#include <png.h>

#include <cstdio>

namespace gdp::io {

// The message of libpng's last error. A caller's libpng state derives from it and makes its
// libpng struct with png_reader(state) or png_writer(state).
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

// libpng's read and write structs reporting to `errors` (nullptr when out of memory).
inline png_structp png_reader(PngErrors& errors) {
  return png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, png_error_callback, png_warning_callback);
}
inline png_structp png_writer(PngErrors& errors) {
  return png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, png_error_callback, png_warning_callback);
}

}  // namespace gdp::io
