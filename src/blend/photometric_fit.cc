// Exposure and vignetting fitted to overlap samples: Gauss-Newton with the scene eliminated, Huber weights.
#include "blend/photometric_fit.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "gdp/errors.h"

namespace gdp::blending {
namespace {

// Parameters: gains g_k, offsets o_kc, vignetting a_j, in one vector.
struct Model {
  int K = 0, C = 0, J = 0;
  std::vector<double> p;
  int g(int k) const { return k; }
  int o(int k, int c) const { return K + k * C + c; }
  int a(int j) const { return K + K * C + j; }
  int size() const { return K + K * C + J; }
  std::vector<double> vignetting() const { return {p.begin() + a(0), p.end()}; }
};

// The normal equations of the reduced problem (the scene eliminated), P x P.
struct Normal {
  int P = 0;
  std::vector<double> A, b;
};

struct Entry {
  int i;
  double v;
};

// Robust residuals: one per observation and channel, with its weight (0: clipped, never used).
struct Residuals {
  std::vector<float> r, w;
  double count = 0.0;
};

// f(i, w, observation i) for the observations [b, e) whose channel c is not clipped (w <= 0).
template <class F>
void each_weighted(const OverlapSamples& s, const Residuals& res, int C, std::uint32_t b, std::uint32_t e, int c, F&& f) {
  for (std::uint32_t i = b; i < e; ++i) {
    const double w = res.w[i * C + c];
    if (w <= 0.0) continue;
    f(i, w, s.obs[i]);
  }
}

// One point's channel c: the scene value given the model, the weighted residuals, and (with
// `n`) its contribution to the reduced normal equations. Returns the weighted squared residuals.
double cell(const OverlapSamples& s, const Model& m, const std::vector<double>& v, std::uint32_t b, std::uint32_t e,
            int c, Residuals& res, Normal* n, std::vector<Entry>& coupling) {
  double D = 0.0, num = 0.0;
  int used = 0;
  each_weighted(s, res, m.C, b, e, c, [&](std::uint32_t i, double w, const OverlapObservation& q) {
    const double G = m.p[m.g(q.layer)] * v[i];
    D += w * G * G;
    num += w * G * (q.value[c] - m.p[m.o(q.layer, c)]);
    ++used;
  });
  if (used < 2 || D <= 0.0) return 0.0;
  const double S = num / D;
  double cost = 0.0, gS = 0.0;
  coupling.clear();
  Entry J[2 + 3];
  each_weighted(s, res, m.C, b, e, c, [&](std::uint32_t i, double w, const OverlapObservation& q) {
    const double g = m.p[m.g(q.layer)], G = g * v[i];
    const double r = G * S + m.p[m.o(q.layer, c)] - q.value[c];
    res.r[i * m.C + c] = static_cast<float>(r);
    cost += w * r * r;
    if (!n) return;
    int k = 0;
    J[k++] = {m.g(q.layer), v[i] * S};
    J[k++] = {m.o(q.layer, c), 1.0};
    double tj = 1.0;
    for (int j = 0; j < m.J; ++j) J[k++] = {m.a(j), g * S * (tj *= q.t)};
    for (int x = 0; x < k; ++x) {
      n->b[J[x].i] += w * J[x].v * r;
      for (int y = 0; y < k; ++y) n->A[static_cast<std::size_t>(J[x].i) * n->P + J[y].i] += w * J[x].v * J[y].v;
      coupling.push_back({J[x].i, w * G * J[x].v});
    }
    gS += w * G * r;
  });
  if (n)  // Schur complement of the scene value: A -= b b^T / D, rhs -= b gS / D
    for (const Entry& x : coupling) {
      n->b[x.i] -= x.v * gS / D;
      for (const Entry& y : coupling) n->A[static_cast<std::size_t>(x.i) * n->P + y.i] -= x.v * y.v / D;
    }
  return cost;
}

// Every point and channel: the data term's cost (and normal equations with `n`).
double sweep(const OverlapSamples& s, const Model& m, Residuals& res, Normal* n) {
  std::vector<double> v(s.obs.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = vignetting_gain(m.vignetting(), s.obs[i].t);
  std::vector<Entry> coupling;
  double cost = 0.0;
  for (int p = 0; p < s.points(); ++p)
    for (int c = 0; c < m.C; ++c) cost += cell(s, m, v, s.start[p], s.start[p + 1], c, res, n, coupling);
  return cost;
}

// 1.4826 x the median absolute residual of the usable observations.
double robust_sigma(const Residuals& res) {
  std::vector<float> a;
  a.reserve(res.r.size());
  for (std::size_t i = 0; i < res.r.size(); ++i)
    if (res.w[i] > 0.0f) a.push_back(std::fabs(res.r[i]));
  if (a.empty()) return 0.0;
  std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
  return 1.4826 * a[a.size() / 2];
}

// The priors: gains' mean 1 and each channel's offsets summing to 0 (the gauge, strong), ridges
// on each gain's distance from 1 and on the vignetting coefficients (weak). Adds to `n` when given.
double priors(const Model& m, const PhotometricFit& f, double count, Normal* n) {
  const double gauge = count, ridge_g = f.gain_prior * count / m.K, ridge_o = 1e-6 * count / m.K,
               ridge_a = f.vignetting_prior * count;
  double cost = 0.0;
  const auto term = [&](const std::vector<Entry>& lin, double value, double weight) {
    cost += weight * value * value;
    if (!n) return;
    for (const Entry& x : lin) {
      n->b[x.i] += weight * x.v * value;
      for (const Entry& y : lin) n->A[static_cast<std::size_t>(x.i) * n->P + y.i] += weight * x.v * y.v;
    }
  };
  std::vector<Entry> mean;
  double sum = 0.0;
  for (int k = 0; k < m.K; ++k) mean.push_back({m.g(k), 1.0 / m.K}), sum += m.p[m.g(k)] / m.K;
  term(mean, sum - 1.0, gauge);
  for (int c = 0; c < m.C; ++c) {
    std::vector<Entry> lin;
    double total = 0.0;
    for (int k = 0; k < m.K; ++k) lin.push_back({m.o(k, c), 1.0 / m.K}), total += m.p[m.o(k, c)] / m.K;
    term(lin, total, gauge);
  }
  for (int k = 0; k < m.K; ++k) {
    term({{m.g(k), 1.0}}, m.p[m.g(k)] - 1.0, ridge_g);
    for (int c = 0; c < m.C; ++c) term({{m.o(k, c), 1.0}}, m.p[m.o(k, c)], ridge_o);
  }
  for (int j = 0; j < m.J; ++j) term({{m.a(j), 1.0}}, m.p[m.a(j)], ridge_a);
  return cost;
}

// Solves A x = b, A symmetric positive definite (the priors make it so: every parameter has a
// ridge); Eigen's Cholesky, refused with a clear error when rounding leaves A indefinite.
std::vector<double> solve_spd(const Normal& n) {
  const Eigen::Map<const Eigen::MatrixXd> A(n.A.data(), n.P, n.P);
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success)
    throw Error(fmt::format("--photometric: the normal equations of the exposure and vignetting fit ({} unknowns) "
                            "are not positive definite", n.P));
  std::vector<double> x(n.P);
  Eigen::Map<Eigen::VectorXd>(x.data(), n.P) = llt.solve(Eigen::Map<const Eigen::VectorXd>(n.b.data(), n.P));
  return x;
}

// Huber weights (1 within 1.5 sigma, then falling as 1/|r|) on the usable observations.
void reweight(Residuals& res) {
  const double k = 1.5 * robust_sigma(res);
  for (std::size_t i = 0; i < res.r.size(); ++i)
    if (res.w[i] > 0.0f) {
      const double a = std::fabs(res.r[i]);
      res.w[i] = static_cast<float>(a <= k || k <= 0.0 ? 1.0 : std::max(k / a, 1e-3));
    }
}

}  // namespace

double vignetting_gain(const std::vector<double>& a, double t) {
  double v = 1.0, tj = 1.0;
  for (const double c : a) v += c * (tj *= t);
  return std::max(v, 0.05);
}

PhotometricResult fit_photometry(const OverlapSamples& s, int terms, const PhotometricFit& f) {
  Model m;
  m.K = s.layers;
  m.C = s.channels;
  m.J = terms;
  m.p.assign(m.size(), 0.0);
  for (int k = 0; k < m.K; ++k) m.p[m.g(k)] = 1.0;
  Residuals res;
  res.r.assign(s.obs.size() * m.C, 0.0f);
  res.w.assign(s.obs.size() * m.C, 0.0f);
  for (std::size_t i = 0; i < s.obs.size(); ++i)
    for (int c = 0; c < m.C; ++c) {
      const float v = s.obs[i].value[c];
      res.w[i * m.C + c] = v > f.low && v < f.high ? 1.0f : 0.0f;
      res.count += res.w[i * m.C + c];
    }
  PhotometricResult out;
  sweep(s, m, res, nullptr);
  out.rms_before = robust_sigma(res);
  for (int it = 0; it < f.iterations && res.count > 0; ++it) {
    reweight(res);
    Normal n;
    n.P = m.size();
    n.A.assign(static_cast<std::size_t>(n.P) * n.P, 0.0);
    n.b.assign(n.P, 0.0);
    const double cost = sweep(s, m, res, &n) + priors(m, f, res.count, &n);
    std::vector<double> step = solve_spd(n);
    double largest = 0.0;
    for (double& x : step) x = -x, largest = std::max(largest, std::fabs(x));
    Model next = m;
    for (double alpha = 1.0; alpha > 1.0 / 64; alpha /= 2) {  // halve the step until the cost falls
      for (int i = 0; i < n.P; ++i) next.p[i] = m.p[i] + alpha * step[i];
      Residuals trial = res;
      if (sweep(s, next, trial, nullptr) + priors(next, f, res.count, nullptr) <= cost) {
        m = std::move(next);
        res = std::move(trial);
        break;
      }
      largest *= 0.5;
    }
    if (largest < f.converged) break;
  }
  sweep(s, m, res, nullptr);
  out.rms_after = robust_sigma(res);
  out.vignetting = m.vignetting();
  out.gains.assign(m.p.begin(), m.p.begin() + m.K);
  out.offsets.assign(m.p.begin() + m.K, m.p.begin() + m.K + m.K * m.C);
  return out;
}

}  // namespace gdp::blending
