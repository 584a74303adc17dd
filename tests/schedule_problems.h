// Set-up shared by the schedule tests: starting guesses with seams to correct, domains by name.
#pragma once

#include "gdp/image.h"
#include "gdp/topology.h"

namespace gdp::test {

// `img` plus steps (seams for a V-cycle to correct, as in stitching): `right_third` right of
// x = w / 3, `lower_half` below y = h / 2 and `right_quarter` right of x = 3 w / 4.
inline Image with_seams(const Image& img, float right_third, float lower_half, float right_quarter) {
  Image out = img;
  for (int c = 0; c < img.channels; ++c)
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        out.at(c, x, y) += right_third * (x > img.width / 3) + lower_half * (y > img.height / 2) +
                           right_quarter * (x > 3 * img.width / 4);
  return out;
}

// "planar ", "cylindrical " or "spherical ": test parameters printed by gtest begin with it.
inline const char* domain_name(Domain d) {
  return d == Domain::Planar ? "planar " : d == Domain::Cylindrical ? "cylindrical " : "spherical ";
}

}  // namespace gdp::test
