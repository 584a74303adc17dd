// A sky mosaic's PQ image as a WorldWideTelescope TOAST pyramid: grey stretched to [0, 1] with alpha for the covered sky.
#pragma once

#include <filesystem>
#include <utility>

#include "sky/pq_store.h"

namespace gdp::sky {

// The smallest TOAST PQ height (128 * 2^n) at least `height`.
int toast_height(int height);

// Writes `dir` (new or empty) from the whole-sphere `pq` (one channel, NaN where no plate is), read a
// row at a time (memory: the strips of 256 square rows per level, about 8 kB x H in all): PNG tiles of grey
// (linear from the 0.5th to the 99.5th percentile of the covered pixels) and alpha (1 where
// covered). Throws UsageError / OutputError as sphere::write_toast_pyramid does.
void write_sky_toast(const PqStore& pq, const std::filesystem::path& dir);

}  // namespace gdp::sky
