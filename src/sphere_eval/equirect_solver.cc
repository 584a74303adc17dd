// Multigrid V-cycles and conjugate gradients for the intrinsic equirectangular operator.
#include "sphere_eval/equirect_solver.h"

#include <cmath>
#include <numeric>
#include <utility>

#include "gdp/errors.h"
#include "multigrid/coarse_cg.h"

namespace gdp::sphere_eval {

namespace {

double dot(std::span<const double> a, std::span<const double> b) {
  return std::inner_product(a.begin(), a.end(), b.begin(), 0.0);
}

}  // namespace

int solve_cg(const RowStencilOperator& op, std::span<const double> b, std::span<double> u, double tolerance,
             int max_iterations) {
  const auto apply = [&](std::span<const double> in, std::span<double> out) { op.apply(in, out); };
  return multigrid::conjugate_gradients(apply, op.singular(), b, u, tolerance, max_iterations);
}

EquirectSolver::EquirectSolver(int width, int height, double alpha, const EquirectSolverOptions& options)
    : EquirectSolver(EquirectOperator::make(width, height, alpha), options) {}

EquirectSolver::EquirectSolver(EquirectOperator fine, const EquirectSolverOptions& options)
    : options_(options), fine_(std::move(fine)) {
  if (options.sweeps < 0 || options.coarsest_height < 1 || !(options.coarse_tolerance > 0.0))
    throw UsageError("equirectangular solver: sweeps >= 0, coarsest height >= 1 and a positive tolerance needed");
  levels_.push_back(RowStencilOperator::from(fine_));
  // A coarse level needs W >= 5 (RowStencilOperator::galerkin), i.e. H >= 3.
  while (levels_.back().height() % 2 == 0 && levels_.back().height() > options.coarsest_height &&
         levels_.back().height() >= 6)
    levels_.push_back(RowStencilOperator::galerkin(levels_.back()));
}

void EquirectSolver::cycle(int level, std::span<double> u, std::span<const double> b) const {
  const RowStencilOperator& op = levels_[level];
  if (level + 1 == levels()) {
    solve_cg(op, b, u, options_.coarse_tolerance, options_.max_coarse_iterations);
    return;
  }
  op.relax(u, b, options_.sweeps);
  std::vector<double> r(op.size());
  op.apply(u, r);
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = b[k] - r[k];
  const RowStencilOperator& coarse = levels_[level + 1];
  std::vector<double> bc(coarse.size(), 0.0), uc(coarse.size(), 0.0);
  restrict_add(coarse.width(), coarse.height(), r, bc);
  cycle(level + 1, uc, bc);
  prolong_add(coarse.width(), coarse.height(), uc, u);
  op.relax(u, b, options_.sweeps);
}

void EquirectSolver::vcycle(std::span<double> u, std::span<const double> b) const { cycle(0, u, b); }

double EquirectSolver::relative_residual(std::span<const double> u, std::span<const double> b) const {
  std::vector<double> r(levels_[0].size());
  levels_[0].apply(u, r);
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = b[k] - r[k];
  const double bb = dot(b, b);
  return std::sqrt(dot(r, r) / (bb > 0.0 ? bb : 1.0));
}

}  // namespace gdp::sphere_eval
