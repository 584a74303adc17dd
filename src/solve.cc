// gdp::solve: build the hierarchy, assemble the right-hand side, run V-cycles per channel.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numeric>
#include <thread>

#include <fmt/format.h>

#include "fem/rhs.h"
#include "gdp/errors.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "topology/topology.h"

namespace gdp {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

template <class T>
double mean_of(const std::vector<T>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

template <class T>
Image solve_typed(GuidanceSource& source, const SolverOptions& opt, const Image* initial,
                  SolveSummary& summary) {
  using multigrid::Plane;
  const int w = source.width(), h = source.height(), channels = source.channels();
  const auto topo = topology::make_topology(opt.domain);
  topo->validate_size(w, h);
  const multigrid::Hierarchy hierarchy =
      multigrid::build_hierarchy(*topo, w, h, source.alpha(), opt.coarsest_size);
  const multigrid::Operators<T> ops(hierarchy);
  summary.width = w;
  summary.height = h;
  summary.channels = channels;
  summary.levels = static_cast<int>(hierarchy.levels.size());
  for (const auto& g : hierarchy.levels) {
    summary.level_widths.push_back(g.width());
    summary.level_heights.push_back(g.height());
  }

  // Right-hand side, streamed row by row from the source.
  const auto t_rhs = Clock::now();
  std::vector<Plane<T>> b(channels, Plane<T>(w, h));
  {
    const fem::Axis& x = hierarchy.levels[0].x;
    fem::RhsAssembler assembler(x, hierarchy.levels[0].y, source.alpha(), channels);
    GuidanceRow row;
    row.x_edges = x.edges();
    row.gx.assign(static_cast<std::size_t>(channels) * x.edges(), 0.0);
    row.gy.assign(static_cast<std::size_t>(channels) * w, 0.0);
    row.value.assign(static_cast<std::size_t>(channels) * w, 0.0);
    const auto sink = [&](int r, int c, std::span<const double> v) {
      constexpr double scale = multigrid::LevelOperator<T>::kScale;
      std::transform(v.begin(), v.end(), b[c].row(r), [](double x) { return static_cast<T>(scale * x); });
    };
    for (int j = 0; j < h; ++j) {
      source.read_row(j, row);
      assembler.push(j, row, sink);
    }
    assembler.finish(sink);
  }
  summary.seconds_rhs = seconds_since(t_rhs);

  // V-cycles, channels spread over threads.
  const auto t_solve = Clock::now();
  Image out(w, h, channels);
  const int cycles = opt.tolerance > 0.0 ? opt.max_vcycles : opt.vcycles;
  std::vector<std::vector<double>> rel(channels);
  std::vector<std::vector<std::string>> logs(channels);
  std::mutex progress_mutex;
  int cycles_done = 0;
  const auto report = [&] {
    if (!opt.progress) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    opt.progress(std::min(1.0, double(++cycles_done) / (double(channels) * cycles)));
  };
  // vc and u are per thread and reused across that thread's channels (fresh memory is
  // costly: page faults were a third of a 2048^2 solve before this).
  const auto solve_channel = [&](int c, multigrid::InCoreVCycle<T>& vc, Plane<T>& u) {
    if (initial)
      std::transform(initial->plane(c).begin(), initial->plane(c).end(), u.data.begin(),
                     [](float v) { return std::isfinite(v) ? static_cast<T>(v) : T(0); });
    else
      std::fill(u.data.begin(), u.data.end(), T(0));
    const double target_mean = initial ? mean_of(u.data) : 0.0;
    const double bnorm = std::sqrt(std::inner_product(b[c].data.begin(), b[c].data.end(), b[c].data.begin(), 0.0));
    const auto relative = [&](double r) { return bnorm > 0.0 ? r / bnorm : r; };
    rel[c].push_back(relative(vc.residual_norm(u, b[c])));
    for (int k = 0; k < cycles; ++k) {
      std::vector<double> levels;
      vc.run(u, b[c], opt.log ? &levels : nullptr);
      rel[c].push_back(relative(vc.residual_norm(u, b[c])));
      report();
      if (opt.log) {
        std::string line = fmt::format("channel {} v-cycle {}: relative residual {:.3e}; per level |r|/|b|", c,
                                       k + 1, rel[c].back());
        for (double r : levels) line += fmt::format(" {:.3e}", relative(r));
        logs[c].push_back(line);
      }
      if (opt.tolerance > 0.0 && rel[c].back() <= opt.tolerance) break;
    }
    const double shift = ops.singular ? target_mean - mean_of(u.data) : 0.0;
    std::transform(u.data.begin(), u.data.end(), out.plane(c).begin(),
                   [shift](T v) { return static_cast<float>(v + shift); });
  };
  const int threads = std::clamp(opt.threads, 1, std::max(channels, 1));
  const auto worker = [&](int t) {
    multigrid::InCoreVCycle<T> vc(ops, opt.sweeps, opt.coarse_tolerance);
    Plane<T> u(w, h);
    for (int c = t; c < channels; c += threads) solve_channel(c, vc, u);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (std::thread& th : pool) th.join();
  summary.seconds_solve = seconds_since(t_solve);

  std::size_t done = 0;
  for (const auto& r : rel) done = std::max(done, r.size());
  summary.vcycles = static_cast<int>(done) - 1;
  summary.relative_residuals.assign(done, 0.0);
  for (const auto& r : rel)
    for (std::size_t k = 0; k < r.size(); ++k)
      summary.relative_residuals[k] = std::max(summary.relative_residuals[k], r[k]);
  if (opt.log)
    for (const auto& lines : logs)
      for (const auto& l : lines) opt.log(l);
  return out;
}

}  // namespace

void SolverOptions::validate() const {
  if (sweeps < 0 || sweeps > 100) throw UsageError(fmt::format("--iters must be in 0..100, got {}", sweeps));
  if (vcycles < 1) throw UsageError(fmt::format("--vcycles must be at least 1, got {}", vcycles));
  if (tolerance < 0.0 || !std::isfinite(tolerance))
    throw UsageError(fmt::format("--tolerance must be a non-negative number, got {}", tolerance));
  if (max_vcycles < 1) throw UsageError("the V-cycle cap must be at least 1");
  if (coarsest_size < 1) throw UsageError(fmt::format("coarsest size must be positive, got {}", coarsest_size));
  if (threads < 1) throw UsageError(fmt::format("--threads must be at least 1, got {}", threads));
}

Image solve(GuidanceSource& source, const SolverOptions& options, const Image* initial,
            SolveSummary* summary) {
  options.validate();
  if (source.width() < 1 || source.height() < 1 || source.channels() < 1)
    throw InputError(fmt::format("nothing to solve: image is {}x{} with {} channels", source.width(),
                                 source.height(), source.channels()));
  if (initial && (initial->width != source.width() || initial->height != source.height() ||
                  initial->channels != source.channels()))
    throw UsageError("initial guess does not match the guidance size");
  SolveSummary local;
  SolveSummary& s = summary ? *summary : local;
  s = SolveSummary{};
  return options.precision == Precision::Float64 ? solve_typed<double>(source, options, initial, s)
                                                 : solve_typed<float>(source, options, initial, s);
}

}  // namespace gdp
