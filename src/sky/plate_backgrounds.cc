// Smooth plate backgrounds from the overlaps: block-sparse normal equations, damped smooth terms, preconditioned CG.
#include "sky/plate_backgrounds.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "sky/overlap_samples.h"

namespace gdp::sky {
namespace {

constexpr int kTerms = 4;
using Block = std::array<double, kTerms * kTerms>;

// The normal equations N x = rhs, x = the plates' coefficients one after another: diagonal
// blocks per plate, one off-diagonal block per pair (a < b; the (b, a) block is its transpose).
struct NormalEquations {
  std::vector<Block> diagonal;
  std::map<std::pair<int, int>, Block> pairs;
  std::vector<double> rhs;

  explicit NormalEquations(std::size_t count) : diagonal(count, Block{}), rhs(count * kTerms, 0.0) {}

  void add(const BackgroundEquation& e) {
    const bool swap = e.a > e.b;  // keep the pair's block as (min, max)
    const int lo = swap ? e.b : e.a, hi = swap ? e.a : e.b;
    const auto& p = swap ? e.basis_b : e.basis_a;  // basis of lo
    const auto& q = swap ? e.basis_a : e.basis_b;
    const double d = swap ? -e.difference : e.difference;  // lo's value minus hi's
    Block& off = pairs[{lo, hi}];
    for (int i = 0; i < kTerms; ++i) {
      for (int j = 0; j < kTerms; ++j) {
        diagonal[lo][i * kTerms + j] += p[i] * p[j];
        diagonal[hi][i * kTerms + j] += q[i] * q[j];
        off[i * kTerms + j] -= p[i] * q[j];
      }
      rhs[lo * kTerms + i] += p[i] * d;
      rhs[hi * kTerms + i] -= q[i] * d;
    }
  }

  // out = (N + diag(damping)) x.
  void apply(const std::vector<double>& x, const std::vector<double>& damping, std::vector<double>& out) const {
    std::fill(out.begin(), out.end(), 0.0);
    for (std::size_t k = 0; k < diagonal.size(); ++k)
      for (int i = 0; i < kTerms; ++i) {
        double s = damping[k * kTerms + i] * x[k * kTerms + i];
        for (int j = 0; j < kTerms; ++j) s += diagonal[k][i * kTerms + j] * x[k * kTerms + j];
        out[k * kTerms + i] += s;
      }
    for (const auto& [ab, block] : pairs)
      for (int i = 0; i < kTerms; ++i)
        for (int j = 0; j < kTerms; ++j) {
          out[ab.first * kTerms + i] += block[i * kTerms + j] * x[ab.second * kTerms + j];
          out[ab.second * kTerms + j] += block[i * kTerms + j] * x[ab.first * kTerms + i];
        }
  }
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) s += a[k] * b[k];
  return s;
}

// Conjugate gradients preconditioned by the diagonal, from 0. The system is semidefinite only in
// the offsets' common constant, which the right-hand side does not excite.
std::vector<double> solve(const NormalEquations& n, const std::vector<double>& damping) {
  const std::size_t size = n.rhs.size();
  std::vector<double> inverse(size, 0.0);
  for (std::size_t k = 0; k < size; ++k) {
    const double d = n.diagonal[k / kTerms][(k % kTerms) * (kTerms + 1)] + damping[k];
    inverse[k] = d > 0.0 ? 1.0 / d : 0.0;
  }
  std::vector<double> x(size, 0.0), r = n.rhs, z(size), p(size), q(size);
  for (std::size_t k = 0; k < size; ++k) z[k] = inverse[k] * r[k];
  p = z;
  double rz = dot(r, z);
  const double stop = dot(r, r) * 1e-26;
  for (std::size_t it = 0; it < 10 * size + 100 && dot(r, r) > stop && rz > 0.0; ++it) {
    n.apply(p, damping, q);
    const double pq = dot(p, q);
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    for (std::size_t k = 0; k < size; ++k) {
      x[k] += alpha * p[k];
      r[k] -= alpha * q[k];
      z[k] = inverse[k] * r[k];
    }
    const double next = dot(r, z);
    for (std::size_t k = 0; k < size; ++k) p[k] = z[k] + next / rz * p[k];
    rz = next;
  }
  return x;
}

}  // namespace

