// Plate offsets from overlaps: mean differences on sample points, then least squares (CG) on the overlap graph.
#include "sky/plate_offsets.h"

#include <algorithm>
#include <cmath>

#include "sky/overlap_samples.h"

namespace gdp::sky {

std::vector<double> offsets_from_overlaps(std::size_t count, const std::vector<OverlapSum>& pairs) {
  // L o = r: L the Laplacian weighted by n_ab, r_a = sum over a's pairs of sum(a - b). Each
  // connected part's r sums to 0, so CG from 0 converges to the solution of mean 0 per part.
  std::vector<double> r(count, 0.0), diagonal(count, 0.0);
  for (const OverlapSum& p : pairs) {
    if (p.n == 0) continue;
    r[p.a] += p.sum;
    r[p.b] -= p.sum;
    diagonal[p.a] += static_cast<double>(p.n);
    diagonal[p.b] += static_cast<double>(p.n);
  }
  const auto apply = [&](const std::vector<double>& x, std::vector<double>& out) {
    for (std::size_t k = 0; k < count; ++k) out[k] = diagonal[k] * x[k];
    for (const OverlapSum& p : pairs) {
      out[p.a] -= static_cast<double>(p.n) * x[p.b];
      out[p.b] -= static_cast<double>(p.n) * x[p.a];
    }
  };
  const auto dot = [](const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) s += a[k] * b[k];
    return s;
  };
  std::vector<double> o(count, 0.0), d = r, q(count);
  double rr = dot(r, r);
  const double stop = rr * 1e-28;
  for (std::size_t it = 0; it < 4 * count + 20 && rr > stop && rr > 0.0; ++it) {
    apply(d, q);
    const double alpha = rr / dot(d, q);
    for (std::size_t k = 0; k < count; ++k) {
      o[k] += alpha * d[k];
      r[k] -= alpha * q[k];
    }
    const double next = dot(r, r);
    for (std::size_t k = 0; k < count; ++k) d[k] = r[k] + next / rr * d[k];
    rr = next;
  }
  double mean = 0.0;
  long long linked = 0;
  for (std::size_t k = 0; k < count; ++k)
    if (diagonal[k] > 0.0) {
      mean += o[k];
      ++linked;
    }
  if (linked) mean /= static_cast<double>(linked);
  for (std::size_t k = 0; k < count; ++k) o[k] = diagonal[k] > 0.0 ? o[k] - mean : 0.0;
  return o;
}

std::vector<double> plate_offsets(const std::vector<Plate>& plates) {
  const std::size_t m = plates.size();
  std::vector<OverlapSum> pairs;
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a + 1; b < m; ++b) {
      if (!cones_meet(plates[a], plates[b])) continue;
      OverlapSum o{static_cast<int>(a), static_cast<int>(b), 0.0, 0};
      for (const OverlapSample& p : overlap_samples(plates[a], plates[b])) {
        o.sum += p.difference;
        ++o.n;
      }
      if (o.n > 0) pairs.push_back(o);
    }
  return offsets_from_overlaps(m, pairs);
}

void set_fade_levels(std::vector<Plate>& plates) {
  const std::vector<double> o = plate_offsets(plates);
  double level = 0.0;
  for (std::size_t k = 0; k < plates.size(); ++k) level += plates[k].mean - o[k];
  level /= static_cast<double>(plates.size());
  for (std::size_t k = 0; k < plates.size(); ++k) plates[k].fade_to = level + o[k];
}

}  // namespace gdp::sky
