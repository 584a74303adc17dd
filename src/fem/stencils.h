// Interior 1D stencils of the quadratic B-spline Galerkin discretisation (NUMERICS.md §2-3).
#pragma once

#include <array>

namespace gdp::fem {

// Mass matrix row, offsets -2..+2: integral of B_i B_{i+d}.
inline constexpr std::array<double, 5> kMass = {1.0 / 120, 13.0 / 60, 11.0 / 20, 13.0 / 60, 1.0 / 120};
// Stiffness matrix row, offsets -2..+2: integral of B_i' B_{i+d}'.
inline constexpr std::array<double, 5> kStiffness = {-1.0 / 6, -1.0 / 3, 1.0, -1.0 / 3, -1.0 / 6};
// Coupling of B_i' with the linear hat on edge e (between samples e and e+1), e = i-2..i+1.
inline constexpr std::array<double, 4> kDerivative = {1.0 / 6, 1.0 / 2, -1.0 / 2, -1.0 / 6};
// Two-scale relation: coarse j feeds fine 2j-1, 2j, 2j+1, 2j+2 with these weights.
inline constexpr std::array<double, 4> kRefine = {0.25, 0.75, 0.75, 0.25};

}  // namespace gdp::fem
