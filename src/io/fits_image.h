// One image HDU of a FITS file read with cfitsio: size, planes, header text and rows of floats.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gdp/image_io.h"

namespace gdp::io {

// The first HDU of `path` holding pixels (a primary array, an image extension, or a
// tile-compressed image; .gz files too). Rows are gdp's, top down: row y is FITS row NAXIS2 - y
// (FITS counts rows from the bottom). Integers come scaled by BSCALE/BZERO; BLANK integers and
// NaN floats come as NaN. Throws CodecError with the problem.
class FitsImage {
 public:
  explicit FitsImage(const std::string& path);
  ~FitsImage();
  FitsImage(const FitsImage&) = delete;
  FitsImage& operator=(const FitsImage&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  // Planes: the product of NAXIS3, NAXIS4, ... (1 for a plain image).
  long planes() const { return planes_; }
  int naxis() const { return naxis_; }
  // Double for BITPIX -64, else Float (integers are physical values once scaled, not fractions).
  SampleType sample_type() const { return sample_type_; }
  // Every header card of the HDU (80 characters each, no END card), as wcslib's wcspih reads it.
  const std::string& header() const { return header_; }
  // Rows [y0, y1), columns [x0, x1) of plane `plane` (0-based) into `out`, row after row.
  void read(long plane, int y0, int y1, int x0, int x1, float* out);

 private:
  struct File;
  std::unique_ptr<File> file_;
  int width_ = 0, height_ = 0, naxis_ = 0;
  long planes_ = 1;
  std::vector<long> axes_;  // NAXISn
  SampleType sample_type_ = SampleType::Float;
  std::string header_;
};

// cfitsio's message for a status code, with its error stack, on one line.
std::string fits_error(int status);

// A FitsImage of `path`, or InputError "<path>: <the problem>".
std::unique_ptr<FitsImage> open_fits(const std::string& path);

}  // namespace gdp::io
