// Gradient-domain sharpening and smoothing: scaled gradients, values held with weight alpha.
#include <fmt/format.h>

#include "apps/image_guidance.h"
#include "apps/output_fixups.h"
#include "gdp/apps.h"
#include "gdp/errors.h"

namespace gdp {
namespace {

// Image guidance that also notes the input's blanks for the output.
class Recorded final : public apps::ImageGuidance {
 public:
  Recorded(RowReader& image, double alpha, double beta, bool start, apps::OutputFixups& fixups)
      : ImageGuidance(image, alpha, beta, start), fixups_(fixups) {}

 protected:
  void on_source_row(int y, std::span<const float> row) override { fixups_.record(y, row); }

 private:
  apps::OutputFixups& fixups_;
};

void solve_image(RowReader& image, double alpha, double beta, bool start, const SolverOptions& solver, RowWriter& out,
                 SolveSummary* summary) {
  apps::OutputFixups fixups(out, image.width(), image.height(), image.channels(), solver);
  Recorded guidance(image, alpha, beta, start, fixups);
  solve(guidance, solver, fixups, summary);
}

}  // namespace

void sharpen(RowReader& image, double alpha, double beta, const SolverOptions& solver, RowWriter& out,
             SolveSummary* summary) {
  if (!(alpha > 0.0)) throw UsageError(fmt::format("--alpha must be positive, got {}", alpha));
  if (!(beta >= 0.0)) throw UsageError(fmt::format("--beta must be non-negative, got {}", beta));
  solve_image(image, alpha, beta, true, solver, out, summary);
}

Image sharpen(const Image& image, double alpha, double beta, const SolverOptions& solver, SolveSummary* summary) {
  ImageRowReader in(image);
  Image out(image.width, image.height, image.channels);
  ImageRowWriter writer(out);
  sharpen(in, alpha, beta, solver, writer, summary);
  return out;
}

void reconstruct(RowReader& image, const SolverOptions& solver, RowWriter& out, SolveSummary* summary) {
  solve_image(image, 0.0, 1.0, false, solver, out, summary);
}

}  // namespace gdp
