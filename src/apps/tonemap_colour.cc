// Log luminance of input rows; colour restoration and the display mapping of solved rows.
#include "apps/tonemap_colour.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace gdp::apps::tonemap {
namespace {

constexpr double kWeights[3] = {0.2126, 0.7152, 0.0722};  // Rec. 709 / sRGB primaries

double clean(float v) { return std::isfinite(v) ? std::max(double(v), 0.0) : (v > 0 ? double(FLT_MAX) : 0.0); }

double luminance(std::span<const float> row, int width, int channels, int i) {
  if (colour_channels(channels) == 1) return clean(row[i]);
  double l = 0.0;
  for (int c = 0; c < 3; ++c) l += kWeights[c] * clean(row[static_cast<std::size_t>(c) * width + i]);
  return l;
}

}  // namespace

void log_luminance(std::span<const float> row, int width, int channels, std::span<float> out) {
  for (int i = 0; i < width; ++i)
    out[i] = static_cast<float>(std::log(std::max(luminance(row, width, channels, i), kMinLuminance)));
}

void display_row(std::span<const float> input, std::span<const float> u, int width, int channels,
                 const DisplayMap& map, std::span<float> out) {
  const int colours = colour_channels(channels);
  const double inv_gamma = 1.0 / map.gamma, stretch = 1.0 / (1.0 - map.black);
  for (int i = 0; i < width; ++i) {
    const double l_in = std::max(luminance(input, width, channels, i), kMinLuminance);
    const double l_out = std::isfinite(u[i]) ? std::exp(double(u[i]) - map.u_high) : 0.0;
    for (int c = 0; c < colours; ++c) {
      const std::size_t k = static_cast<std::size_t>(c) * width + i;
      const double ratio = colours == 1 ? 1.0 : clean(input[k]) / l_in;
      const double v = std::clamp((std::pow(ratio, map.saturation) * l_out - map.black) * stretch, 0.0, 1.0);
      out[k] = static_cast<float>(std::pow(v, inv_gamma));
    }
    for (int c = colours; c < channels; ++c) {
      const std::size_t k = static_cast<std::size_t>(c) * width + i;
      out[k] = input[k];
    }
  }
}

}  // namespace gdp::apps::tonemap
