// Conjugate gradients in double precision for the coarsest multigrid level.
#pragma once

#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"

namespace gdp::multigrid {

// Solves A u = b on one level to a relative residual `tolerance`. With alpha == 0 the
// operator's null space (the constants) is projected out of b and of u.
// Returns the number of iterations.
int solve_cg(const LevelOperator<double>& op, bool singular, const Plane<double>& b, Plane<double>& u,
             double tolerance, int max_iterations);

}  // namespace gdp::multigrid
