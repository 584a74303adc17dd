// What a streamed solve's workers share: the problem set-up, the mean rule, residual bookkeeping.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gdp/guidance.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "topology/topology.h"

namespace gdp::schedule {

// The hierarchy and operators of a source's problem (not movable: ops points at hierarchy).
template <class T>
struct Problem {
  std::unique_ptr<topology::Topology> topology;
  multigrid::Hierarchy hierarchy;
  multigrid::Operators<T> ops;
  Problem(const GuidanceSource& source, const SolverOptions& options, SolveSummary& summary);
  Problem(const Problem&) = delete;
};

// The first level (>= 1) whose planes, u and b for every channel, fit in `bytes`: the first that
// streaming schedules hold whole (and solve in-core).
template <class T>
int first_whole_level(const multigrid::Operators<T>& ops, int channels, std::size_t bytes) {
  for (int l = 1; l < ops.count(); ++l) {
    const auto& op = ops.levels[l];
    if (2.0 * channels * op.width * static_cast<double>(op.height) * sizeof(T) <= static_cast<double>(bytes)) return l;
  }
  return ops.count() - 1;
}

// With alpha == 0, the constant added to a channel's result after a V-cycle so that its
// weighted mean is the starting guess's: (target sum - predicted sum) / total weight, the
// prediction being the sum of the cycle's per-level dots (multigrid::CycleProbe).
double mean_shift(bool singular, double target_sum, double weight_total, const std::vector<double>& dots);
// Adds `shift` (mean_shift's) to every value, in double.
template <class T>
void shift_mean(std::span<T> values, double shift) {
  if (shift != 0.0)
    for (T& v : values) v = static_cast<T>(static_cast<double>(v) + shift);
}

// Relative residuals and per-cycle log lines of every channel, turned into the summary.
class ResidualLog {
 public:
  ResidualLog(int channels, bool keep_lines);
  void set_rhs_norm(int c, double norm) { b_norm_[c] = norm; }
  void initial(int c, double norm);
  void cycle(int c, double norm, const multigrid::CycleProbe& probe);
  // Iterating to `tolerance` (> 0): channel c is there, or stalled: its last kStallCycles V-cycles
  // did not bring its residual 10 % below the best before them (the floor of the arithmetic: a
  // float solve of smooth data stalls near 1e-5, docs/sky.md; more cycles would only repeat it).
  bool settled(int c, double tolerance) const;
  static constexpr int kStallCycles = 3;
  // Worst channel per cycle into the summary (none where options do not measure residuals); log
  // lines (channel by channel) to options.log.
  void finish(SolveSummary& summary, const SolverOptions& options) const;
  // Checkpoints: channels c0 .. c0 + n - 1 (one lane's) to a ByteWriter or from a ByteReader.
  template <class Archive>
  void state(Archive& archive, int c0, int n);

 private:
  double relative(int c, double r) const { return b_norm_[c] > 0.0 ? r / b_norm_[c] : r; }
  bool keep_lines_;
  std::vector<double> b_norm_;
  std::vector<std::vector<double>> rel_;
  std::vector<std::vector<std::string>> lines_;
};

}  // namespace gdp::schedule
