// Reading one FITS image HDU with cfitsio: parameters, header cards, scaled rows with blanks as NaN.
#include "io/fits_image.h"

#include <fitsio.h>

#include <cmath>
#include <exception>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "io/codec.h"
#include "io/codec_util.h"

namespace gdp::io {

struct FitsImage::File {
  fitsfile* f = nullptr;
  ~File() {
    int status = 0;
    if (f) fits_close_file(f, &status);
  }
};

std::string fits_error(int status) {
  char text[FLEN_STATUS] = {};
  fits_get_errstatus(status, text);
  std::string message = text;
  char line[FLEN_ERRMSG] = {};
  std::string stack;
  while (fits_read_errmsg(line)) {
    if (!stack.empty()) stack += "\n";
    stack += line;
  }
  if (!stack.empty() && stack.find(message) == std::string::npos) message += "\n" + stack;
  else if (!stack.empty()) message = stack;
  return one_line(message);
}

FitsImage::FitsImage(const std::string& path) : file_(std::make_unique<File>()) {
  int status = 0;
  // fits_open_image moves past an empty primary HDU to the first image extension.
  // On failure the handle may be open all the same (an HDU that is not an image): ~File closes it.
  if (fits_open_image(&file_->f, path.c_str(), READONLY, &status)) {
    throw CodecError("cannot read FITS: " + fits_error(status));
  }
  int equivalent = 0, bitpix = 0, naxis = 0;
  long naxes[9] = {0};
  fits_get_img_equivtype(file_->f, &equivalent, &status);
  fits_get_img_param(file_->f, 9, &bitpix, &naxis, naxes, &status);
  if (status) throw CodecError("cannot read FITS: " + fits_error(status));
  naxis_ = naxis;
  if (naxis < 2) throw CodecError(fmt::format("FITS HDU has {} axes; an image needs 2 or more", naxis));
  if (naxis > 9) throw CodecError(fmt::format("FITS HDU has {} axes; gdp reads at most 9", naxis));
  if (naxes[0] > std::numeric_limits<int>::max() || naxes[1] > std::numeric_limits<int>::max())
    throw CodecError(fmt::format("FITS image of {}x{} pixels is too large", naxes[0], naxes[1]));
  width_ = static_cast<int>(naxes[0]);
  height_ = static_cast<int>(naxes[1]);
  axes_.assign(naxes, naxes + naxis);
  for (int k = 2; k < naxis; ++k) planes_ *= naxes[k];
  if (width_ <= 0 || height_ <= 0 || planes_ <= 0) throw CodecError("FITS image has zero size");
  // Integers are physical values after BSCALE/BZERO, not fractions of a range: floats to gdp.
  sample_type_ = equivalent == DOUBLE_IMG ? SampleType::Double : SampleType::Float;
  char* cards = nullptr;
  int count = 0;
  if (fits_convert_hdr2str(file_->f, 1, nullptr, 0, &cards, &count, &status))
    throw CodecError("cannot read the FITS header: " + fits_error(status));
  header_.assign(cards, static_cast<std::size_t>(count) * 80);
  fits_free_memory(cards, &status);
}

FitsImage::~FitsImage() = default;

std::unique_ptr<FitsImage> open_fits(const std::string& path) {
  try {
    return std::make_unique<FitsImage>(path);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
}

void FitsImage::read(long plane, int y0, int y1, int x0, int x1, float* out) {
  // Coordinates of the first pixel of each row: column, row, then the plane over axes 3...
  long first[9], last[9], step[9];
  long rest = plane;
  for (int k = 0; k < naxis_; ++k) step[k] = 1;
  for (int k = 2; k < naxis_; ++k) {
    first[k] = last[k] = rest % axes_[k] + 1;
    rest /= axes_[k];
  }
  first[0] = x0 + 1;
  last[0] = x1;
  float blank = std::numeric_limits<float>::quiet_NaN();
  const std::size_t w = static_cast<std::size_t>(x1 - x0);
  for (int y = y0; y < y1; ++y) {
    first[1] = last[1] = height_ - y;
    int any = 0, status = 0;
    if (fits_read_subset(file_->f, TFLOAT, first, last, step, &blank, out + (y - y0) * w, &any, &status))
      throw CodecError(fmt::format("cannot read FITS row {}: {}", height_ - y, fits_error(status)));
  }
}

}  // namespace gdp::io
