// Colour-space conversions for blending: log values, and CIE L*a*b* (D65) from linear or sRGB-encoded RGB.
#include "apps/colour_space.h"

#include <algorithm>
#include <cmath>

#include "gdp/errors.h"

namespace gdp::apps {
namespace {

// sRGB primaries, D65 white (IEC 61966-2-1).
constexpr double kToXyz[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                 {0.2126729, 0.7151522, 0.0721750},
                                 {0.0193339, 0.1191920, 0.9503041}};
constexpr double kFromXyz[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                   {-0.9692660, 1.8760108, 0.0415560},
                                   {0.0556434, -0.2040259, 1.0572252}};
constexpr double kWhite[3] = {0.95047, 1.0, 1.08883};

double srgb_decode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double srgb_encode(double c) {
  c = std::max(c, 0.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

constexpr double kDelta = 6.0 / 29.0;
double lab_f(double t) { return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3 * kDelta * kDelta) + 4.0 / 29.0; }
double lab_f_inverse(double f) { return f > kDelta ? f * f * f : 3 * kDelta * kDelta * (f - 4.0 / 29.0); }

void check_lab(int channels) {
  if (channels < 3) throw UsageError("the Lab blending space needs an RGB image (3 or more channels)");
}

// Log: each finite sample v becomes log_value(v); Lab: each pixel's first three channels go
// through lab_pixel(r, g, b).
template <class LogValue, class LabPixel>
void convert(const BlendSpace& space, std::span<float> row, int width, int channels, LogValue&& log_value,
             LabPixel&& lab_pixel) {
  if (space.kind == BlendSpace::Kind::Values) return;
  if (space.kind == BlendSpace::Kind::Log) {
    for (std::size_t k = 0; k < static_cast<std::size_t>(width) * channels; ++k)
      if (std::isfinite(row[k])) row[k] = static_cast<float>(log_value(double(row[k])));
    return;
  }
  check_lab(channels);
  float *r = row.data(), *g = r + width, *b = g + width;
  for (int i = 0; i < width; ++i) lab_pixel(r[i], g[i], b[i]);
}

}  // namespace

void to_space(const BlendSpace& space, std::span<float> row, int width, int channels) {
  const auto log_value = [&](double v) { return std::log(std::max(v, 0.0) + space.log_offset); };
  convert(space, row, width, channels, log_value, [&](float& r, float& g, float& b) {
    double rgb[3] = {r, g, b}, xyz[3] = {};
    if (space.srgb_encoded)
      for (double& v : rgb) v = srgb_decode(v);
    for (int a = 0; a < 3; ++a) xyz[a] = (kToXyz[a][0] * rgb[0] + kToXyz[a][1] * rgb[1] + kToXyz[a][2] * rgb[2]) / kWhite[a];
    const double fx = lab_f(xyz[0]), fy = lab_f(xyz[1]), fz = lab_f(xyz[2]);
    r = static_cast<float>(116.0 * fy - 16.0);
    g = static_cast<float>(500.0 * (fx - fy));
    b = static_cast<float>(200.0 * (fy - fz));
  });
}

void from_space(const BlendSpace& space, std::span<float> row, int width, int channels) {
  const auto log_value = [&](double v) { return std::exp(v) - space.log_offset; };
  convert(space, row, width, channels, log_value, [&](float& r, float& g, float& b) {
    const double fy = (r + 16.0) / 116.0, fx = fy + g / 500.0, fz = fy - b / 200.0;
    const double xyz[3] = {kWhite[0] * lab_f_inverse(fx), kWhite[1] * lab_f_inverse(fy), kWhite[2] * lab_f_inverse(fz)};
    double rgb[3];
    for (int a = 0; a < 3; ++a) rgb[a] = kFromXyz[a][0] * xyz[0] + kFromXyz[a][1] * xyz[1] + kFromXyz[a][2] * xyz[2];
    if (space.srgb_encoded)
      for (double& v : rgb) v = srgb_encode(v);
    r = static_cast<float>(rgb[0]);
    g = static_cast<float>(rgb[1]);
    b = static_cast<float>(rgb[2]);
  });
}

}  // namespace gdp::apps
