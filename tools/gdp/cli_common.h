// Options and reporting shared by the gdp subcommands: solver flags, progress, statistics.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "gdp/apps.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "gdp/solver.h"
#include "gdp/sphere_rows.h"
#include "gdp/strip_files.h"

namespace gdp::cli {

// Flags every solving subcommand accepts.
struct CommonOptions {
  SolverOptions solver;
  std::string iters;  // --iters K or PRE/POST (parse_sweeps; empty: the solver's default)
  std::string domain = "planar";
  bool double_precision = false;
  bool verbose = false;
  bool quiet = false;
  std::string stats_path;
  std::string depth;  // output sample type: 8, 16, half, float (default: the input's)
  int quality = 95;   // JPEG quality
  bool tiled = false; // tiled TIFF / OpenEXR output
  std::string compression;
  bool in_core = false;
  int bands = 0;  // > 0: the band schedule with this many bands (threads)
  bool sphere = false;  // --sphere: equirectangular or PQ input, solved on the PQ domain
  int pq_height = 0;    // --pq-height (0: sphere::default_pq_height)
  long long max_pixels = 0;  // --max-pixels (0: what the free scratch disk and memory allow; size_guard.h)
  std::string checkpoint, resume;  // --checkpoint DIR, --resume DIR (cli_checkpoint.h)
  std::string memory;              // --memory SIZE (gdp::parse_memory_size; empty: the default)
  std::string scratch;             // --scratch float|narrow (empty: narrow, float with --double)
  bool half_scratch = false;       // --half-scratch: --scratch narrow (kept for older scripts)
  const CLI::App* app = nullptr;   // the subcommand these flags were added to
};

void add_common_options(CLI::App& cmd, CommonOptions& o, bool solver_flags = true);

// "\r<label> 42%  ETA 3s" on stderr when it is a terminal and not --quiet; else empty.
std::function<void(double)> progress_line(const CommonOptions& o, const std::string& label);

// Validates and converts flags into the solver's options (log/progress hooked to stderr).
SolverOptions solver_options(CommonOptions& o, const std::string& command);

// With --sphere, the wrapper that puts the command's rows on the PQ domain (sized from its main
// input `reader`, named `name` in errors); empty otherwise.
std::unique_ptr<SphereRows> sphere_rows(const CommonOptions& o, const RowReader& reader, const std::string& name);

// --weights and --pin (stitch, sharpen, smooth): per-pixel fidelity images.
struct FidelityFiles {
  std::string weights, pins;
};
void add_fidelity_options(CLI::App& cmd, FidelityFiles& f);

// The fidelity images opened beside the main input `main` (named `main_name`): size-checked
// (InputError naming the file) or, with --sphere, resampled like it (pins nearest-neighbour).
struct FidelityInputs {
  std::unique_ptr<StripFilesReader> weights_file, pins_file;
  Fidelity fidelity;
};
std::unique_ptr<FidelityInputs> open_fidelity(const FidelityFiles& f, const RowReader& main,
                                              const std::string& main_name, SphereRows* sphere);

// The output file's writer; under mpirun rank 0 writes the file, putting every row together from
// the columns each rank solved (gdp::MpiRun::gather_writer). A path with {rank} gives every rank
// a file of its own columns instead (`out_{rank}.tif`: out_0.tif, out_1.tif, ... left to right;
// each rank says on stderr which columns it wrote, unless `quiet`).
std::unique_ptr<RowWriter> open_output(const std::string& path, int width, int height, int channels,
                                       const WriteOptions& options, bool quiet);

// `path` with every {rank} replaced by this process's MPI rank (0 without mpirun).
std::string for_this_rank(const std::string& path);

// Output write options: sample type from --depth or else the input file's.
WriteOptions write_options(const CommonOptions& o, const ImageFileInfo& input);

// Wall-clock phases and results, written as JSON by --stats.
class Stats {
 public:
  explicit Stats(std::string command) : command_(std::move(command)), start_(Clock::now()) {}
  // Runs f, adding its wall time to the named phase, and returns what f returns.
  template <class F>
  decltype(auto) time(const std::string& phase, F&& f) {
    const Timer timer{seconds_[phase]};
    return f();
  }
  void set(const std::string& key, const std::string& json_value) { extra_[key] = json_value; }
  void summary(const SolveSummary& s);
  // Input and output sizes for the JSON.
  void image(int width, int height, int channels);
  // Writes the JSON file when one was asked for (empty path: nothing).
  void write(const std::string& path) const;

 private:
  using Clock = std::chrono::steady_clock;
  struct Timer {
    double& total;
    Clock::time_point start = Clock::now();
    ~Timer() { total += std::chrono::duration<double>(Clock::now() - start).count(); }
  };
  std::string command_;
  Clock::time_point start_;
  std::map<std::string, double> seconds_;
  std::map<std::string, std::string> extra_;
  double megapixels_ = 0.0;  // of the last image() (minor page faults per Mpix)
  double scratch_memory_mb_ = 0.0;  // the most scratch held in memory (memfds: not in the RSS)
};

// A line on stderr unless --quiet.
void note(const CommonOptions& o, const std::string& message);
// ", relative residual 1.23e-04" (the last V-cycle's) for a note, or "" when the solve did not
// measure residuals (SolverOptions::measures_residuals: --residuals, --verbose, --tolerance).
std::string residual_note(const SolveSummary& s);
// Under mpirun: a note (rank 0) when this rank may use no more cores than it runs bands (Open MPI
// binds ranks to one core by default), which leaves its reading and writing threads none of their own.
void warn_if_bound(const CommonOptions& o, int bands);

}  // namespace gdp::cli
