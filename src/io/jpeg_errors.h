// libjpeg's error handling and row hand-over, shared by gdp's JPEG decoder and encoder.
#pragma once

#include <cstdio>
// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>

#include <csetjmp>

namespace gdp::io {

// libjpeg reports errors by calling error_exit(), which here records the message and longjmp()s
// back to the guarded() call (io/guarded_call.h) that started it. A codec's libjpeg state derives
// from JpegErrors, sets cinfo.err = jpeg_errors(state, ...) and calls libjpeg only through
// guarded(state.jump, ...).
struct JpegErrors {
  jpeg_error_mgr errors{};  // first: error_exit finds the JpegErrors from cinfo->err
  std::jmp_buf jump{};
  char message[JMSG_LENGTH_MAX] = {};
};

inline void jpeg_error_exit(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->message);
  std::longjmp(e->jump, 1);
}

// `e`'s error manager, set up to call jpeg_error_exit on errors and `emit_message` on warnings
// and traces.
inline jpeg_error_mgr* jpeg_errors(JpegErrors& e, void (*emit_message)(j_common_ptr, int)) {
  jpeg_std_error(&e.errors);
  e.errors.error_exit = jpeg_error_exit;
  e.errors.emit_message = emit_message;
  return &e.errors;
}

// Hands `count` rows to `scanlines(rows, n)` (jpeg_read_scanlines or jpeg_write_scanlines, which
// may take fewer than n at a call) until all are done. False, with a message, should it take none:
// libjpeg then waits on a suspending source or destination, which gdp's are not; never loop on it.
template <class Scanlines>
bool all_scanlines(JpegErrors& e, unsigned char* const* rows, int count, Scanlines&& scanlines) {
  for (int done = 0; done < count;) {
    const JDIMENSION n = scanlines(const_cast<JSAMPARRAY>(rows + done), static_cast<JDIMENSION>(count - done));
    if (n == 0) {
      std::snprintf(e.message, sizeof e.message, "no more rows");
      return false;
    }
    done += static_cast<int>(n);
  }
  return true;
}

}  // namespace gdp::io
