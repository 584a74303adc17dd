// Attenuated log-luminance gradients streamed to the solver, across periodic columns and PQ folds.
#include "apps/tonemap_guidance.h"

#include <algorithm>

#include "apps/tonemap_colour.h"
#include "fem/axis.h"

namespace gdp::apps::tonemap {

Guidance::Guidance(RowReader& in, Domain domain, double a0, double beta, schedule::RowStore<float>* phi1,
                   int phi1_width, int phi1_height)
    : in_(in), a0_(a0), beta_(beta), log_l_(domain, in.width(), in.height(), 4),
      input_(static_cast<std::size_t>(in.channels()) * in.width()), row_(in.width()), g_(in.width()) {
  if (phi1) expand_.emplace(*phi1, domain, phi1_width, phi1_height, in.width());
  for (auto& p : phi_) p.resize(in.width());
}

void Guidance::read_input() {
  const int y = log_l_.pushed();
  in_.read_row(y, input_);
  log_luminance(input_, width(), in_.channels(), row_);
  log_l_.push(row_);
}

void Guidance::make_phi(int y) {
  std::vector<float>& p = phi_[y % 2];
  gradient_magnitude(log_l_, y, g_);
  if (expand_) expand_->row(y, p);
  else std::fill(p.begin(), p.end(), 1.0f);
  multiply_phi(g_, a0_, beta_, p);
}

void Guidance::read_row(int j, GuidanceRow& out) {
  const int w = width(), h = height(), e = out.x_edges;
  while (log_l_.pushed() < std::min(j + 3, h)) read_input();
  while (phi_made_ <= std::min(j + 1, h - 1)) make_phi(phi_made_++);
  const std::span<const float> here = log_l_.row(j), p = phi(j);
  const auto edge = [](double h0, double h1, double p0, double p1) { return (h1 - h0) * 0.5 * (p0 + p1); };
  for (int i = 0; i < e; ++i) {
    const int k = i + 1 < w ? i + 1 : 0;
    out.gx[i] = edge(here[i], here[k], p[i], p[k]);
  }
  if (j + 1 < h) {
    const std::span<const float> next = log_l_.row(j + 1), pn = phi(j + 1);
    for (int i = 0; i < w; ++i) out.gy[i] = edge(here[i], next[i], p[i], pn[i]);
  } else if (out.spherical) {  // across the bottom fold
    for (int i = 0; i < w; ++i) {
      const int k = fem::mirror_column(fem::Mirror::Bottom, i, w);
      out.gy[i] = edge(here[i], here[k], p[i], p[k]);
    }
  } else {
    std::fill(out.gy.begin(), out.gy.end(), 0.0);
  }
  if (out.spherical && j == 0)  // across the top fold
    for (int i = 0; i < w; ++i) {
      const int k = fem::mirror_column(fem::Mirror::Top, i, w);
      out.gy_above[i] = edge(here[k], here[i], p[k], p[i]);
    }
  std::copy(here.begin(), here.end(), out.initial.begin());
}

}  // namespace gdp::apps::tonemap
