// The attenuation Phi of the coarse levels, each level one streamed pass over its log luminance.
#include "apps/tonemap_attenuation.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "apps/tonemap_filters.h"
#include "apps/tonemap_window.h"

namespace gdp::apps::tonemap {

std::unique_ptr<schedule::RowStore<float>> coarse_attenuation(Pyramid& pyramid, Domain domain, double alpha,
                                                              double beta, int first,
                                                              const schedule::StorePolicy& policy) {
  std::unique_ptr<schedule::RowStore<float>> finer;  // Phi_{k+1} while level k is made
  for (int k = pyramid.levels - 1; k >= 1; --k) {
    const int w = pyramid.widths[k], h = pyramid.heights[k];
    auto phi = std::make_unique<schedule::RowStore<float>>(policy, w, h, fmt::format("tonemap-phi{}", k));
    schedule::RowStore<float>& levels = *pyramid.rows[k];
    levels.rewind();
    RowWindow window(domain, w, h, 4);
    std::optional<Expander> expand;
    if (finer) expand.emplace(*finer, domain, pyramid.widths[k + 1], pyramid.heights[k + 1], w);
    std::vector<float> in(w), g(w), out(w);
    for (int y = 0; y < h; ++y) {
      while (window.pushed() < std::min(y + 2, h)) {
        levels.read(in);
        window.push(in);
      }
      gradient_magnitude(window, y, g);
      if (expand) expand->row(y, out);
      else std::fill(out.begin(), out.end(), 1.0f);
      multiply_phi(g, k >= first ? alpha * pyramid.mean_gradient[k] : 0.0, beta, out);
      phi->append(out);
    }
    pyramid.rows[k].reset();
    expand.reset();
    finer = std::move(phi);
  }
  return finer;
}

}  // namespace gdp::apps::tonemap
