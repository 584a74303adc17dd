// Multigrid V-cycles for the intrinsic equirectangular operator: the baseline of the paper's section 4.5.
#pragma once

#include <span>
#include <vector>

#include "sphere_eval/equirect_operator.h"

namespace gdp::sphere_eval {

struct EquirectSolverOptions {
  int sweeps = 3;                   // lexicographic Gauss-Seidel sweeps before restriction and after prolongation
  int coarsest_height = 32;         // halve W and H while H is even and above this (W <= 64 by default)
  double coarse_tolerance = 1e-10;  // relative residual of the coarsest-level conjugate gradients
  int max_coarse_iterations = 100000;
};

// Conjugate gradients on one level to a relative residual `tolerance`. With α = 0 the constants
// are projected out of b and of u. Returns the number of iterations.
int solve_cg(const EquirectOperator& op, std::span<const double> b, std::span<double> u, double tolerance,
             int max_iterations);

// The V-cycle has the shape of gdp's planar solver (docs/multigrid.md): the same grid is rediscretised
// at every level (W and H halve; coarse cells are unions of 2x2 fine cells), prolongation is the
// cell-centred two-scale relation (1/4, 3/4, 3/4, 1/4) per axis, periodic in longitude and
// reflected at the poles, restriction is its transpose, the coarsest level is solved by CG.
class EquirectSolver {
 public:
  // Throws UsageError for a grid EquirectOperator::make rejects or invalid options.
  EquirectSolver(int width, int height, double alpha, const EquirectSolverOptions& options = {});

  int levels() const { return static_cast<int>(ops_.size()); }
  const EquirectOperator& op(int level = 0) const { return ops_[level]; }

  // One V-cycle on the finest level, improving u in place.
  void vcycle(std::span<double> u, std::span<const double> b) const;

  // |b - L u| / |b| on the finest level (|L u| when b = 0).
  double relative_residual(std::span<const double> u, std::span<const double> b) const;

 private:
  void cycle(int level, std::span<double> u, std::span<const double> b) const;
  void relax(const EquirectOperator& op, std::span<double> u, std::span<const double> b) const;

  EquirectSolverOptions options_;
  std::vector<EquirectOperator> ops_;
};

// Coarse to fine: fine += P coarse, and its transpose, coarse += Pᵀ fine. The fine grid is 2Wc x 2Hc.
void prolong_add(int coarse_width, int coarse_height, std::span<const double> coarse, std::span<double> fine);
void restrict_add(int coarse_width, int coarse_height, std::span<const double> fine, std::span<double> coarse);

}  // namespace gdp::sphere_eval
