// Plate levels from their overlaps: each plate's constant offset against its neighbours (where its extension fades to).
#pragma once

#include <vector>

#include "sky/plate.h"

namespace gdp::sky {

// The sum of (a - b) over n points that images a and b both cover.
struct OverlapSum {
  int a = 0, b = 0;
  double sum = 0.0;
  long long n = 0;
};

// Offsets o_k of `count` images minimising sum over pairs of n_ab (o_a - o_b - sum_ab / n_ab)^2
// (conjugate gradients on the overlap graph's Laplacian), mean 0 over the images in some pair;
// images in none get 0.
std::vector<double> offsets_from_overlaps(std::size_t count, const std::vector<OverlapSum>& pairs);

// The sum of (a - b) over the overlap samples of plates a and b (indices ia < ib; overlap_samples).
OverlapSum overlap_sum(const Plate& a, int ia, const Plate& b, int ib);

// Offsets o_k minimising sum over overlapping pairs of n_ab (o_a - o_b - d_ab)^2, where d_ab is
// the mean of (a - b) over n_ab sample points inside both plates (every `stride`-th pixel of a,
// about 64 per side), with mean 0 over the plates that overlap some other. Plates overlapping
// none get 0. No I/O; the plates' WCS are used (not thread-safe, like Wcs).
std::vector<double> plate_offsets(const std::vector<Plate>& plates);

// Sets every plate's `fade_to`: the sky's common level (the mean of mean_k - o_k) plus the
// plate's own offset o_k (`offsets`: plate_offsets or offsets_from_overlaps), so the extensions
// of plates that differ by constants end on values the solve makes equal, and those of plates
// over a varying sky end on nearly one level.
void set_fade_levels(std::vector<Plate>& plates, const std::vector<double>& offsets);

}  // namespace gdp::sky
