// Shared CLI plumbing: flag definitions, progress with ETA on a terminal, JSON statistics.
#include "cli_common.h"

#include "gdp/mpi_run.h"

#include <sys/resource.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <thread>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/scratch_flags.h"
#include "gdp/size_check.h"
#include "cli_checkpoint.h"
#include "size_guard.h"

namespace gdp::cli {

namespace {

// Checked when the flags are parsed: a --stats file that cannot be written fails before the run.
std::string stats_path_problem(const std::string& path) {
  const std::filesystem::path p(path);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return fmt::format("no such directory '{}'", dir.string());
  if (std::filesystem::is_directory(p, ec)) return fmt::format("'{}' is a directory", path);
  return "";
}

}  // namespace

void add_common_options(CLI::App& cmd, CommonOptions& o, bool solver_flags) {
  if (solver_flags) {
    cmd.add_option("--iters,-k", o.iters,
                   "Gauss-Seidel sweeps per level: K before restriction and K after prolongation, or PRE/POST "
                   "(docs/multigrid.md)")
        ->default_str(o.solver.sweeps == o.solver.post_sweeps
                          ? std::to_string(o.solver.sweeps)
                          : std::to_string(o.solver.sweeps) + "/" + std::to_string(o.solver.post_sweeps));
    cmd.add_option("--vcycles", o.solver.vcycles, "number of V-cycles")->capture_default_str();
    cmd.add_option("--tolerance", o.solver.tolerance,
                   "run V-cycles until the relative residual is below this (overrides --vcycles), or until three "
                   "cycles do not lower it by 10% (the arithmetic's floor: a float solve of smooth data stalls near 1e-5; "
                   "--double goes further; --stats lists the residuals)");
    o.solver.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    cmd.add_option("--threads", o.solver.threads, "threads: in-core, two smooth one channel, a channel group per two; streaming, one lane per channel beyond the two codec threads (one band on 2 or more threads: a lane per channel); default: all cores")
        ->capture_default_str();
    cmd.add_option("--coarsest", o.solver.coarsest_size, "coarsest level size solved by conjugate gradients")
        ->capture_default_str();
    cmd.add_option("--domain", o.domain, "planar | cylindrical (periodic left/right edges) | spherical (a PQ image, 4H x H: see gdp sphere to-pq)")->capture_default_str();
    cmd.add_flag("--sphere", o.sphere,
                 "spherical image: an equirectangular (2:1) input is resampled to PQ, solved there and resampled "
                 "back; a PQ (4:1) input is solved in place");
    cmd.add_option("--pq-height", o.pq_height, "with --sphere: PQ height for equirectangular inputs (default: about "
                                                "the input's pixel count, H = m * 2^k)");
    cmd.add_flag("--double", o.double_precision, "solve in double precision (default float)");
    cmd.add_flag("--verbose,-v", o.verbose, "print the residual per level and V-cycle");
    cmd.add_flag("--residuals", o.solver.residuals,
                 "measure the relative residual before the first V-cycle and after each (the final note's, and "
                 "--stats' relative_residuals, else null): two residual sweeps of the finest level more, about 4 % "
                 "of a stitch's CPU; --verbose, --tolerance and --checkpoint measure them anyway");
    cmd.add_flag("--in-core", o.in_core, "hold every level in memory instead of streaming (same result)");
    cmd.add_option("--incore-bytes", o.solver.incore_bytes,
                   "streaming and bands: coarse levels of at most this many bytes are solved in memory (on one "
                   "worker with bands; narrower bands merge in pairs above it)")
        ->capture_default_str()
        ->check(CLI::Validator(
            [](const std::string& v) { return v.find('-') == std::string::npos ? "" : "a negative size, got " + v; },
            "BYTES"));
    cmd.add_option("--bands", o.bands, "split the columns into this many bands solved in parallel, one thread each "
                                       "(paper section 6; docs/how-bands-work.md); under mpirun this many on every "
                                       "rank, default 1")
        ->check(CLI::Range(1, 1 << 16));
    cmd.add_option("--temp", o.solver.temp_dir,
                   "directory for scratch files (default: the system's); under mpirun, {rank} in it becomes the "
                   "rank's number (a directory per rank, e.g. on each node's own disk)");
    cmd.add_option("--scratch", o.scratch,
                   "precision of what the V-cycle keeps between its passes: narrow (16-bit floats but the data "
                   "later V-cycles reuse: half the scratch, every schedule the same bits; the default) or float "
                   "(the exact solver; the default with --double)")
        ->check(CLI::IsMember({"float", "narrow"}));
    cmd.add_flag("--half-scratch", o.half_scratch, "the same as --scratch narrow");
    cmd.add_option("--memory", o.memory,
                   fmt::format("scratch rows kept in memory, e.g. 512M, 4G; beyond it they go to files in --temp "
                               "(0 or 'files': always files; with --checkpoint always files); default a quarter "
                               "of physical memory, {:.1f}G here, where stores of 64M or more are O_DIRECT files "
                               "whatever the budget (a fresh page can cost more than the disk); with --memory "
                               "given, scratch stays in memory while it fits (GDP_DIRECT_SCRATCH=off or =SIZE "
                               "overrides both)", default_scratch_memory() / 1073741824.0))
        ->check(CLI::Validator(
            [](const std::string& v) {
              try {
                parse_memory_size(v);
                return std::string();
              } catch (const std::exception& e) {
                return std::string(e.what());
              }
            },
            "SIZE"));
    add_checkpoint_options(cmd, o.checkpoint, o.resume);
  }
  o.app = &cmd;
  cmd.add_flag("--quiet,-q", o.quiet, "no progress or notes on stderr");
  cmd.add_option("--max-pixels", o.max_pixels,
                 "refuse images of more pixels (default: what the free scratch disk and memory allow, estimated "
                 "from the header before anything is allocated)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--stats", o.stats_path, "write statistics as JSON to this file")
      ->check(CLI::Validator(stats_path_problem, "FILE"));
  cmd.add_option("--depth", o.depth, "output sample type: 8, 16, half, float (default: the input's)")
      ->check(CLI::IsMember({"8", "16", "half", "float"}));
  cmd.add_option("--quality", o.quality, "JPEG quality 1-100")->check(CLI::Range(1, 100))->capture_default_str();
  cmd.add_flag("--tiled", o.tiled, "write a tiled TIFF or OpenEXR (256x256 tiles)");
  cmd.add_option("--compression", o.compression, "output compression (TIFF: none, lzw, zip; default: the format's)");
}

namespace {

// "\r<label> 42% ETA 3s" on a terminal, rate-limited, a final newline at 100%. Into a log file or
// pipe (a batch job, a device run): whole lines every 30 s, none for a run shorter than that.
class Progress {
 public:
  Progress(std::string label, bool terminal) : label_(std::move(label)), terminal_(terminal), start_(Clock::now()) {}
  void operator()(double fraction) {
    const auto now = Clock::now();
    const auto every = terminal_ ? std::chrono::milliseconds(200) : std::chrono::milliseconds(30000);
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (!terminal_ && elapsed < 30.0) return;
    if (fraction < 1.0 && now - last_ < every) return;
    last_ = now;
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    if (terminal_)
      std::fprintf(stderr, "\r%s %3.0f%%  ETA %.0fs   %s", label_.c_str(), 100.0 * fraction, eta,
                   fraction >= 1.0 ? "\n" : "");
    else
      std::fprintf(stderr, "%s %3.0f%%  ETA %.0fs  (%.0fs elapsed)\n", label_.c_str(), 100.0 * fraction, eta, elapsed);
    std::fflush(stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  bool terminal_;
  Clock::time_point start_, last_{};
};

}  // namespace

std::function<void(double)> progress_line(const CommonOptions& o, const std::string& label) {
  if (o.quiet) return nullptr;
  return Progress(label, isatty(STDERR_FILENO) != 0);
}

SolverOptions solver_options(CommonOptions& o, const std::string& command) {
  SolverOptions s = o.solver;
  if (!o.iters.empty()) parse_sweeps(o.iters, s);
  if (MpiRun::size() > 1 && o.bands == 0) o.bands = 1;  // under mpirun: one band per rank unless told
  ScheduleFlags{o.domain, o.sphere, o.pq_height, o.in_core, o.bands}.apply(s);
  if (o.bands != 0) warn_if_bound(o, o.bands);
  s.temp_dir = for_this_rank(o.solver.temp_dir.string());
  if (!o.memory.empty()) app_scratch_memory(s, parse_memory_size(o.memory));
  s.precision = o.double_precision ? Precision::Float64 : Precision::Float32;
  s.scratch = app_scratch_precision(o.scratch, o.half_scratch, o.double_precision);
  if (o.verbose) s.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  s.progress = progress_line(o, command + ": solving");
  if (o.app) apply_checkpoint_options(*o.app, command, o.checkpoint, o.resume, s);
  s.validate();
  guard_sizes(o, &s);
  return s;
}

std::unique_ptr<SphereRows> sphere_rows(const CommonOptions& o, const RowReader& reader, const std::string& name) {
  if (!o.sphere) return nullptr;
  if (o.pq_height > 0) check_derived_size(fmt::format("--pq-height {}", o.pq_height), 4LL * o.pq_height, o.pq_height,
                                          reader.channels());
  return std::make_unique<SphereRows>(reader.width(), reader.height(), name, o.pq_height);
}

void add_fidelity_options(CLI::App& cmd, FidelityFiles& f) {
  cmd.add_option("--weights", f.weights,
                 "per-pixel weight of the input's values (first channel, >= 0; 1/s^2 holds detail coarser than s pixels)");
  cmd.add_option("--pin", f.pins, "mask: pixels above 0.5 (first channel) keep their input values");
}

std::unique_ptr<FidelityInputs> open_fidelity(const FidelityFiles& f, const RowReader& main,
                                              const std::string& main_name, SphereRows* sphere) {
  auto in = std::make_unique<FidelityInputs>();
  const auto open = [&](const std::string& path, std::unique_ptr<StripFilesReader>& file, bool nearest) -> RowReader* {
    if (path.empty()) return nullptr;
    file = std::make_unique<StripFilesReader>(path);
    if (sphere) return &sphere->input(*file, path, nearest);
    if (file->width() != main.width() || file->height() != main.height())
      throw InputError(fmt::format("{}: {}x{}, but {} is {}x{}", path, file->width(), file->height(), main_name,
                                   main.width(), main.height()));
    return file.get();
  };
  in->fidelity.weights = open(f.weights, in->weights_file, true);  // Lanczos could make weights negative
  in->fidelity.pins = open(f.pins, in->pins_file, true);
  in->fidelity.weights_name = f.weights;
  in->fidelity.pins_name = f.pins;
  return in;
}

WriteOptions write_options(const CommonOptions& o, const ImageFileInfo& input) {
  WriteOptions w;
  w.jpeg_quality = o.quality;
  w.tiled = o.tiled;
  w.compression = o.compression;
  w.sample_type = parse_depth(o.depth).value_or(input.sample_type);
  return w;
}

std::string for_this_rank(const std::string& path) { return with_rank(path, MpiRun::rank()); }

namespace {

// A rank's own output file (`-o` with {rank}): the columns it solved (RowWriter::set_columns),
// or whole rows when it solved them all; opened at the first row, when the width is known.
class RankFileWriter final : public RowWriter {
 public:
  RankFileWriter(std::string path, int width, int height, int channels, const WriteOptions& options, bool quiet)
      : path_(std::move(path)), width_(width), height_(height), channels_(channels), end_(width), options_(options),
        quiet_(quiet) {}
  void set_columns(int begin, int end) override {
    begin_ = begin;
    end_ = end;
  }
  void write_row(int y, std::span<const float> row) override {
    const int n = end_ - begin_;
    if (!file_) {
      if (options_.frame) options_.frame->x += begin_;  // OpenEXR: its columns' place in the frame
      file_ = std::make_unique<ImageFileWriter>(path_, n, height_, channels_, options_);
    }
    row_.resize(static_cast<std::size_t>(channels_) * n);
    for (int c = 0; c < channels_; ++c)
      std::copy_n(row.begin() + static_cast<std::ptrdiff_t>(c) * width_ + begin_, n,
                  row_.begin() + static_cast<std::ptrdiff_t>(c) * n);
    file_->write_row(y, row_);
  }
  void commit() override {
    if (!file_) return;
    file_->commit();
    if (!quiet_)
      std::fprintf(stderr, "gdp: rank %d wrote columns [%d, %d) of %d to %s\n", MpiRun::rank(), begin_, end_, width_,
                   path_.c_str());
  }

