// Conjugate gradients in double precision for the coarsest multigrid level (and any operator given as a function).
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"

namespace gdp::multigrid {

// out = A in, for a symmetric positive (semi)definite A on vectors of doubles.
using ApplyOperator = std::function<void(std::span<const double> in, std::span<double> out)>;

// Solves A u = b to a relative residual `tolerance`, improving u in place. With `singular`, the
// constants (A's null space) are projected out of b, u and the residuals. A non-empty
// `inverse_diagonal` makes it Jacobi-preconditioned (for operators whose diagonal varies over
// orders of magnitude, as with pinned pixels). Returns the number of iterations.
int conjugate_gradients(const ApplyOperator& apply, bool singular, std::span<const double> b, std::span<double> u,
                        double tolerance, int max_iterations, std::span<const double> inverse_diagonal = {});

// The reciprocal diagonal of A + diag on one level (the Jacobi preconditioner solve_cg uses
// with a diagonal term), exact where a mirrored row couples a pixel to itself.
std::vector<double> inverse_diagonal(const LevelOperator<double>& op, const Plane<double>& diag);

// The same on one level (singular when alpha == 0 and there is no diagonal term), with the
// optional per-pixel diagonal term of window_ops.h, then preconditioned with `inverse` (computed
// here when empty: callers solving many times pass inverse_diagonal()'s once).
int solve_cg(const LevelOperator<double>& op, bool singular, const Plane<double>& b, Plane<double>& u,
             double tolerance, int max_iterations, const Plane<double>* diag = nullptr,
             std::span<const double> inverse = {});

}  // namespace gdp::multigrid
