// Solving the screened Poisson equation for every channel of a guidance source.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "gdp/checkpoint.h"
#include "gdp/guidance.h"
#include "gdp/image.h"
#include "gdp/rows.h"
#include "gdp/topology.h"

namespace gdp {

enum class Precision { Float32, Float64 };

// How a V-cycle keeps what its second pass reads back (u and b of every level, the finest
// weights, the result carried between V-cycles). Part of the numerics: every schedule rounds the
// same quantities at the same points, so they agree bit for bit (docs/how-streaming-works.md,
// "Which quantities can be half floats").
enum class ScratchPrecision {
  Float,   // the kernel's own precision: the exact solver (the library's default)
  Narrow,  // 16-bit floats but for the finest b and u when more V-cycles may run and the carried
           // result when iterating to a tolerance: half the scratch of one V-cycle (the CLI's default)
};
// "float" or "narrow"; UsageError naming the text otherwise.
ScratchPrecision parse_scratch_precision(const std::string& text);

// The default scratch budget (SolverOptions::scratch_memory, --memory): a quarter of the
// machine's physical memory.
std::size_t default_scratch_memory();
// A --memory value: bytes ("1000000"), or with a binary unit K, M, G or T ("512M", "1.5G"), "0"
// or "files" (always files); UsageError naming the text otherwise.
std::size_t parse_memory_size(const std::string& text);
// SolverOptions::direct_scratch_from's default: the finest level's stores of an 8192² solve, one
// band or two (docs/how-streaming-works.md, "The e2e stitch, third round": on the machine measured
// a fresh page of memory cost more CPU than the disk).
inline constexpr std::size_t kDirectScratchFrom = std::size_t{64} << 20;

// How the V-cycles are carried out (docs/multigrid.md, docs/how-streaming-works.md). Both give
// bit-identical results.
enum class Schedule {
  Streaming,  // two passes over the rows per V-cycle, a few rows per level in memory
  InCore,     // every level held whole in memory
  Bands,      // streaming, the columns split into bands solved in lockstep (docs/how-bands-work.md);
              // a valid Gauss-Seidel ordering of its own, so close to but not bit-identical with the others
};

struct SolverOptions {
  Domain domain = Domain::Planar;
  int sweeps = 3;             // Gauss-Seidel sweeps before restriction (the pre-smoother)
  int post_sweeps = 3;        // and after prolongation (3/3 meets the stitching accuracy target with
                              // margin: docs/reproduce.md; splits: docs/multigrid.md)
  int vcycles = 1;            // V-cycles to run (when tolerance == 0)
  double tolerance = 0.0;     // > 0: run V-cycles until the relative residual is below this
  int max_vcycles = 100;      // cap when iterating to a tolerance
  int coarsest_size = 64;     // coarsen until no side exceeds this, then conjugate gradients
  double coarse_tolerance = 1e-10;  // relative residual of the coarsest-level CG solve
  Precision precision = Precision::Float32;
  int threads = 1;            // in-core: a channel group per two threads, the two smoothing one channel
  Schedule schedule = Schedule::Streaming;
  int bands = 1;              // Schedule::Bands: bands (worker threads) in this process
  std::filesystem::path temp_dir;  // streaming scratch files (empty: the system's temporary directory)
  // Float keeps the library an exact solver (callers with manufactured solutions, double
  // precision, or data that is not an image get float's answer); applications writing images opt
  // into Narrow (docs/how-streaming-works.md). Float64 allows Float only.
  ScratchPrecision scratch = ScratchPrecision::Float;
  // These quantities as 16-bit floats too ("u", "b", "w", "result", or one level's: "level0-u";
  // docs/how-streaming-works.md measures each).
  std::vector<std::string> half_quantities;
  // Bytes of scratch rows that all solves of the process together keep in memory; stores beyond it
  // go to files in temp_dir (0: always files). With checkpoint_dir, stores are files regardless.
  std::size_t scratch_memory = default_scratch_memory();
  // Stores of at least this many bytes are O_DIRECT files in temp_dir even when they fit
  // scratch_memory, where the directory takes them. SIZE_MAX: memory first while the budget holds,
  // files only past it (app_scratch_memory: a budget the application names). GDP_DIRECT_SCRATCH
  // overrides both.
  std::size_t direct_scratch_from = kDirectScratchFrom;
  // Streaming: levels whose planes (u and b, all channels) fit in this many bytes are held in
  // memory and solved in-core; larger ones stream.
  std::size_t incore_bytes = std::size_t{8} << 20;
  // Streaming: keep the scratch and the solver's state in this directory at every completed unit
  // of work (docs/resume.md); with `resume`, continue from what it holds. `checkpoint_identity`
  // (inputs and options) is written to its manifest and must match when resuming.
  std::filesystem::path checkpoint_dir;
  bool resume = false;
  CheckpointIdentity checkpoint_identity;
  // Measure the relative residual of the finest level before the first V-cycle and after each
  // (SolveSummary::relative_residuals; the CLI's --residuals): two residual sweeps of the finest
  // level more per V-cycle, only read, never changing the result. Measured regardless when
  // iterating to a tolerance, with a log, or with a checkpoint (a resumed run then has them whole
  // whatever its flags); else relative_residuals is left empty (docs/multigrid.md, "Residual norms
  // only when asked for").
  bool residuals = false;
  // Receives one line per level and V-cycle with residual norms (the CLI's --verbose).
  std::function<void(const std::string&)> log;
  // Receives the fraction of work done, from 0 to 1.
  std::function<void(double)> progress;

