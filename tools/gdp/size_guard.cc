// Bounds on image sizes from --max-pixels or the free scratch disk and memory, checked from the header.
#include "size_guard.h"

#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/scratch_flags.h"
#include "gdp/size_check.h"
#include "scratch_split.h"

namespace gdp::cli {
namespace {

// Measured with --stats (docs/reproduce.md): a streaming solve keeps about 8 bytes of scratch per
// sample in float (u and b of the finest level; coarser levels add a third, some apps a weight
// row): 10 with the margin. In core, about 16 bytes of memory per sample. Rows in memory: the
// windows of every level, about 64 rows' worth of samples at most.
constexpr double kScratchPerSample = 10.0, kInCorePerSample = 16.0, kRowsInMemory = 64.0;

double free_disk(const std::filesystem::path& dir) {
  struct statvfs s{};
  if (::statvfs(dir.c_str(), &s) != 0) return 1e300;  // unknown: the solve itself will say
  return static_cast<double>(s.f_bavail) * static_cast<double>(s.f_frsize);
}

double available_memory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kb = 0;
  while (meminfo >> key >> kb)
    if (key == "MemAvailable:") return kb * 1024.0;
  return static_cast<double>(::sysconf(_SC_AVPHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

std::string gb(double bytes) { return fmt::format("{:.1f} GB", bytes / 1e9); }

}  // namespace

namespace {

// What guard_sizes and check_canvas_size need to know of the command: its limits and estimates.
struct Limits {
  long long max_pixels = 0;
  double scale = 1.0, disk_per_sample = 0.0, memory_budget = 0.0, direct_from = 0.0;
  int halo = 0;  // a band's, in columns (band_halo_columns)
  bool in_core = false, scratch = false;
  std::filesystem::path dir;
};

Limits limits_of(const CommonOptions& o, const SolverOptions* solver, bool in_memory) {
  Limits l;
  l.max_pixels = o.max_pixels;
  l.scale = solver && solver->precision == Precision::Float64 ? 2.0 : 1.0;
  l.halo = solver ? band_halo_columns(std::max(solver->sweeps, solver->post_sweeps)) : 0;
  l.in_core = in_memory || (solver && solver->schedule == Schedule::InCore);
  l.scratch = solver && !l.in_core;
  l.disk_per_sample = kScratchPerSample * l.scale * (solver && solver->scratch == ScratchPrecision::Narrow ? 0.5 : 1.0);
  // Scratch rows up to the budget (--memory) stay in memory, in each process: only the rest goes to disk.
  if (l.scratch) l.memory_budget = static_cast<double>(solver->scratch_memory);
  if (l.scratch) l.direct_from = static_cast<double>(direct_scratch_from(*solver));
  if (l.scratch) l.dir = solver->temp_dir.empty() ? std::filesystem::temp_directory_path() : solver->temp_dir;
  return l;
}

// The largest row store of a rank: one plane of the finest level (u, b or the carried result) in
// the kernel's precision over the rank's columns, with a band's halo each side under mpirun.
double largest_store(const Limits& l, long long width, long long height, int channels) {
  const double ranks = MpiRun::size(), w = static_cast<double>(width);
  const double columns = ranks > 1 ? std::min(w, w / ranks + 2.0 * l.halo) : w;
  return columns * static_cast<double>(height) * channels * 4.0 * l.scale;
}

// Throws UsageError when width x height x channels exceeds the limits; `extra_disk_per_pixel`: the
// command's own scratch (bytes per pixel) beside the solver's.
void check(const Limits& l, long long width, long long height, int channels, double extra_disk_per_pixel) {
  const double pixels = static_cast<double>(width) * static_cast<double>(height);
  const std::string size = fmt::format("{}x{} ({:.2f} gigapixels)", width, height, pixels / 1e9);
  if (l.max_pixels > 0) {
    if (pixels > static_cast<double>(l.max_pixels))
      throw UsageError(fmt::format("{} is more than --max-pixels {}", size, l.max_pixels));
    return;
  }
  const std::string allow = fmt::format("--max-pixels {:.0f} to try anyway", pixels);
  const double samples = pixels * channels;
  // Under mpirun every rank keeps the scratch of its own columns, each with its own budget.
  const double ranks = MpiRun::size();
  const double scratch = l.scratch ? samples * l.disk_per_sample / ranks : 0.0;
  const double store = l.scratch ? largest_store(l, width, height, channels) : 0.0;
  const ScratchSplit split = split_scratch(scratch, l.memory_budget, store, l.direct_from);
  const double in_memory = split.memory;
  const double memory = l.in_core ? samples * kInCorePerSample * l.scale
                                  : static_cast<double>(width) * channels * kRowsInMemory * 4.0 * l.scale + in_memory;
  const double have_memory = available_memory();
  if (memory > have_memory)
    throw UsageError(fmt::format("{} would need about {} of memory{}, and {} is available ({})", size, gb(memory),
                                 in_memory > 0 ? fmt::format(" ({} of scratch rows: --memory)", gb(in_memory)) : "",
                                 gb(have_memory), allow));
  if (!l.scratch) return;
  const double disk = split.disk + pixels * extra_disk_per_pixel / ranks, have_disk = free_disk(l.dir);
  if (disk > have_disk)
    throw UsageError(fmt::format("{} would need about {} of scratch space in {}, which has {} free (--temp DIR "
                                 "elsewhere, --memory, --half-scratch, or {})",
                                 size, gb(disk), l.dir.string(), gb(have_disk), allow));
}

}  // namespace

void guard_sizes(const CommonOptions& o, const SolverOptions* solver, bool in_memory) {
  const Limits limits = limits_of(o, solver, in_memory);
  set_size_check([=](long long width, long long height, int channels) { check(limits, width, height, channels, 0.0); });
}

void check_canvas_size(const std::string& what, const CommonOptions& o, const SolverOptions& solver, long long width,
                       long long height, int channels, double extra_disk_per_pixel) {
  try {
    check(limits_of(o, &solver, false), width, height, channels, extra_disk_per_pixel);
  } catch (const UsageError& e) {
    throw UsageError(fmt::format("{}: {}", what, e.what()));
  }
}

}  // namespace gdp::cli
