// Smooth plate backgrounds from the overlaps: block-sparse normal equations, damped smooth terms, Huber-weighted (IRLS), Eigen's CG.
#include "sky/plate_backgrounds.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <utility>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <fmt/format.h>

#include "sky/overlap_samples.h"

namespace gdp::sky {
namespace {

constexpr int kTerms = 4;
constexpr int kReweightings = 6;  // Huber iterations after the plain least-squares fit
// Huber's limit in robust spreads of the residuals: 3, not the usual 1.345, which also trims the
// model's own misfit (12-plate bench: bg rms 0.0057 with 1.345, 0.0054 with 3, least squares 0.0053).
constexpr double kHuber = 3.0;
using Block = std::array<double, kTerms * kTerms>;

// The normal equations N x = rhs of weighted equations, x = the plates' coefficients one after
// another: diagonal blocks per plate, one off-diagonal block per pair (a < b; the (b, a) block is
// its transpose).
struct NormalEquations {
  std::vector<Block> diagonal;
  std::map<std::pair<int, int>, Block> pairs;
  std::vector<double> rhs;

  explicit NormalEquations(std::size_t count) : diagonal(count, Block{}), rhs(count * kTerms, 0.0) {}

  void add(const BackgroundEquation& e, double weight) {
    const bool swap = e.a > e.b;  // keep the pair's block as (min, max)
    const int lo = swap ? e.b : e.a, hi = swap ? e.a : e.b;
    const auto& p = swap ? e.basis_b : e.basis_a;  // basis of lo
    const auto& q = swap ? e.basis_a : e.basis_b;
    const double d = swap ? -e.difference : e.difference;  // lo's value minus hi's
    Block& off = pairs[{lo, hi}];
    for (int i = 0; i < kTerms; ++i) {
      for (int j = 0; j < kTerms; ++j) {
        diagonal[lo][i * kTerms + j] += weight * p[i] * p[j];
        diagonal[hi][i * kTerms + j] += weight * q[i] * q[j];
        off[i * kTerms + j] -= weight * p[i] * q[j];
      }
      rhs[lo * kTerms + i] += weight * p[i] * d;
      rhs[hi * kTerms + i] -= weight * q[i] * d;
    }
  }