std::array<double, 4> background_basis(const Plate& plate, double x, double y) {
  const double w = plate.width, h = plate.height, L = std::max(w, h);
  const double u = (x - w / 2) / L, v = (y - h / 2) / L;
  // The mean of u^2 + v^2 over the pixel centres (x + 1/2 for x = 0 .. w-1): ((w^2 - 1) + (h^2 - 1)) / (12 L^2).
  const double mean = (w * w - 1.0 + h * h - 1.0) / (12.0 * L * L);
  return {1.0, u, v, u * u + v * v - mean};
}

std::array<double, 4> background_energy(const Plate& plate) {
  const double L = std::max(plate.width, plate.height), a = plate.width / (2.0 * L), b = plate.height / (2.0 * L);
  // Over [-a, a] x [-b, b]: the mean of u^2 is a^2/3, the variance of u^2 + v^2 is 4 (a^4 + b^4) / 45.
  return {1.0, a * a / 3.0, b * b / 3.0, 4.0 * (a * a * a * a + b * b * b * b) / 45.0};
}

std::vector<PlateBackground> fit_backgrounds(const std::vector<std::array<double, 4>>& energy,
                                             const std::vector<BackgroundEquation>& equations, double damping) {
  const std::size_t count = energy.size();
  NormalEquations n(count);
  for (const BackgroundEquation& e : equations) n.add(e);
  // lambda: damping x the data's mean diagonal over the smooth terms, per unit of energy.
  double trace = 0.0, energies = 0.0;
  for (std::size_t k = 0; k < count; ++k)
    for (int i = 1; i < kTerms; ++i)
      if (n.diagonal[k][0] > 0.0) {
        trace += n.diagonal[k][i * (kTerms + 1)];
        energies += energy[k][i];
      }
  const double lambda = energies > 0.0 ? damping * trace / energies : 0.0;
  std::vector<double> weights(count * kTerms, 0.0);
  for (std::size_t k = 0; k < count; ++k)
    for (int i = 1; i < kTerms; ++i) weights[k * kTerms + i] = lambda * energy[k][i];
  const std::vector<double> x = solve(n, weights);
  std::vector<PlateBackground> out(count);
  double mean = 0.0;
  long long linked = 0;
  for (std::size_t k = 0; k < count; ++k) {
    out[k] = {x[k * kTerms], x[k * kTerms + 1], x[k * kTerms + 2], x[k * kTerms + 3]};
    if (n.diagonal[k][0] > 0.0) {
      mean += out[k].offset;
      ++linked;
    }
  }
  for (std::size_t k = 0; k < count; ++k)
    if (n.diagonal[k][0] > 0.0) out[k].offset -= mean / static_cast<double>(linked);
  return out;
}

std::vector<PlateBackground> plate_backgrounds(const std::vector<Plate>& plates, double damping) {
  std::vector<BackgroundEquation> equations;
  for (std::size_t a = 0; a < plates.size(); ++a)
    for (std::size_t b = a + 1; b < plates.size(); ++b) {
      if (!cones_meet(plates[a], plates[b])) continue;
      for (const OverlapSample& s : overlap_samples(plates[a], plates[b]))
        equations.push_back({static_cast<int>(a), static_cast<int>(b), background_basis(plates[a], s.ax, s.ay),
                             background_basis(plates[b], s.bx, s.by), s.difference});
    }
  std::vector<std::array<double, 4>> energy;
  for (const Plate& p : plates) energy.push_back(background_energy(p));
  return fit_backgrounds(energy, equations, damping);
}

void subtract_smooth_backgrounds(std::vector<Plate>& plates, const std::vector<PlateBackground>& backgrounds) {
  for (std::size_t k = 0; k < plates.size(); ++k) {
    Plate& p = plates[k];
    const PlateBackground& m = backgrounds[k];
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
}

}  // namespace gdp::sky
