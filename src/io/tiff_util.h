// libtiff's messages captured per file handle, and TIFF sample kinds converted to band samples.
#pragma once

#include <tiffio.h>

#include "gdp/image_io.h"

#include <cstddef>
#include <string>

namespace gdp::io {

// Error messages of one TIFF handle: given to TIFFOpenOptions' handlers, so that no message
// reaches the process-wide handlers (which print to stderr) and threads never mix them up.
// Warnings are dropped (they concern tags) until warn_as_errors(): from then on (the decoder,
// while it decodes pixels) a warning means lost data ("Discarding N bytes to avoid buffer
// overrun") and is kept like an error, and warned() says that one came.
class TiffMessages {
 public:
  TiffMessages();
  ~TiffMessages();
  TiffMessages(const TiffMessages&) = delete;
  TiffMessages& operator=(const TiffMessages&) = delete;
  TIFFOpenOptions* options() const { return options_; }
  std::string take();  // the messages since the last take(), one line; "unknown error" if none
  void add(const char* text);
  void warn_as_errors() { warnings_are_errors_ = true; }
  void warning(const char* text);
  bool warned() const { return warned_; }

 private:
  TIFFOpenOptions* options_;
  std::string text_;
  bool warnings_are_errors_ = false, warned_ = false;
};

// Copies `count` samples of `kind` (every `src_step`-th from src) to band samples (UInt8, UInt16 or
// Float for the float kinds), every `dst_step`-th into dst.
void tiff_to_band(SampleType kind, const unsigned char* src, std::size_t src_step, unsigned char* dst,
                  std::size_t dst_step, std::size_t count);

}  // namespace gdp::io
