// Sample points two plates share: where in each plate they lie and the difference of the plates' values there.
#pragma once

#include <vector>

#include "sky/plate.h"

namespace gdp::sky {

// One point inside plates a and b: its pixel coordinates in each, and a's value minus b's.
struct OverlapSample {
  double ax = 0, ay = 0, bx = 0, by = 0;
  double difference = 0;
};

// Whether the cones containing a and b meet (a cheap test before sampling).
bool cones_meet(const Plate& a, const Plate& b);

// a's finite pixels on a grid of about 64 x 64 (every stride-th pixel centre) that lie inside b
// where b has a value (b sampled as Plate::sample does). Uses both WCS (not thread-safe).
std::vector<OverlapSample> overlap_samples(const Plate& a, const Plate& b);

// The most samples overlap_samples(a, b) can give: a's grid points (needs only a's size).
std::size_t overlap_sample_bound(const Plate& a);

}  // namespace gdp::sky
