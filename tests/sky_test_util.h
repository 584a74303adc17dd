// Checks shared by the sky tests: a written FITS file carries a template's WCS.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "io/fits_image.h"
#include "sky/header.h"
#include "sky/wcs.h"

namespace gdp::test {

// The FITS file's header maps a pixel to the sky as the template (Montage's form) does.
inline void expect_template_wcs(const std::string& fits, const std::string& hdr) {
  io::FitsImage out(fits);
  const int w = out.width(), h = out.height();
  const sky::Wcs written(out.header(), w, h, fits), asked(sky::read_header_template(hdr), w, h, hdr);
  double a = 0, b = 0, c = 0, d = 0;
  ASSERT_TRUE(written.pixel_to_sky(w * 0.3 + 0.5, h * 0.6 + 0.25, a, b));
  ASSERT_TRUE(asked.pixel_to_sky(w * 0.3 + 0.5, h * 0.6 + 0.25, c, d));
  EXPECT_DOUBLE_EQ(a, c);
  EXPECT_DOUBLE_EQ(b, d);
}

}  // namespace gdp::test
