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
  return solve(guidance, solver, &image, summary);
}

}  // namespace gdp
