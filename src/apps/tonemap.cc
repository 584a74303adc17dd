// gdp::tonemap: the passes of gradient-domain dynamic-range compression put together (docs/tonemap.md).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "apps/tonemap_attenuation.h"
#include "apps/tonemap_display.h"
#include "apps/tonemap_guidance.h"
#include "apps/tonemap_pyramid.h"
#include "gdp/apps.h"
#include "gdp/errors.h"

namespace gdp {

void TonemapOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw UsageError(fmt::format("--{} must be positive, got {}", name, v));
  };
  positive(alpha, "alpha");
  positive(beta, "beta");
  positive(gamma, "gamma");
  if (!(saturation >= 0.0) || !std::isfinite(saturation))
    throw UsageError(fmt::format("--saturation must be non-negative, got {}", saturation));
  if (scales < 0) throw UsageError(fmt::format("--scales must be 0 (automatic) or positive, got {}", scales));
  if (resolution < 0)
    throw UsageError(fmt::format("--resolution must be 0 (every level) or positive, got {}", resolution));
  if (!(low_percentile >= 0.0 && low_percentile < high_percentile && high_percentile <= 100.0))
    throw UsageError(fmt::format("percentiles must satisfy 0 <= low < high <= 100, got {} and {}", low_percentile,
                                 high_percentile));
}

void tonemap(RowReader& in, const TonemapOptions& options, const SolverOptions& solver, RowWriter& out,
             SolveSummary* summary) {
  options.validate();
  solver.validate();
  schedule::StorePolicy policy;
  policy.dir = solver.temp_dir;
  policy.budget = &schedule::ScratchBudget::process();  // the pyramid in memory while it fits
  policy.budget->apply(solver);
  // Its own stores (the log-luminance pyramid, the solved rows) keep floats: outside the
  // V-cycle, their rounding was never measured (solver.scratch is the V-cycle's).
  const Domain domain = solver.domain;

  // Pass 1: the pyramid of log luminance and each level's mean gradient; then Phi of levels >= 1.
  const int levels = apps::tonemap::pyramid_levels(in.width(), in.height(), options.scales);
  apps::tonemap::Pyramid pyramid = apps::tonemap::build_pyramid(in, domain, levels, policy);
  // The finest level that is attenuated: the first whose long side is at most options.resolution.
  int first = 0;
  if (options.resolution > 0)
    while (first + 1 < levels && std::max(pyramid.widths[first], pyramid.heights[first]) > options.resolution) ++first;
  const auto phi1 = apps::tonemap::coarse_attenuation(pyramid, domain, options.alpha, options.beta, first, policy);

  // Pass 2: the attenuated gradients, solved; the solution goes to a store.
  in.rewind();
  const double a0 = first == 0 ? options.alpha * pyramid.mean_gradient[0] : 0.0;  // 0: phi_0 = 1
  apps::tonemap::Guidance guidance(in, domain, a0, options.beta, phi1.get(),
                                   levels > 1 ? pyramid.widths[1] : 0, levels > 1 ? pyramid.heights[1] : 0);
  apps::tonemap::SolvedRows solved(in.width(), in.height(), policy);
  solve(guidance, solver, solved, summary);

  // Pass 3: percentiles of the solution, then colour and display values.
  const auto [low, high] = solved.percentiles(options.low_percentile, options.high_percentile);
  apps::tonemap::DisplayMap map;
  map.u_high = high;
  map.black = options.low_percentile > 0.0 ? std::exp(low - high) : 0.0;
  if (!(map.black < 0.999)) map.black = 0.0;  // a flat result: no black point to stretch from
  map.saturation = options.saturation;
  map.gamma = options.gamma;
  in.rewind();
  solved.write_display(in, map, out);
}

Image tonemap(const Image& image, const TonemapOptions& options, const SolverOptions& solver, SolveSummary* summary) {
  ImageRowReader in(image);
  Image out(image.width, image.height, image.channels);
  ImageRowWriter writer(out);
  tonemap(in, options, solver, writer, summary);
  return out;
}

}  // namespace gdp
