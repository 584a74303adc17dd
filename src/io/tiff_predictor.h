// TIFF's predictors (tag 317) applied to one row before compression: horizontal differencing and the floating-point predictor.
#pragma once

#include <cstddef>

namespace gdp::io {

// Horizontal differencing (predictor 2) of a row of `width` pixels of `channels` unsigned
// samples of `bytes` (1 or 2) each, in the machine's (little-endian) order, in place: every sample
// becomes its difference to the same channel's sample one pixel to the left, modulo 2^bits.
void horizontal_difference(unsigned char* row, int width, int channels, std::size_t bytes);

// The floating-point predictor (3, Adobe's TIFF Technical Note 3) of a row of `width` pixels of
// `channels` IEEE samples of `bytes` (4 or 8) each, from `row` into `out` (same size): the
// samples' bytes regrouped by significance, most significant first, then each byte replaced by
// its difference to the byte `channels` places before it.
void float_difference(const unsigned char* row, unsigned char* out, int width, int channels, std::size_t bytes);

}  // namespace gdp::io