  // Throws UsageError describing the first invalid option.
  void validate() const;
  // The most V-cycles a solve runs: max_vcycles when iterating to a tolerance, else vcycles.
  int cycle_cap() const { return tolerance > 0.0 ? max_vcycles : vcycles; }
  // Whether the solve measures the finest level's residual norms (see `residuals`).
  bool measures_residuals() const {
    return residuals || tolerance > 0.0 || static_cast<bool>(log) || !checkpoint_dir.empty();
  }
};

// --iters: "K" (K sweeps before restriction and K after prolongation) or "PRE/POST"; sets
// options.sweeps and options.post_sweeps, or throws UsageError naming the flag and the value.
void parse_sweeps(const std::string& text, SolverOptions& options);

// How the CLI's flags --domain NAME, --sphere, --pq-height H, --in-core and --bands N choose the
// domain and schedule (shared with the Python module, so both report conflicts alike).
struct ScheduleFlags {
  std::string domain = "planar";
  bool sphere = false;  // solve on the spherical domain (an equirectangular input is resampled to PQ)
  int pq_height = 0;    // with sphere: the PQ height (0: chosen from the input's size)
  bool in_core = false;
  int bands = 0;        // > 0: the band schedule with this many bands
  // Sets options.domain, schedule and bands; throws UsageError naming the flags that conflict.
  void apply(SolverOptions& options) const;
};

struct SolveSummary {
  int width = 0, height = 0, channels = 0, levels = 0, vcycles = 0;
  std::vector<int> level_widths, level_heights;
  // Relative residual |b - A u| / |b| (worst channel) before the first V-cycle and after each;
  // empty when not measured (SolverOptions::measures_residuals).
  std::vector<double> relative_residuals;
  double seconds_rhs = 0.0, seconds_solve = 0.0;  // reading guidance (the input pass), the rest
  // Streamed: CPU seconds of the input pass, its decoding thread's and its lanes' (all together).
  double cpu_rhs_decode = 0.0, cpu_rhs_columns = 0.0;
  std::string schedule;          // "streaming" or "in-core"
  int streamed_levels = 0;       // levels that streamed (the rest were held in memory)
  std::size_t scratch_bytes = 0; // bytes stored between passes per V-cycle (disk or memory)
  std::size_t window_bytes = 0;  // bytes of rows and small levels held in memory by the solver
  // Scratch of the whole process during the solve, at most at once: in memory (the budget's
  // part) and in files; stores that did not fit in the budget.
  std::size_t scratch_memory_peak = 0, scratch_disk_peak = 0, scratch_spilled = 0;
};

// Solves for every channel of the source and writes the result's rows, in order, to `out`
// (commit() is left to the caller). The starting guess is the source's `initial` rows (zero
// when it has none). When alpha == 0 the result is defined up to a constant per channel: it
// keeps the starting guess's mean over the counted pixels with finite values (zero when there
// is no starting guess), up to how much the last smoothing sweeps move the mean (docs/multigrid.md).
void solve(GuidanceSource& source, const SolverOptions& options, RowWriter& out, SolveSummary* summary = nullptr);

// The same into an in-memory image; `initial` (optional, same size and channels) replaces the
// source's starting guess.
Image solve(GuidanceSource& source, const SolverOptions& options, const Image* initial = nullptr,
            SolveSummary* summary = nullptr);

}  // namespace gdp
