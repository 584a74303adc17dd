// Multigrid V-cycles for the intrinsic equirectangular operator: the baseline of the paper's section 4.5.
#pragma once

#include <span>
#include <vector>

#include "sphere_eval/equirect_operator.h"
#include "sphere_eval/row_stencil.h"

namespace gdp::sphere_eval {

struct EquirectSolverOptions {
  int sweeps = 3;                   // lexicographic Gauss-Seidel sweeps before restriction and after prolongation
  int coarsest_height = 32;         // halve W and H while H is even and above this (W <= 64 by default)
  double coarse_tolerance = 1e-10;  // relative residual of the coarsest-level conjugate gradients
  int max_coarse_iterations = 100000;
};

// Conjugate gradients to a relative residual `tolerance` (multigrid::conjugate_gradients). On a
// singular operator the constants are projected out of b and of u. Returns the number of iterations.
int solve_cg(const RowStencilOperator& op, std::span<const double> b, std::span<double> u, double tolerance,
             int max_iterations);

// The V-cycle has the shape of gdp's planar solver (docs/multigrid.md): W and H halve from level
// to level, prolongation is the cell-centred two-scale relation (prolong_add), restriction its
// transpose, coarse operators are Galerkin products Pᵀ L P, k Gauss-Seidel sweeps before
// restricting and after prolonging, conjugate gradients on the coarsest level.
class EquirectSolver {
 public:
  // Throws UsageError for a grid EquirectOperator::make rejects or invalid options.
  EquirectSolver(int width, int height, double alpha, const EquirectSolverOptions& options = {});
  // The same cycle for a given finest operator (bench/sphere_table1's control with a flat metric).
  explicit EquirectSolver(EquirectOperator fine, const EquirectSolverOptions& options = {});

  const EquirectOperator& fine() const { return fine_; }
  int levels() const { return static_cast<int>(levels_.size()); }
  const RowStencilOperator& level(int l) const { return levels_[l]; }

  // One V-cycle on the finest level, improving u in place.
  void vcycle(std::span<double> u, std::span<const double> b) const;

  // |b - L u| / |b| on the finest level (|L u| when b = 0).
  double relative_residual(std::span<const double> u, std::span<const double> b) const;

 private:
  void cycle(int level, std::span<double> u, std::span<const double> b) const;

  EquirectSolverOptions options_;
  EquirectOperator fine_;
  std::vector<RowStencilOperator> levels_;
};

}  // namespace gdp::sphere_eval
