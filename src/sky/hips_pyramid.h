// The HiPS tile pyramid, streamed: deepest tiles sampled one at a time, each lower order by 2x2 averages of its children.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "gdp/image.h"

namespace gdp::sky {

// Fills a deepest-order tile (width x width, one channel, NaN where no data); returns false when
// it holds no finite pixel.
using HipsSample = std::function<bool(std::int64_t npix, Image& tile)>;
// Receives every tile with data, children before their parent; `tile` is valid during the call.
using HipsEmit = std::function<void(int order, std::int64_t npix, const Image& tile)>;

// For each of `deepest` (tile indices of order `order`, ascending) sample(); then every tile of
// orders order - 1 .. min_order holding data: pixel = mean of the finite ones among the 2x2
// child pixels covering it (NaN when none). A parent's child k (nested index 4 npix + k) fills
// its rows (k & 1) * width/2 + [0, width/2) and columns (k >> 1) * width/2 + [0, width/2) (rows
// are HEALPix x, columns y: hips_geometry.h). Memory: one tile per order.
void build_hips_pyramid(int order, int min_order, int width, const std::vector<std::int64_t>& deepest,
                        const HipsSample& sample, const HipsEmit& emit);

}  // namespace gdp::sky
