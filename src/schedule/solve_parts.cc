// Shared solve pieces: problem set-up, the mean shift, residual logs.
#include "schedule/solve_parts.h"

#include <algorithm>
#include <numeric>

#include <fmt/format.h>

#include "schedule/bytes.h"

namespace gdp::schedule {

template <class T>
Problem<T>::Problem(const GuidanceSource& source, const SolverOptions& options, SolveSummary& summary)
    : topology(topology::make_topology(options.domain)),
      hierarchy(multigrid::build_hierarchy(*topology, source.width(), source.height(), source.alpha(),
                                           options.coarsest_size)),
      ops(hierarchy) {
  // Per-pixel weights hold values (where positive): no null space, no mean to keep.
  if (source.has_weights()) ops.singular = false;
  summary.width = source.width();
  summary.height = source.height();
  summary.channels = source.channels();
  summary.levels = ops.count();
  for (const auto& g : hierarchy.levels) {
    summary.level_widths.push_back(g.width());
    summary.level_heights.push_back(g.height());
  }
}

double mean_shift(bool singular, double target_sum, double weight_total, const std::vector<double>& dots) {
  if (!singular || weight_total <= 0.0) return 0.0;
  return (target_sum - std::accumulate(dots.begin(), dots.end(), 0.0)) / weight_total;
}

ResidualLog::ResidualLog(int channels, bool keep_lines)
    : keep_lines_(keep_lines), b_norm_(channels, 0.0), rel_(channels), lines_(channels) {}

void ResidualLog::initial(int c, double norm) { rel_[c].assign(1, relative(c, norm)); }

void ResidualLog::cycle(int c, double norm, const multigrid::CycleProbe& probe) {
  rel_[c].push_back(relative(c, norm));
  if (!keep_lines_) return;
  std::string line = fmt::format("channel {} v-cycle {}: relative residual {:.3e}; per level |r|/|b|", c,
                                 rel_[c].size() - 1, rel_[c].back());
  for (double r : probe.level_norms) line += fmt::format(" {:.3e}", relative(c, r));
  lines_[c].push_back(std::move(line));
}

bool ResidualLog::settled(int c, double tolerance) const {
  if (tolerance <= 0.0) return false;
  const std::vector<double>& r = rel_[c];
  if (r.back() <= tolerance) return true;
  if (r.size() <= kStallCycles) return false;
  // The best of the last cycles against the best before them: noise at the floor does not count.
  const auto recent = r.end() - kStallCycles;
  return *std::min_element(recent, r.end()) > 0.9 * *std::min_element(r.begin(), recent);
}

void ResidualLog::finish(SolveSummary& summary, const SolverOptions& options) const {
  std::size_t done = 0;
  for (const auto& r : rel_) done = std::max(done, r.size());
  summary.vcycles = static_cast<int>(done) - 1;
  summary.relative_residuals.assign(done, 0.0);
  for (const auto& r : rel_)
    for (std::size_t k = 0; k < r.size(); ++k)
      summary.relative_residuals[k] = std::max(summary.relative_residuals[k], r[k]);
  if (!options.measures_residuals()) summary.relative_residuals.clear();  // (zeros: not measured)
  if (options.log)
    for (const auto& lines : lines_)
      for (const auto& l : lines) options.log(l);
}

template <class Archive>
void ResidualLog::state(Archive& a, int c0, int n) {
  for (int c = c0; c < c0 + n; ++c) {
    a.io(b_norm_[c]);
    a.io(rel_[c]);
    auto count = static_cast<std::uint64_t>(lines_[c].size());
    a.io(count);
    if (count > (1u << 20)) throw CorruptState("too many log lines");
    lines_[c].resize(count);
    for (std::string& line : lines_[c]) {
      std::vector<char> chars(line.begin(), line.end());
      a.io(chars);
      line.assign(chars.begin(), chars.end());
    }
  }
}
template void ResidualLog::state(ByteWriter&, int, int);
template void ResidualLog::state(ByteReader&, int, int);

template struct Problem<float>;
template struct Problem<double>;

}  // namespace gdp::schedule
