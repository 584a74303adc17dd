// Gradient-domain sharpening and smoothing: scaled gradients, values held with weight alpha.
#include <cmath>

#include <fmt/format.h>

#include "apps/fidelity_guidance.h"
#include "apps/image_guidance.h"
#include "apps/output_fixups.h"
#include "gdp/apps.h"
#include "gdp/errors.h"

namespace gdp {
namespace {

// Image guidance that also notes the input's blanks for the output. With a `low` image, the
// values (and the starting guess) come from it instead of the image.
class Recorded final : public apps::ImageGuidance {
 public:
  Recorded(RowReader& image, double alpha, double beta, bool start, apps::OutputFixups& fixups, RowReader* low)
      : ImageGuidance(image, alpha, beta, start), fixups_(fixups), low_(low) {
    if (low) low_row_.resize(static_cast<std::size_t>(low->channels()) * low->width());
  }
  void set_columns(int begin, int end) override {
    ImageGuidance::set_columns(begin, end);
    if (low_) low_->set_columns(begin, end);
  }
  void read_row(int j, GuidanceRow& out) override {
    ImageGuidance::read_row(j, out);
    if (!low_) return;
    low_->read_row(j, low_row_);
    std::copy(low_row_.begin(), low_row_.end(), out.initial.begin());
    for (std::size_t k = 0; k < low_row_.size(); ++k) out.value[k] = std::isfinite(low_row_[k]) ? low_row_[k] : 0.0;
  }

 protected:
  void on_source_row(int y, std::span<const float> row) override { fixups_.record(y, row); }

 private:
  apps::OutputFixups& fixups_;
  RowReader* low_;
  std::vector<float> low_row_;
};

void solve_image(RowReader& image, double alpha, double beta, bool start, const SolverOptions& solver, RowWriter& out,
                 SolveSummary* summary, RowReader* low = nullptr, const Fidelity& fidelity = {}) {
  apps::OutputFixups fixups(out, image.width(), image.height(), image.channels(), solver);
  Recorded guidance(image, alpha, beta, start, fixups, low);
  apps::solve_with_fidelity(guidance, fidelity, solver, fixups, summary);
}

// Above these the solve overflows in float (alpha 1e6 is a scale of 1/1000 pixel: the input itself).
constexpr double kMaxAlpha = 1e6, kMaxBeta = 1e6;

void check_parameters(double alpha, double beta) {
  if (!(alpha > 0.0 && alpha <= kMaxAlpha))
    throw UsageError(fmt::format("--alpha must be in (0, {:g}], got {}", kMaxAlpha, alpha));
  if (!(beta >= 0.0 && beta <= kMaxBeta))
    throw UsageError(fmt::format("--beta must be in [0, {:g}], got {}", kMaxBeta, beta));
}

}  // namespace

void sharpen(RowReader& image, double alpha, double beta, const SolverOptions& solver, RowWriter& out,
             SolveSummary* summary, const Fidelity& fidelity) {
  check_parameters(alpha, beta);
  solve_image(image, alpha, beta, true, solver, out, summary, nullptr, fidelity);
}

void sharpen(RowReader& high, RowReader& low, double alpha, double beta, const SolverOptions& solver, RowWriter& out,
             SolveSummary* summary, const Fidelity& fidelity) {
  check_parameters(alpha, beta);
  if (low.width() != high.width() || low.height() != high.height() || low.channels() != high.channels())
    throw InputError(fmt::format("the low-frequency image is {}x{}x{} but the image is {}x{}x{}", low.width(),
                                 low.height(), low.channels(), high.width(), high.height(), high.channels()));
  solve_image(high, alpha, beta, true, solver, out, summary, &low, fidelity);
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
