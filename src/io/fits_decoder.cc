// Decoding FITS through FitsImage: a plain image as one channel, NAXIS3 = 2..4 planes as channels, else the first plane.
#include <cstring>
#include <vector>

#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/fits_image.h"

namespace gdp::io {
namespace {

class FitsDecoder final : public Decoder {
 public:
  explicit FitsDecoder(const std::string& path) : image_(path) {
    layout_.width = image_.width();
    layout_.height = image_.height();
    // A cube of 2-4 planes is what gdp writes for a multi-channel image; larger cubes (spectral
    // axes, ...) give their first plane (gdp sky takes any plane with --plane).
    const bool channels = image_.naxis() == 3 && image_.planes() >= 2 && image_.planes() <= 4;
    layout_.channels = channels ? static_cast<int>(image_.planes()) : 1;
    layout_.stored = SampleType::Float;
    layout_.info = {image_.sample_type(), "fits", false};
  }

  const ImageLayout& layout() const override { return layout_; }

  void read(int y0, int y1, int x0, int x1, void* out) override {
    float* dst = static_cast<float*>(out);
    const int ch = layout_.channels;
    if (ch == 1) return image_.read(0, y0, y1, x0, x1, dst);
    const std::size_t n = static_cast<std::size_t>(y1 - y0) * (x1 - x0);
    plane_.resize(n);
    for (int c = 0; c < ch; ++c) {
      image_.read(c, y0, y1, x0, x1, plane_.data());
      for (std::size_t k = 0; k < n; ++k) dst[k * ch + c] = plane_[k];
    }
  }

 private:
  FitsImage image_;
  ImageLayout layout_;
  std::vector<float> plane_;
};

}  // namespace

// "SIMPLE  =" opens every FITS file; gzipped ones (cfitsio reads them) are known by their name.
bool is_fits(const std::string& path, const unsigned char* head, std::size_t n) {
  if (n >= 8 && std::memcmp(head, "SIMPLE  ", 8) == 0) return true;
  if (n < 2 || head[0] != 0x1f || head[1] != 0x8b || lower_extension(path) != "gz") return false;
  const std::string inner = lower_extension(path.substr(0, path.size() - 3));
  return inner == "fits" || inner == "fit" || inner == "fts";
}

std::unique_ptr<Decoder> open_fits_decoder(const std::string& path) { return std::make_unique<FitsDecoder>(path); }

}  // namespace gdp::io
