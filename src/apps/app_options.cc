// Application options from names and units: --unknown and --space names, sharpen's scale to alpha.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gdp/apps.h"
#include "gdp/errors.h"

namespace gdp {

UnknownMode parse_unknown_mode(std::string_view name) {
  if (name == "black") return UnknownMode::Black;
  if (name == "harmonic") return UnknownMode::Harmonic;
  if (name == "label") return UnknownMode::Label;
  if (name == "extend") return UnknownMode::Extend;
  throw UsageError(fmt::format("--unknown must be black, harmonic, label or extend, got '{}'", name));
}

BlendSpace::Kind parse_blend_space(std::string_view name) {
  if (name == "values") return BlendSpace::Kind::Values;
  if (name == "log") return BlendSpace::Kind::Log;
  if (name == "lab") return BlendSpace::Kind::Lab;
  throw UsageError(fmt::format("--space must be values, log or lab, got '{}'", name));
}

void SharpenScale::validate(Domain domain) const {
  // Below 1/1000 pixel alpha = 1 / scale^2 is beyond what the solve takes (the input itself).
  if (!(pixels >= 1e-3 && std::isfinite(pixels)))
    throw UsageError(fmt::format("--scale must be a finite number of pixels, at least 0.001, got {}", pixels));
  if (at && !(*at > 0)) throw UsageError(fmt::format("--scale-at must be positive, got {}", *at));
  if (degrees && !(*degrees > 0.0 && *degrees < 180.0))
    throw UsageError(fmt::format("--scale-deg must be in (0, 180), got {}", *degrees));
  if (degrees && domain != Domain::Spherical)
    throw UsageError("--scale-deg needs a spherical image (--sphere or --domain spherical)");
}

double SharpenScale::alpha(Domain domain, int in_width, int in_height, int solved_width, int solved_height) const {
  validate(domain);
  double s = 0.0;
  if (degrees) {
    // A PQ image W = 4H pixels covers 4 pi steradians: a pixel spans sqrt(pi) / H radians.
    s = *degrees * M_PI / 180.0 * solved_height / std::sqrt(M_PI);
  } else {
    const double px = at ? pixels * std::max(in_width, in_height) / *at : pixels;
    s = px * std::sqrt(double(solved_width) * solved_height / (double(in_width) * in_height));
  }
  return 1.0 / std::pow(s, 2);
}

}  // namespace gdp
