// Gradient-domain sharpening and smoothing: scaled gradients, values held with weight alpha.
#include <fmt/format.h>

#include "apps/image_guidance.h"
#include "gdp/apps.h"
#include "gdp/errors.h"

namespace gdp {

Image sharpen(const Image& image, double alpha, double beta, const SolverOptions& solver, SolveSummary* summary) {
  if (!(alpha > 0.0)) throw UsageError(fmt::format("--alpha must be positive, got {}", alpha));
  if (!(beta >= 0.0)) throw UsageError(fmt::format("--beta must be non-negative, got {}", beta));
  apps::ImageGuidance guidance(image, &image, alpha, beta);
  Image out = solve(guidance, solver, &image, summary);
  restore_non_finite(out, image);
  return out;
}

}  // namespace gdp