  // (N + diag(damping)) x = rhs by Eigen's conjugate gradients (diagonal preconditioner), from 0.
  // The system is semidefinite only in the offsets' common constant, which rhs does not excite.
  // A coefficient no equation or damping reaches gets 1 on the diagonal (and stays 0).
  std::vector<double> solve(const std::vector<double>& damping) const {
    const Eigen::Index size = static_cast<Eigen::Index>(rhs.size());
    std::vector<Eigen::Triplet<double>> t;
    for (std::size_t k = 0; k < diagonal.size(); ++k)
      for (int i = 0; i < kTerms; ++i)
        for (int j = 0; j < kTerms; ++j) {
          double v = diagonal[k][i * kTerms + j];
          if (i == j) v += damping[k * kTerms + i];
          if (i == j && v <= 0.0) v = 1.0;
          if (v != 0.0) t.emplace_back(k * kTerms + i, k * kTerms + j, v);
        }
    for (const auto& [ab, block] : pairs)
      for (int i = 0; i < kTerms; ++i)
        for (int j = 0; j < kTerms; ++j) {
          t.emplace_back(ab.first * kTerms + i, ab.second * kTerms + j, block[i * kTerms + j]);
          t.emplace_back(ab.second * kTerms + j, ab.first * kTerms + i, block[i * kTerms + j]);
        }
    Eigen::SparseMatrix<double> n(size, size);
    n.setFromTriplets(t.begin(), t.end());
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
    cg.setTolerance(1e-13);
    cg.setMaxIterations(10 * size + 100);
    cg.compute(n);
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(rhs.data(), size);
    const Eigen::VectorXd x = cg.solve(b);
    return {x.data(), x.data() + size};
  }
};

// The equation's residual: the fitted difference less the measured one.
double residual(const BackgroundEquation& e, const std::vector<double>& x) {
  double r = -e.difference;
  for (int i = 0; i < kTerms; ++i) r += e.basis_a[i] * x[e.a * kTerms + i] - e.basis_b[i] * x[e.b * kTerms + i];
  return r;
}

double median(std::vector<double>& v) {  // reorders v
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Huber's rule: the robust centre of the equations' residuals and their limit (kHuber robust
// spreads, 1.4826 x the median absolute deviation); a residual r weighs 1 within the limit of the
// centre, limit / |r - centre| beyond. Limit 0 when the spread is 0 (the differences fitted
// exactly: nothing to weight down). 8 bytes per equation while it runs.
std::pair<double, double> huber_limits(const BackgroundEquations& equations, const std::vector<double>& x) {
  std::vector<double> r;
  equations([&](const BackgroundEquation& e) { r.push_back(residual(e, x)); });
  if (r.empty()) return {0.0, 0.0};
  const double centre = median(r);
  for (double& v : r) v = std::abs(v - centre);
  return {centre, kHuber * 1.4826 * median(r)};
}

}  // namespace

std::array<double, 4> background_basis(double w, double h, double x, double y) {
  const double L = std::max(w, h);
  const double u = (x - w / 2) / L, v = (y - h / 2) / L;
  // The mean of u^2 + v^2 over the pixel centres (x + 1/2 for x = 0 .. w-1): ((w^2 - 1) + (h^2 - 1)) / (12 L^2).
  const double mean = (w * w - 1.0 + h * h - 1.0) / (12.0 * L * L);
  return {1.0, u, v, u * u + v * v - mean};
}

std::array<double, 4> background_basis(const Plate& plate, double x, double y) {
  return background_basis(plate.width, plate.height, x, y);
}

std::array<double, 4> background_energy(double width, double height) {
  const double L = std::max(width, height), a = width / (2.0 * L), b = height / (2.0 * L);
  // Over [-a, a] x [-b, b]: the mean of u^2 is a^2/3, the variance of u^2 + v^2 is 4 (a^4 + b^4) / 45.
  return {1.0, a * a / 3.0, b * b / 3.0, 4.0 * (a * a * a * a + b * b * b * b) / 45.0};
}

std::array<double, 4> background_energy(const Plate& plate) { return background_energy(plate.width, plate.height); }

std::vector<PlateBackground> fit_backgrounds(const std::vector<std::array<double, 4>>& energy,
                                             const BackgroundEquations& equations, double damping, bool robust) {
  const std::size_t count = energy.size();
  NormalEquations n(count);
  long long total = 0;
  equations([&](const BackgroundEquation& e) {
    n.add(e, 1.0);
    ++total;
  });
  // lambda: damping x the data's mean diagonal over the smooth terms, per unit of energy (of the
  // unweighted equations, so that the reweighting does not move it).
  double trace = 0.0, energies = 0.0;
  std::vector<char> linked(count, 0);
  for (std::size_t k = 0; k < count; ++k) {
    linked[k] = n.diagonal[k][0] > 0.0;
    for (int i = 1; i < kTerms && linked[k]; ++i) {
      trace += n.diagonal[k][i * (kTerms + 1)];
      energies += energy[k][i];
    }
  }
  const double lambda = energies > 0.0 ? damping * trace / energies : 0.0;
  std::vector<double> weights(count * kTerms, 0.0);
  for (std::size_t k = 0; k < count; ++k)
    for (int i = 1; i < kTerms; ++i) weights[k * kTerms + i] = lambda * energy[k][i];
  std::vector<double> x = n.solve(weights);
  // Stars, plate defects and other compact sources in the overlaps are outliers of the
  // differences: iteratively reweighted least squares with Huber's weights bounds their pull.
  for (int it = 0; it < kReweightings && robust && total > 0; ++it) {
    const auto [centre, limit] = huber_limits(equations, x);
    if (!(limit > 0.0)) break;
    NormalEquations weighted(count);
    equations([&](const BackgroundEquation& e) {
      const double deviation = std::abs(residual(e, x) - centre);
      weighted.add(e, deviation <= limit ? 1.0 : limit / deviation);
    });
    x = weighted.solve(weights);
  }
  std::vector<PlateBackground> out(count);
  double mean = 0.0;
  long long linked_count = 0;
  for (std::size_t k = 0; k < count; ++k) {
    out[k] = {x[k * kTerms], x[k * kTerms + 1], x[k * kTerms + 2], x[k * kTerms + 3]};
    if (linked[k]) {
      mean += out[k].offset;
      ++linked_count;
    }
  }
  for (std::size_t k = 0; k < count; ++k)
    if (linked[k]) out[k].offset -= mean / static_cast<double>(linked_count);
  return out;
}

BackgroundEquation background_equation(const Plate& a, int ia, const Plate& b, int ib, const OverlapSample& s) {
  return {ia, ib, background_basis(a, s.ax, s.ay), background_basis(b, s.bx, s.by), s.difference};
}

std::vector<PlateBackground> plate_backgrounds(const std::vector<Plate>& plates, double damping, bool robust) {
  std::vector<BackgroundEquation> equations;
  for (std::size_t a = 0; a < plates.size(); ++a)
    for (std::size_t b = a + 1; b < plates.size(); ++b)
      if (cones_meet(plates[a], plates[b]))
        for (const OverlapSample& s : overlap_samples(plates[a], plates[b]))
          equations.push_back(background_equation(plates[a], static_cast<int>(a), plates[b], static_cast<int>(b), s));
  std::vector<std::array<double, 4>> energy;
  for (const Plate& p : plates) energy.push_back(background_energy(p));
  return fit_backgrounds(
      energy, [&](const auto& visit) { for (const BackgroundEquation& e : equations) visit(e); }, damping, robust);
}

double smooth_rms(double width, double height, const PlateBackground& b) {
  const auto e = background_energy(width, height);
  return std::sqrt(e[1] * b.slope_u * b.slope_u + e[2] * b.slope_v * b.slope_v + e[3] * b.radial * b.radial);
}

double smooth_rms(const Plate& plate, const PlateBackground& b) { return smooth_rms(plate.width, plate.height, b); }

std::string backgrounds_note(const std::vector<std::string>& paths, const std::vector<double>& rms) {
  std::vector<std::size_t> order(rms.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rms[a] > rms[b]; });
  std::string largest;
  for (std::size_t k = 0; k < order.size() && k < 3; ++k)
    largest += fmt::format("{}{} {:.3g}", k ? ", " : "", std::filesystem::path(paths[order[k]]).filename().string(),
                           rms[order[k]]);
  const double middle = order.empty() ? 0.0 : rms[order[order.size() / 2]];
  return fmt::format("smooth backgrounds (plane + radial) fitted to the overlaps and taken off {} plate(s): rms over a "
                     "plate median {:.3g}, largest {} (each plate's fit: --verbose or --stats)",
                     rms.size(), middle, largest);
}

void subtract_smooth_background(Plate& p, const PlateBackground& m) {
  double sum = 0.0;
  long long finite = 0;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      float& v = p.pixels[static_cast<std::size_t>(y) * p.width + x];
      if (!std::isfinite(v)) continue;
      const auto f = background_basis(p, x + 0.5, y + 0.5);
      v = static_cast<float>(v - (m.slope_u * f[1] + m.slope_v * f[2] + m.radial * f[3]));
      sum += v;
      ++finite;
    }
  if (finite) p.mean = sum / static_cast<double>(finite);
}

}  // namespace gdp::sky
