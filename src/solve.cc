// gdp::solve: check the options, pick the schedule and precision.
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/scratch_flags.h"
#include "gdp/solver.h"
#include "bands/band_layout.h"
#include "bands/solve_streamed.h"
#include "schedule/scratch_budget.h"
#include "schedule/solve_parts.h"
#include "util/forwarding_guidance.h"

namespace gdp {
namespace {

// A source whose starting guess comes from an in-memory image.
class WithInitial final : public util::ForwardingGuidance {
 public:
  WithInitial(GuidanceSource& inner, const Image& initial) : ForwardingGuidance(inner), initial_(initial) {}
  bool has_initial() const override { return true; }
  bool start_from_initial() const override { return true; }
  void read_row(int j, GuidanceRow& out) override {
    inner_.read_row(j, out);
    for (int c = 0; c < initial_.channels; ++c) {
      const auto r = initial_.row(c, j);
      std::copy(r.begin(), r.end(), out.initial.begin() + static_cast<std::ptrdiff_t>(c) * initial_.width);
    }
  }

 private:
  const Image& initial_;
};

void solve_with_schedule(GuidanceSource& source, const SolverOptions& options, RowWriter& out, SolveSummary& s);

}  // namespace

void SolverOptions::validate() const {
  if (sweeps < 0 || sweeps > 100 || post_sweeps < 0 || post_sweeps > 100)
    throw UsageError(fmt::format("--iters must be K or PRE/POST with counts in 0..100, got '{}'",
                                 sweeps == post_sweeps ? fmt::format("{}", sweeps)
                                                       : fmt::format("{}/{}", sweeps, post_sweeps)));
  if (vcycles < 1) throw UsageError(fmt::format("--vcycles must be at least 1, got {}", vcycles));
  if (tolerance < 0.0 || !std::isfinite(tolerance))
    throw UsageError(fmt::format("--tolerance must be a non-negative number, got {}", tolerance));
  if (max_vcycles < 1) throw UsageError("the V-cycle cap must be at least 1");
  if (coarsest_size < 1) throw UsageError(fmt::format("coarsest size must be positive, got {}", coarsest_size));
  if (bands < 1) throw UsageError(fmt::format("--bands must be at least 1, got {}", bands));
  if (threads < 1) throw UsageError(fmt::format("--threads must be at least 1, got {}", threads));
  if ((scratch != ScratchPrecision::Float || !half_quantities.empty()) && precision == Precision::Float64)
    throw UsageError("half-float scratch would throw away double precision: use one or the other");
  std::error_code ec;
  if (!temp_dir.empty() && !std::filesystem::is_directory(temp_dir, ec))
    throw UsageError(fmt::format("--temp: '{}' is not a directory", temp_dir.string()));
  if (resume && checkpoint_dir.empty()) throw UsageError("resuming needs the checkpoint's directory");
  if (!checkpoint_dir.empty() && schedule == Schedule::InCore)
    throw UsageError("--checkpoint and --resume need the streaming schedule: they do not combine with --in-core");
}

void parse_sweeps(const std::string& text, SolverOptions& options) {
  // Digits only (no sign, no spaces), one or two counts, each 0..100.
  const auto count = [&](const std::string& part) {
    if (part.empty() || part.size() > 3 || part.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(part) > 100)
      throw UsageError(fmt::format("--iters must be K or PRE/POST with counts in 0..100, got '{}'", text));
    return std::stoi(part);
  };
  const std::size_t slash = text.find('/');
  options.sweeps = count(text.substr(0, slash));
  options.post_sweeps = slash == std::string::npos ? options.sweeps : count(text.substr(slash + 1));
}

ScratchPrecision parse_scratch_precision(const std::string& text) {
  if (text == "float") return ScratchPrecision::Float;
  if (text == "narrow") return ScratchPrecision::Narrow;
  throw UsageError(fmt::format("--scratch must be float or narrow, got '{}'", text));
}

ScratchPrecision app_scratch_precision(const std::string& scratch, bool half_scratch, bool double_precision) {
  if (half_scratch && scratch == "float") throw UsageError("--half-scratch is --scratch narrow, not float");
  if (half_scratch) return ScratchPrecision::Narrow;
  if (!scratch.empty()) return parse_scratch_precision(scratch);
  return double_precision ? ScratchPrecision::Float : ScratchPrecision::Narrow;
}

void app_scratch_memory(SolverOptions& options, std::size_t bytes) {
  options.scratch_memory = bytes;
  options.direct_scratch_from = SIZE_MAX;
}

int band_halo_columns(int sweeps) { return bands::band_halo(sweeps, bands::kDefaultPhaseGroups); }

std::size_t direct_scratch_from(const SolverOptions& options) { return schedule::ScratchBudget::direct_from(options); }

void ScheduleFlags::apply(SolverOptions& options) const {
  options.domain = parse_domain(domain);
  if (sphere) {
    if (options.domain != Domain::Planar && options.domain != Domain::Spherical)
      throw UsageError(fmt::format("--sphere solves on the spherical domain, not --domain {}", domain));
    options.domain = Domain::Spherical;
  }
  if (pq_height < 0 || pq_height % 2 != 0)
    throw UsageError(fmt::format("--pq-height must be a positive even number, got {}", pq_height));
  options.schedule = in_core ? Schedule::InCore : Schedule::Streaming;
  if (bands != 0) {
    if (in_core) throw UsageError("--bands streams: it does not combine with --in-core");
    options.schedule = Schedule::Bands;
    options.bands = bands;
  }
}

void solve(GuidanceSource& source, const SolverOptions& options, RowWriter& out, SolveSummary* summary) {
  options.validate();
  if (source.width() < 1 || source.height() < 1 || source.channels() < 1)
    throw InputError(fmt::format("nothing to solve: image is {}x{} with {} channels", source.width(),
                                 source.height(), source.channels()));
  SolveSummary local;
  SolveSummary& s = summary ? *summary : local;
  s = SolveSummary{};
  schedule::ScratchBudget& budget = schedule::ScratchBudget::process();
  budget.apply(options);
  budget.reset_peaks();
  solve_with_schedule(source, options, out, s);
  s.scratch_memory_peak = budget.peak_in_memory();
  s.scratch_disk_peak = budget.peak_on_disk();
  s.scratch_spilled = budget.spilled();
}

namespace {

// The precision the options ask for; every schedule (in-core, streaming, bands) is solve_streamed's.
void solve_with_schedule(GuidanceSource& source, const SolverOptions& options, RowWriter& out, SolveSummary& s) {
  if (options.precision == Precision::Float64) bands::solve_streamed<double>(source, options, out, s);
  else bands::solve_streamed<float>(source, options, out, s);
}

}  // namespace

Image solve(GuidanceSource& source, const SolverOptions& options, const Image* initial, SolveSummary* summary) {
  if (initial && (initial->width != source.width() || initial->height != source.height() ||
                  initial->channels != source.channels()))
    throw UsageError("initial guess does not match the guidance size");
  Image out(source.width(), source.height(), source.channels());
  ImageRowWriter writer(out);
  if (initial) {
    WithInitial with(source, *initial);
    solve(with, options, writer, summary);
  } else {
    solve(source, options, writer, summary);
  }
  return out;
}

}  // namespace gdp
