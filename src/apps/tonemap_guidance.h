// Tone mapping's guidance: log-luminance gradients of the input times the attenuation Phi, row by row.
#pragma once

#include <optional>
#include <vector>

#include "apps/tonemap_filters.h"
#include "apps/tonemap_window.h"
#include "gdp/guidance.h"
#include "gdp/rows.h"

namespace gdp::apps::tonemap {

// Level 0 of the attenuation: phi_0 (from the input's own |grad H|, a_0 = alpha * mean) times
// Phi_1 expanded (when there is one). gx, gy are the forward differences of H = log luminance
// times the mean of Phi at the edge's two pixels, also across the PQ folds; the `initial`
// rows are H (the mean the solution keeps). Reads `in` once, from row 0, in step with the rows
// the solver asks for (H three rows ahead).
class Guidance final : public GuidanceSource {
 public:
  Guidance(RowReader& in, Domain domain, double a0, double beta, schedule::RowStore<float>* phi1, int phi1_width,
           int phi1_height);
  int width() const override { return in_.width(); }
  int height() const override { return in_.height(); }
  int channels() const override { return 1; }
  bool has_initial() const override { return true; }
  bool start_from_initial() const override { return false; }
  void read_row(int j, GuidanceRow& out) override;

 private:
  void read_input();
  std::span<const float> phi(int y) const { return phi_[y % 2]; }
  void make_phi(int y);

  RowReader& in_;
  double a0_, beta_;
  RowWindow log_l_;
  std::optional<Expander> expand_;
  std::vector<float> input_, row_, g_;
  std::vector<float> phi_[2];
  int phi_made_ = 0;
};

}  // namespace gdp::apps::tonemap
