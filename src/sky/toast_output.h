// A sky mosaic's PQ image as a WorldWideTelescope TOAST pyramid: grey stretched to [0, 1] with alpha for the covered sky.
#pragma once

#include <filesystem>
#include <utility>

#include "gdp/image.h"

namespace gdp::sky {

// The smallest TOAST PQ height (128 * 2^n) at least `height`.
int toast_height(int height);

// The display cut of a sky image: its covered (finite) pixels' 0.5th and 99.5th percentiles
// (hi > lo; 0, 1 when nothing is covered).
std::pair<float, float> display_range(const Image& pq);

// Writes `dir` (new or empty) from `pq` (one channel, NaN where no plate is): PNG tiles of grey
// (linear from the 0.5th to the 99.5th percentile of the covered pixels) and alpha (1 where
// covered). Throws UsageError / OutputError as sphere::write_toast_pyramid does.
void write_sky_toast(const Image& pq, const std::filesystem::path& dir);

}  // namespace gdp::sky
