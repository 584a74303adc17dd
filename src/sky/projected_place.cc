// Placing reprojected images on their template: corners and centre mapped through both WCS; area images' scale.
#include "sky/projected_place.h"

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "io/fits_image.h"

namespace gdp::sky {
namespace {

constexpr double kAxisTolerance = 1e-6, kShiftTolerance = 1e-3;

}  // namespace

Shift place_on_template(const Wcs& image, const Wcs& tpl, const std::string& name) {
  if (image.frame() != tpl.frame())
    throw InputError(fmt::format("{}: longitude axis {}, but the template's is {}; gdp sky does not convert frames",
                                 name, image.frame(), tpl.frame()));
  if (image.projection() != tpl.projection())
    throw InputError(fmt::format("{}: projection {}, but the template's is {}; reproject it onto the template first "
                                 "(Montage's mProjExec)",
                                 name, image.projection(), tpl.projection()));
  // Pixel centres: the four corners, then the centre.
  const double w = image.width(), h = image.height();
  const std::array<double, 10> xy = {0.5, 0.5, w - 0.5, 0.5, 0.5, h - 0.5, w - 0.5, h - 0.5, w / 2, h / 2};
  std::array<double, 10> sky{}, t{};
  std::array<unsigned char, 5> ok{}, back{};
  image.pixel_to_sky(xy, sky, ok);
  tpl.sky_to_pixel(sky, t, back);
  for (int k = 0; k < 5; ++k)
    if (!ok[k] || !back[k])
      throw InputError(fmt::format("{}: pixel ({}, {}) has no position on the template's projection", name, xy[2 * k],
                                   xy[2 * k + 1]));
  // One pixel along the image's rows and down its columns, in template pixels.
  const double rx = w > 1 ? (t[2] - t[0]) / (w - 1) : 1, ry = w > 1 ? (t[3] - t[1]) / (w - 1) : 0;
  const double cx = h > 1 ? (t[4] - t[0]) / (h - 1) : 0, cy = h > 1 ? (t[5] - t[1]) / (h - 1) : 1;
  if (std::max({std::abs(rx - 1), std::abs(ry), std::abs(cx), std::abs(cy - 1)}) > kAxisTolerance)
    throw InputError(fmt::format("{}: not on the template's grid: its pixel steps are ({:.8g}, {:.8g}) and ({:.8g}, "
                                 "{:.8g}) template pixels (scale or rotation differs by more than 1e-6); reproject it "
                                 "onto the template first (Montage's mProjExec)",
                                 name, rx, ry, cx, cy));
  const double dx = t[8] - xy[8], dy = t[9] - xy[9];
  double spread = 0.0;
  for (int k = 0; k < 4; ++k)
    spread = std::max({spread, std::abs(t[2 * k] - xy[2 * k] - dx), std::abs(t[2 * k + 1] - xy[2 * k + 1] - dy)});
  if (spread > kShiftTolerance)
    throw InputError(fmt::format("{}: not the template's projection shifted: its corners lie up to {:.3g} pixels off "
                                 "one shift (CRVAL or the projection's parameters differ from the template's)",
                                 name, spread));
  if (std::abs(dx - std::round(dx)) > kShiftTolerance || std::abs(dy - std::round(dy)) > kShiftTolerance)
    throw InputError(fmt::format("{}: lies {:.4f}, {:.4f} pixels from the template's origin, not a whole number of "
                                 "pixels; reproject it onto the template first (Montage's mProjExec)",
                                 name, dx, dy));
  return {std::llround(dx), std::llround(dy)};
}

double largest_value(const std::string& path) {
  const std::unique_ptr<io::FitsImage> f = io::open_fits(path);
  std::vector<float> row(static_cast<std::size_t>(f->width()));
  double largest = 0.0;
  for (int y = 0; y < f->height(); ++y) {
    try {
      f->read(0, y, y + 1, 0, f->width(), row.data());
    } catch (const std::exception& e) {
      throw InputError(fmt::format("{}: {}", path, e.what()));
    }
    for (const float v : row)
      if (std::isfinite(v) && v > largest) largest = v;
  }
  if (!(largest > 0.0)) throw InputError(fmt::format("{}: an area image with no positive value", path));
  return largest;
}

LayerSource projected_layer(const ProjectedInput& input, const Wcs& tpl) {
  const std::unique_ptr<io::FitsImage> f = io::open_fits(input.image);
  if (f->planes() > 1)
    throw InputError(fmt::format("{}: {} planes; gdp sky --projected takes images of one plane (as mProjExec writes)",
                                 input.image, f->planes()));
  const Wcs wcs(f->header(), f->width(), f->height(), input.image);
  const Shift s = place_on_template(wcs, tpl, input.image);
  LayerSource layer;
  layer.image = input.image;
  layer.mask = input.area;
  layer.placed = true;
  layer.x = s.x;
  layer.y = s.y;
  if (!input.area.empty()) layer.mask_scale = static_cast<float>(1.0 / largest_value(input.area));
  return layer;
}

}  // namespace gdp::sky
