// Solving the screened Poisson equation for every channel of a guidance source.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gdp/guidance.h"
#include "gdp/image.h"
#include "gdp/topology.h"

namespace gdp {

enum class Precision { Float32, Float64 };

struct SolverOptions {
  Domain domain = Domain::Planar;
  int sweeps = 3;             // Gauss-Seidel sweeps before restriction and after prolongation
                              // (3 meets the stitching accuracy target with margin: docs/reproduce.md)
  int vcycles = 1;            // V-cycles to run (when tolerance == 0)
  double tolerance = 0.0;     // > 0: run V-cycles until the relative residual is below this
  int max_vcycles = 100;      // cap when iterating to a tolerance
  int coarsest_size = 64;     // coarsen until no side exceeds this, then conjugate gradients
  double coarse_tolerance = 1e-10;  // relative residual of the coarsest-level CG solve
  Precision precision = Precision::Float32;
  int threads = 1;            // channels are solved concurrently on up to this many threads
  // Receives one line per level and V-cycle with residual norms (the CLI's --verbose).
  std::function<void(const std::string&)> log;
  // Receives the fraction of work done, from 0 to 1.
  std::function<void(double)> progress;

  // Throws UsageError describing the first invalid option.
  void validate() const;
};

struct SolveSummary {
  int width = 0, height = 0, channels = 0, levels = 0, vcycles = 0;
  std::vector<int> level_widths, level_heights;
  // Relative residual |b - A u| / |b| (worst channel) before the first V-cycle and after each.
  std::vector<double> relative_residuals;
  double seconds_rhs = 0.0, seconds_solve = 0.0;
};

// Solves for every channel of the source. `initial` (optional, same size and channels) is the
// starting guess; zero otherwise. The result is defined up to a constant per channel when
// alpha == 0: it keeps the initial guess's mean (zero mean when there is none).
Image solve(GuidanceSource& source, const SolverOptions& options, const Image* initial = nullptr,
            SolveSummary* summary = nullptr);

}  // namespace gdp
