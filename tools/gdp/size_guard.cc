// Bounds on image sizes from --max-pixels or the free scratch disk and memory, checked from the header.
#include "size_guard.h"

#include <sys/statvfs.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/size_check.h"

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

void guard_sizes(const CommonOptions& o, const SolverOptions* solver, bool in_memory) {
  const long long max_pixels = o.max_pixels;
  const double scale = solver && solver->precision == Precision::Float64 ? 2.0 : 1.0;
  const bool in_core = in_memory || (solver && solver->schedule == Schedule::InCore);
  const bool scratch = solver && !in_core;
  const double disk_per_sample = kScratchPerSample * scale * (solver && solver->scratch == ScratchPrecision::Narrow ? 0.5 : 1.0);
  std::filesystem::path dir;
  if (scratch) dir = solver->temp_dir.empty() ? std::filesystem::temp_directory_path() : solver->temp_dir;
  set_size_check([=](long long width, long long height, int channels) {
    const double pixels = static_cast<double>(width) * static_cast<double>(height);
    const std::string size = fmt::format("{}x{} ({:.2f} gigapixels)", width, height, pixels / 1e9);
    if (max_pixels > 0) {
      if (pixels > static_cast<double>(max_pixels))
        throw UsageError(fmt::format("{} is more than --max-pixels {}", size, max_pixels));
      return;
    }
    const std::string allow = fmt::format("--max-pixels {:.0f} to try anyway", pixels);
    const double samples = pixels * channels;
    const double memory = in_core ? samples * kInCorePerSample * scale
                                  : static_cast<double>(width) * channels * kRowsInMemory * 4.0 * scale;
    const double have_memory = available_memory();
    if (memory > have_memory)
      throw UsageError(fmt::format("{} would need about {} of memory, and {} is available ({})", size, gb(memory),
                                   gb(have_memory), allow));
    if (!scratch) return;
    // Under mpirun every rank keeps the scratch of its own columns.
    const double disk = samples * disk_per_sample / MpiRun::size(), have_disk = free_disk(dir);
    if (disk > have_disk)
      throw UsageError(fmt::format("{} would need about {} of scratch space in {}, which has {} free (--temp DIR "
                                   "elsewhere, or {})",
                                   size, gb(disk), dir.string(), gb(have_disk), allow));
  });
}

}  // namespace gdp::cli
