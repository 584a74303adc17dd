// Conjugate gradients in double precision for the coarsest multigrid level (and any operator given as a function).
#pragma once

#include <functional>
#include <span>

#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"

namespace gdp::multigrid {

// out = A in, for a symmetric positive (semi)definite A on vectors of doubles.
using ApplyOperator = std::function<void(std::span<const double> in, std::span<double> out)>;

// Solves A u = b to a relative residual `tolerance`, improving u in place. With `singular`, the
// constants (A's null space) are projected out of b, u and the residuals. Returns the number of
// iterations.
int conjugate_gradients(const ApplyOperator& apply, bool singular, std::span<const double> b, std::span<double> u,
                        double tolerance, int max_iterations);

// The same on one level (singular when alpha == 0).
int solve_cg(const LevelOperator<double>& op, bool singular, const Plane<double>& b, Plane<double>& u,
             double tolerance, int max_iterations);

}  // namespace gdp::multigrid
