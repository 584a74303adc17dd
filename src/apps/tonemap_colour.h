// Tone mapping's per-pixel colour maths: log luminance in, colour restoration and display mapping out.
#pragma once

#include <span>

namespace gdp::apps::tonemap {

// Luminances below this (and zero, negative or non-finite samples) count as this much.
inline constexpr double kMinLuminance = 1e-6;

// Channels that make the luminance: RGB (Rec. 709 weights) when there are three or more, else
// the first channel alone. Later channels (alpha, ...) pass through.
inline int colour_channels(int channels) { return channels >= 3 ? 3 : 1; }

// H = log(max(L, kMinLuminance)) of a channel-major row.
void log_luminance(std::span<const float> row, int width, int channels, std::span<float> out);

// How solved log luminance u becomes display values: L_out = exp(u); colour
// C = (C_in / L_in)^saturation * L_out; then (C / hi - black) / (1 - black) clamped to [0, 1]
// and raised to 1 / gamma, where hi = exp(u_high) and black = exp(u_low - u_high) (or 0).
struct DisplayMap {
  double u_high = 0.0;
  double black = 0.0;
  double saturation = 1.0;
  double gamma = 1.0;
};

// One output row from the input row and the solved log luminance of that row.
void display_row(std::span<const float> input, std::span<const float> u, int width, int channels,
                 const DisplayMap& map, std::span<float> out);

}  // namespace gdp::apps::tonemap
