// In-core V-cycle: pre-smooth, restrict, recurse, coarse CG, prolong, post-smooth.
#include "multigrid/incore_vcycle.h"

#include <algorithm>
#include <cmath>

#include "multigrid/coarse_cg.h"
#include "multigrid/plane_ops.h"

namespace gdp::multigrid {

template <class T>
Operators<T>::Operators(const Hierarchy& h)
    : hierarchy(&h), coarsest(h.levels.back(), h.alpha), singular(h.alpha == 0.0) {
  for (const LevelGeometry& g : h.levels) levels.emplace_back(g, h.alpha);
}

template <class T>
InCoreVCycle<T>::InCoreVCycle(const Operators<T>& ops, int sweeps, double coarse_tolerance)
    : ops_(ops), sweeps_(sweeps), coarse_tolerance_(coarse_tolerance), scratch_(ops.levels[0].width) {
  for (std::size_t l = 0; l < ops.levels.size(); ++l) {
    const LevelOperator<T>& op = ops.levels[l];
    if (l > 0) {
      u_.emplace_back(op.width, op.height);
      b_.emplace_back(op.width, op.height);
    }
  }
  tmp_.resize(ops.levels[0].width);
  r_row_.resize(ops.levels[0].width);
}

template <class T>
void InCoreVCycle<T>::run(Plane<T>& u0, const Plane<T>& b0, std::vector<double>* level_residuals) {
  const std::vector<LevelGeometry>& geo = ops_.hierarchy->levels;
  const int levels = static_cast<int>(geo.size());
  auto U = [&](int l) -> Plane<T>& { return l == 0 ? u0 : u_[l - 1]; };
  auto B = [&](int l) -> const Plane<T>& { return l == 0 ? b0 : b_[l - 1]; };

  for (int l = 0; l + 1 < levels; ++l) {
    const LevelOperator<T>& op = ops_.levels[l];
    relax(op, U(l), B(l), sweeps_, scratch_);
    Plane<T>& coarse_b = b_[l];
    std::fill(coarse_b.data.begin(), coarse_b.data.end(), T(0));
    std::fill(u_[l].data.begin(), u_[l].data.end(), T(0));
    const LevelGeometry& g = geo[l + 1];
    double rr = 0.0;
    for (int j = 0; j < op.height; ++j) {
      residual_row(op, j, window(op, U(l), j), B(l).row(j), r_row_.data(), scratch_);
      for (int i = 0; i < op.width; ++i) rr += static_cast<double>(r_row_[i]) * r_row_[i];
      const fem::ProlongationRow& py = g.py.rows[j];
      restrict_row(g.px, py, r_row_.data(), coarse_b.row(py.index[0]), coarse_b.row(py.index[1]),
                   tmp_.data());
    }
    if (level_residuals) level_residuals->push_back(std::sqrt(rr));
  }

  {  // Coarsest level: conjugate gradients in double precision.
    const LevelOperator<double>& op = ops_.coarsest;
    Plane<double> b(op.width, op.height), u(op.width, op.height);
    std::copy(B(levels - 1).data.begin(), B(levels - 1).data.end(), b.data.begin());
    std::copy(U(levels - 1).data.begin(), U(levels - 1).data.end(), u.data.begin());
    solve_cg(op, ops_.singular, b, u, coarse_tolerance_, 20 * (op.width + op.height) + 100);
    if (level_residuals) {
      Plane<double> r(op.width, op.height);
      RowScratch<double> s(op.width);
      residual(op, u, b, r, s);
      level_residuals->push_back(norm2(r));
    }
    std::transform(u.data.begin(), u.data.end(), U(levels - 1).data.begin(),
                   [](double v) { return static_cast<T>(v); });
  }

  for (int l = levels - 2; l >= 0; --l) {
    const LevelOperator<T>& op = ops_.levels[l];
    const LevelGeometry& g = geo[l + 1];
    const Plane<T>& coarse = U(l + 1);
    for (int j = 0; j < op.height; ++j) {
      const fem::ProlongationRow& py = g.py.rows[j];
      prolong_row(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), U(l).row(j), tmp_.data());
    }
    relax(op, U(l), B(l), sweeps_, scratch_);
  }
}

template <class T>
double InCoreVCycle<T>::residual_norm(const Plane<T>& u, const Plane<T>& b) {
  const LevelOperator<T>& op = ops_.levels[0];
  double rr = 0.0;
  for (int j = 0; j < op.height; ++j) {
    residual_row(op, j, window(op, u, j), b.row(j), r_row_.data(), scratch_);
    for (int i = 0; i < op.width; ++i) rr += static_cast<double>(r_row_[i]) * r_row_[i];
  }
  return std::sqrt(rr);
}

template struct Operators<float>;
template struct Operators<double>;
template class InCoreVCycle<float>;
template class InCoreVCycle<double>;

}  // namespace gdp::multigrid
