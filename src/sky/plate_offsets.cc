// Plate offsets from overlaps: mean differences on sample points, then least squares on the overlap graph (Eigen's CG).
#include "sky/plate_offsets.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include "sky/overlap_samples.h"

namespace gdp::sky {

std::vector<double> offsets_from_overlaps(std::size_t count, const std::vector<OverlapSum>& pairs) {
  // L o = r: L the Laplacian weighted by n_ab, r_a = sum over a's pairs of sum(a - b). L is
  // singular (constants on each connected part), but each part's r sums to 0: conjugate gradients
  // from 0, unpreconditioned, stay orthogonal to the constants and end at the solution of mean 0
  // per part (a preconditioner would let each part drift by a constant).
  const auto n = static_cast<Eigen::Index>(count);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Triplet<double>> entries;
  for (const OverlapSum& p : pairs) {
    if (p.n == 0) continue;
    const auto w = static_cast<double>(p.n);
    r[p.a] += p.sum;
    r[p.b] -= p.sum;
    entries.insert(entries.end(), {{p.a, p.a, w}, {p.b, p.b, w}, {p.a, p.b, -w}, {p.b, p.a, -w}});
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(entries.begin(), entries.end());  // duplicates summed: the degrees on the diagonal
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper, Eigen::IdentityPreconditioner> cg;
  cg.setTolerance(1e-14);
  cg.setMaxIterations(4 * n + 20);
  const Eigen::VectorXd solved = cg.compute(L).solve(r), degree = L.diagonal();
  // Mean 0 over the images in some pair (each part's mean is 0 already, up to rounding).
  double mean = 0.0;
  long long linked = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (degree[k] > 0.0) {
      mean += solved[k];
      ++linked;
    }
  if (linked) mean /= static_cast<double>(linked);
  std::vector<double> o(count, 0.0);
  for (Eigen::Index k = 0; k < n; ++k)
    if (degree[k] > 0.0) o[k] = solved[k] - mean;
  return o;
}

OverlapSum overlap_sum(const Plate& a, int ia, const Plate& b, int ib) {
  OverlapSum o{ia, ib, 0.0, 0};
  for (const OverlapSample& p : overlap_samples(a, b)) {
    o.sum += p.difference;
    ++o.n;
  }
  return o;
}

std::vector<double> plate_offsets(const std::vector<Plate>& plates) {
  const std::size_t m = plates.size();
  std::vector<OverlapSum> pairs;
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a + 1; b < m; ++b)
      if (cones_meet(plates[a], plates[b]))
        if (const OverlapSum o = overlap_sum(plates[a], static_cast<int>(a), plates[b], static_cast<int>(b)); o.n > 0)
          pairs.push_back(o);
  return offsets_from_overlaps(m, pairs);
}

void set_fade_levels(std::vector<Plate>& plates, const std::vector<double>& o) {
  double level = 0.0;
  for (std::size_t k = 0; k < plates.size(); ++k) level += plates[k].mean - o[k];
  level /= static_cast<double>(plates.size());
  for (std::size_t k = 0; k < plates.size(); ++k) plates[k].fade_to = level + o[k];
}

}  // namespace gdp::sky