 private:
  std::string path_;
  int width_, height_, channels_, begin_ = 0, end_;
  WriteOptions options_;
  bool quiet_;
  std::unique_ptr<ImageFileWriter> file_;
  std::vector<float> row_;
};

}  // namespace

std::unique_ptr<RowWriter> open_output(const std::string& path, int width, int height, int channels,
                                       const WriteOptions& options, bool quiet) {
  check_compression(path, options.compression);
  if (path.find(kRankKey) != std::string::npos)
    return std::make_unique<RankFileWriter>(for_this_rank(path), width, height, channels, options, quiet);
  return MpiRun::gather_file(path, width, height, channels, options);  // rank 0 writes it, from every rank's columns
}

void warn_if_bound(const CommonOptions& o, int bands) {
  if (!MpiRun::launched()) return;
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return;
  const int cores = CPU_COUNT(&set);
  if (cores <= bands)
    note(o, fmt::format("gdp: note: rank {} may run on {} core(s) only, for {} band(s) and its reading and writing "
                        "threads (mpirun binds every rank to one core by default with up to 2 ranks): mpirun "
                        "--bind-to none, or --map-by slot:PE={}",
                        MpiRun::rank(), cores, bands, bands + 1));
}

void note(const CommonOptions& o, const std::string& message) {
  if (!o.quiet && MpiRun::rank() == 0) std::fprintf(stderr, "%s\n", message.c_str());
}

std::string residual_note(const SolveSummary& s) {
  return s.relative_residuals.empty() ? "" : fmt::format(", relative residual {:.2e}", s.relative_residuals.back());
}

void Stats::summary(const SolveSummary& s) {
  std::string residuals, sizes;
  for (double r : s.relative_residuals) residuals += fmt::format("{}{:.6e}", residuals.empty() ? "" : ", ", r);
  for (std::size_t l = 0; l < s.level_widths.size(); ++l)
    sizes += fmt::format("{}[{}, {}]", l ? ", " : "", s.level_widths[l], s.level_heights[l]);
  image(s.width, s.height, s.channels);
  set("levels", std::to_string(s.levels));
  set("schedule", fmt::format("\"{}\"", s.schedule));
  set("streamed_levels", std::to_string(s.streamed_levels));
  set("scratch_mb", fmt::format("{:.1f}", s.scratch_bytes / 1048576.0));
  const double pixels = static_cast<double>(s.width) * s.height;
  set("scratch_bytes_per_pixel", fmt::format("{:.3f}", pixels > 0 ? s.scratch_bytes / pixels : 0.0));
  set("solver_memory_mb", fmt::format("{:.1f}", s.window_bytes / 1048576.0));
  // The scratch budget (--memory): most held at once in memory and in files, stores that spilled.
  set("scratch_memory_mb", fmt::format("{:.1f}", s.scratch_memory_peak / 1048576.0));
  scratch_memory_mb_ = std::max(scratch_memory_mb_, s.scratch_memory_peak / 1048576.0);
  set("scratch_disk_mb", fmt::format("{:.1f}", s.scratch_disk_peak / 1048576.0));
  set("scratch_spilled_stores", std::to_string(s.scratch_spilled));
  set("level_sizes", "[" + sizes + "]");
  set("vcycles", std::to_string(s.vcycles));
  // null: not measured (--residuals, --verbose or --tolerance measure them; docs/multigrid.md).
  set("relative_residuals", s.relative_residuals.empty() ? "null" : "[" + residuals + "]");
  seconds_["rhs"] += s.seconds_rhs;
  seconds_["rhs_decode_cpu"] += s.cpu_rhs_decode;
  seconds_["rhs_columns_cpu"] += s.cpu_rhs_columns;
  seconds_["vcycles"] += s.seconds_solve;
}

void Stats::image(int width, int height, int channels) {
  megapixels_ = static_cast<double>(width) * height / 1e6;
  set("width", std::to_string(width));
  set("height", std::to_string(height));
  set("channels", std::to_string(channels));
}

void Stats::write(const std::string& path) const {
  if (path.empty() || MpiRun::rank() != 0) return;
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  std::string json = fmt::format("{{\n  \"command\": \"{}\",\n", command_);
  for (const auto& [k, v] : extra_) json += fmt::format("  \"{}\": {},\n", k, v);
  json += "  \"seconds\": {";
  bool first = true;
  for (const auto& [k, v] : seconds_) {
    json += fmt::format("{}\"{}\": {:.4f}", first ? "" : ", ", k, v);
    first = false;
  }
  json += fmt::format("}},\n  \"seconds_total\": {:.4f},\n  \"cpu_seconds\": {:.3f},\n  \"peak_rss_mb\": {:.1f},\n",
                      std::chrono::duration<double>(Clock::now() - start_).count(),
                      ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e6,
                      ru.ru_maxrss / 1024.0);
  // Scratch in memory is memfd pages the process never maps, so the RSS leaves them out: the
  // memory the run held is at most the two together.
  json += fmt::format("  \"peak_memory_mb\": {:.1f},\n", ru.ru_maxrss / 1024.0 + scratch_memory_mb_);
  // Minor page faults count pages first touched, including memory freed to the system and taken
  // again: buffers allocated and freed in an inner loop show here (docs/multigrid.md).
  json += fmt::format("  \"minor_faults\": {},\n  \"minor_faults_per_mpix\": {:.0f}\n}}\n", ru.ru_minflt,
                      megapixels_ > 0 ? ru.ru_minflt / megapixels_ : 0.0);
  // Every step checked (a full disk shows only when the buffer is written, at fclose).
  std::FILE* f = std::fopen(path.c_str(), "w");
  bool ok = f && std::fwrite(json.data(), 1, json.size(), f) == json.size();
  int error = errno;
  if (f && std::fclose(f) != 0 && ok) {
    ok = false;
    error = errno;
  }
  if (ok) return;
  std::error_code ec;
  if (f && std::filesystem::is_regular_file(path, ec)) std::filesystem::remove(path, ec);  // no partial JSON
  throw OutputError(fmt::format("{}: cannot write statistics: {}", path, std::generic_category().message(error)));
}

}  // namespace gdp::cli
