// Encoding FITS with cfitsio: float (or 8/16-bit) images, channels as NAXIS3 planes, extra header cards (WCS), rows top down.
#include <fitsio.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/fits_image.h"

namespace gdp::io {
namespace {

// Cards cfitsio writes itself from the image's shape.
bool structural(const std::string& card) {
  const std::string key = card.substr(0, 8);
  return key.rfind("SIMPLE", 0) == 0 || key.rfind("BITPIX", 0) == 0 || key.rfind("NAXIS", 0) == 0 ||
         key.rfind("EXTEND", 0) == 0 || key == "END     ";
}

class FitsEncoder final : public Encoder {
 public:
  ~FitsEncoder() override {
    int status = 0;
    if (f_) fits_close_file(f_, &status);
  }
  std::string format_name() const override { return "fits"; }

  void open(const std::string& path, const EncodeSpec& spec) override {
    spec_ = spec;
    stored_ = spec.sample_type == SampleType::UInt8 || spec.sample_type == SampleType::UInt16 ? spec.sample_type
                                                                                               : SampleType::Float;
    int status = 0;
    const std::string name = "!" + path;  // '!': replace the (empty) temporary file
    if (fits_create_file(&f_, name.c_str(), &status)) {
      f_ = nullptr;
      throw CodecError("cannot write FITS: " + fits_error(status));
    }
    long axes[3] = {spec.width, spec.height, spec.channels};
    const int bitpix = stored_ == SampleType::UInt8 ? BYTE_IMG : stored_ == SampleType::UInt16 ? USHORT_IMG : FLOAT_IMG;
    fits_create_img(f_, bitpix, spec.channels > 1 ? 3 : 2, axes, &status);
    for (std::size_t at = 0; at + 80 <= spec.fits_header.size(); at += 80) {
      std::string card = spec.fits_header.substr(at, 80);
      if (!structural(card)) fits_write_record(f_, card.c_str(), &status);
    }
    if (status) throw CodecError("cannot write the FITS header: " + fits_error(status));
  }

  SampleType stored() const override { return stored_; }
  bool integer_file() const override { return stored_ != SampleType::Float; }

  void write(int y0, int y1, const void* rows) override {
    const std::size_t w = static_cast<std::size_t>(spec_.width), ch = static_cast<std::size_t>(spec_.channels);
    const std::size_t bytes = sample_bytes(stored_);
    const int type = stored_ == SampleType::UInt8 ? TBYTE : stored_ == SampleType::UInt16 ? TUSHORT : TFLOAT;
    plane_.resize(w * bytes);
    const auto* src = static_cast<const unsigned char*>(rows);
    for (int y = y0; y < y1; ++y) {
      const unsigned char* row = src + static_cast<std::size_t>(y - y0) * w * ch * bytes;
      for (std::size_t c = 0; c < ch; ++c) {
        for (std::size_t x = 0; x < w; ++x) std::memcpy(&plane_[x * bytes], row + (x * ch + c) * bytes, bytes);
        long first[3] = {1, spec_.height - y, static_cast<long>(c) + 1};  // FITS rows count from the bottom
        int status = 0;
        if (fits_write_pix(f_, type, first, static_cast<LONGLONG>(w), plane_.data(), &status))
          throw write_error(nullptr, fits_error(status));
      }
    }
  }

  void close() override {
    int status = 0;
    fits_close_file(f_, &status);
    f_ = nullptr;
    if (status) throw write_error(nullptr, fits_error(status));
  }

 private:
  fitsfile* f_ = nullptr;
  EncodeSpec spec_;
  SampleType stored_ = SampleType::Float;
  std::vector<unsigned char> plane_;
};

}  // namespace

std::unique_ptr<Encoder> create_fits_encoder() { return std::make_unique<FitsEncoder>(); }

}  // namespace gdp::io
