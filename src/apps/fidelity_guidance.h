// Per-pixel weights and pinned pixels layered onto any application's guidance (--weights, --pin).
#pragma once

#include <vector>

#include "gdp/apps.h"
#include "gdp/guidance.h"
#include "gdp/solver.h"
#include "util/forwarding_guidance.h"

namespace gdp::apps {

// Forwards `inner`'s guidance and adds GuidanceRow::weight from the fidelity images: the
// weight image's first channel, plus kPinned where the pin mask's first channel exceeds 0.5.
// The values held are inner's `initial` rows (the composite, the image, or the low image),
// so `inner` must have has_initial(). Throws InputError naming the image for a size mismatch
// or a negative or non-finite weight.
class FidelityGuidance final : public util::ForwardingGuidance {
 public:
  FidelityGuidance(GuidanceSource& inner, const Fidelity& fidelity);
  bool has_weights() const override { return true; }
  bool has_initial() const override { return true; }
  void read_row(int j, GuidanceRow& out) override;
  void set_columns(int begin, int end) override;

 private:
  Fidelity fidelity_;
  std::vector<float> weights_row_, pins_row_;
};

// solve() on `guidance`, through a FidelityGuidance when `fidelity` has any image.
void solve_with_fidelity(GuidanceSource& guidance, const Fidelity& fidelity, const SolverOptions& solver,
                         RowWriter& out, SolveSummary* summary);

}  // namespace gdp::apps
