// Fidelity guidance: weights and pins read row by row beside the application's own guidance.
#include "apps/fidelity_guidance.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::apps {
namespace {

void check_size(const RowReader* r, const std::string& name, const GuidanceSource& inner) {
  if (r && (r->width() != inner.width() || r->height() != inner.height()))
    throw InputError(fmt::format("{} is {}x{} but the input is {}x{}", name, r->width(), r->height(), inner.width(),
                                 inner.height()));
}

}  // namespace

FidelityGuidance::FidelityGuidance(GuidanceSource& inner, const Fidelity& fidelity)
    : ForwardingGuidance(inner), fidelity_(fidelity) {
  if (!inner.has_initial()) throw std::logic_error("FidelityGuidance needs a source with initial rows");
  check_size(fidelity.weights, fidelity.weights_name, inner);
  check_size(fidelity.pins, fidelity.pins_name, inner);
  if (fidelity.weights) weights_row_.resize(static_cast<std::size_t>(fidelity.weights->channels()) * width());
  if (fidelity.pins) pins_row_.resize(static_cast<std::size_t>(fidelity.pins->channels()) * width());
}

void FidelityGuidance::set_columns(int begin, int end) {
  ForwardingGuidance::set_columns(begin, end);
  for (RowReader* r : {fidelity_.weights, fidelity_.pins})
    if (r) r->set_columns(begin, end);
}

void FidelityGuidance::read_row(int j, GuidanceRow& out) {
  inner_.read_row(j, out);
  const int w = width();
  for (std::size_t k = 0; k < out.value.size(); ++k) out.value[k] = out.initial[k];
  std::fill(out.weight.begin(), out.weight.end(), 0.0);
  if (fidelity_.weights) {
    fidelity_.weights->read_row(j, weights_row_);
    for (int i = 0; i < w; ++i) {
      const float v = weights_row_[i];  // the first channel
      if (!(v >= 0.0f) || !std::isfinite(v))
        throw InputError(fmt::format("{}: weight {} at pixel ({}, {}); weights must be finite and >= 0",
                                     fidelity_.weights_name, v, i, j));
      out.weight[i] = v;
    }
  }
  if (fidelity_.pins) {
    fidelity_.pins->read_row(j, pins_row_);
    for (int i = 0; i < w; ++i)
      if (pins_row_[i] > 0.5f) out.weight[i] = kPinned;
  }
}

void solve_with_fidelity(GuidanceSource& guidance, const Fidelity& fidelity, const SolverOptions& solver,
                         RowWriter& out, SolveSummary* summary) {
  if (!fidelity.any()) return solve(guidance, solver, out, summary);
  FidelityGuidance weighted(guidance, fidelity);
  solve(weighted, solver, out, summary);
}

}  // namespace gdp::apps
