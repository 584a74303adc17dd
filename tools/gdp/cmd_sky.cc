// `gdp sky`: FITS plates with WCS blended on the sphere, written for a target header (docs/sky.md).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cli_common.h"
#include "commands.h"
#include "gdp/errors.h"
#include "gdp/sky.h"
#include "gdp/sky_projected.h"

namespace gdp::cli {
namespace {

// "A,B" -> two numbers; UsageError naming the option otherwise.
template <class T>
std::pair<T, T> pair_of(const std::string& text, const char* option) {
  const std::size_t comma = text.find(',');
  try {
    std::size_t used_a = 0, used_b = 0;
    if (comma == std::string::npos) throw std::invalid_argument("no comma");
    const std::string a = text.substr(0, comma), b = text.substr(comma + 1);
    const double x = std::stod(a, &used_a), y = std::stod(b, &used_b);
    if (used_a != a.size() || used_b != b.size()) throw std::invalid_argument("trailing text");
    return {static_cast<T>(x), static_cast<T>(y)};
  } catch (const std::exception&) {
    throw UsageError(fmt::format("{} takes two numbers A,B, not '{}'", option, text));
  }
}

// A JSON string's contents: quotes, backslashes and control characters escaped.
std::string json_escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04x}", static_cast<int>(c));
    else out += c;
  }
  return out;
}

class Sky final : public Command {
 public:
  explicit Sky(CLI::App& root) {
    app = root.add_subcommand("sky", "sky mosaic: FITS plates with WCS blended on the sphere, written for a target WCS");
    app->add_option("plates", plates_, "FITS plates with a celestial WCS (--projected: images or directories)")->required();
    app->add_option("-o,--output", output_, "output image on the target grid (FITS gets the target's WCS in its header); "
                                            "optional with --hips or --toast");
    app->add_option("--header", options_.target.header, "target header template (Montage's form: KEY = value lines)");
    app->add_option("--center", center_, "target centre RA,DEC in degrees (with --size and --scale)");
    app->add_option("--size", size_, "target size W,H in pixels");
    app->add_option("--scale", options_.target.scale, "target pixel scale in degrees");
    app->add_option("--projection", options_.target.projection,
                    "target projection: TAN, CAR, SIN, ZEA, ... (wcslib's codes); HPX without --center/--size: the "
                    "whole sky on HEALPix pixels (of --scale, else as fine as the plates)")
        ->capture_default_str();
    app->add_option("--toast", options_.toast, "also write a WorldWideTelescope TOAST tile pyramid into this new or empty "
                                               "directory (PQ height rounded up to 128 * 2^n)");
    app->add_option("--hips", options_.hips, "also write a HiPS directory (IVOA HiPS 1.0: HEALPix tiles as FITS and PNG, "
                                             "properties, Moc.fits, Allsky) into this new or empty directory");
    app->add_option("--hips-tile", options_.hips_tile, "HiPS tile width (a power of 2)")->capture_default_str();
    app->add_option("--plane", plane_, "plane of cube plates (1-based)")->capture_default_str();
    app->add_flag("!--no-blend", options_.blend,
                  "--no-blend: only the seamed mosaic (each point from the plate it lies deepest inside), no solve");
    app->add_flag("--fit-backgrounds,!--no-fit-backgrounds", options_.fit_backgrounds,
                  "fit each plate's plane and radial term to the overlaps and take them off before the solve "
                  "(default, with --projected too; --no-fit-backgrounds: offsets only)");
    app->add_option("--background-damping", options_.background_damping,
                    "--fit-backgrounds: damping of the smooth terms, relative to the overlaps' weight")
        ->capture_default_str();
    app->add_option("--seams", seams_, "stars: seams go around the stars in the overlaps (each star from one plate); "
                                       "deepest: each point from the plate it lies deepest inside; graphcut: the "
                                       "stars' seams moved by a graph cut to where the plates agree best (with "
                                       "--projected: gdp blend's graph-cut seams)")
        ->check(CLI::IsMember({"stars", "deepest", "graphcut"}))
        ->capture_default_str();
    app->add_option("--seams-from", options_.seam_plates,
                    "find the stars that place the seams in these plates (one per plate, same order and grids: e.g. "
                    "another band), not in the plates");
    app->add_flag("--projected", projected_,
                  "the images are already reprojected onto the --header template (Montage's mProjExec output, a "
                  "directory such as its projdir too; NAME_area.fits give coverage): blend them planar on it");
    add_common_options(*app, common_);
  }

  // Plates on the PQ sphere: every rank builds the mosaic rows and solves its columns, rank 0
  // gathers the PQ rows and writes the outputs (docs/sky.md, "Memory, bands and mpirun").
  bool runs_under_mpi() const override { return true; }

  int run() override {
    Stats stats("sky");
    const SolverOptions solver = solver_options(common_, "sky");
    if (projected_) return run_projected(stats, solver);
    if (!options_.target.header.empty() && !center_.empty())
      throw UsageError("give the target either as --header or as --center/--size/--scale, not both");
    if (options_.target.projection == "HPX" && center_.empty() != size_.empty())
      throw UsageError("--projection HPX takes --center with --size (a region), or neither (the whole sky)");
    if (!center_.empty()) std::tie(options_.target.lon, options_.target.lat) = pair_of<double>(center_, "--center");
    if (!size_.empty()) std::tie(options_.target.width, options_.target.height) = pair_of<int>(size_, "--size");
    if (plane_ < 1) throw UsageError(fmt::format("--plane counts from 1, got {}", plane_));
    options_.plane = plane_ - 1;
    options_.star_seams = seams_ != "deepest";
    options_.graphcut_seams = seams_ == "graphcut";
    if (!options_.star_seams && !options_.seam_plates.empty())
      throw UsageError("--seams-from needs --seams stars or graphcut");
    options_.pq_height = common_.pq_height;
    options_.note = [this](const std::string& m) { note(common_, "gdp sky: " + m); };
    ImageFileInfo info;  // plates are read as floats: the output defaults to float
    SkySummary summary;
    stats.time("total", [&] { sky_mosaic(plates_, options_, solver, output_, write_options(common_, info), &summary); });
    if (options_.blend) stats.summary(summary.solve);
    stats.set("pq_height", std::to_string(summary.pq_height));
    const auto& w = summary.pq_window;
    stats.set("pq_window", fmt::format("\"{}x{}+{}+{}\"", w[2], w[3], w[0], w[1]));
    stats.set("covered_pixels", std::to_string(summary.covered));
    stats.set("plates_held_at_once", std::to_string(summary.plates_held));
    stats.set("plates_crossing_a_row", std::to_string(summary.plates_crossing));
    stats.set("mosaic_pixels_computed", std::to_string(summary.mosaic_pixels));
    if (options_.graphcut_seams) {
      stats.set("seam_cost_depth", fmt::format("{:.9g}", summary.seam_cost_depth));
      stats.set("seam_cost", fmt::format("{:.9g}", summary.seam_cost));
    }
    stats.set("plate_pixels_read", fmt::format("[{}]", fmt::join(summary.plate_pixels_read, ", ")));
    stats.set("plate_pixels_in_files", std::to_string(summary.plate_pixels_in_files));
    report_backgrounds(plates_, summary.backgrounds, summary.background_rms, stats);
    if (!output_.empty())
      note(common_, fmt::format("sky: {} plate(s) on a PQ sphere of height {}; {} of {} target pixels covered -> {}",
                                plates_.size(), summary.pq_height, summary.covered, summary.target_pixels, output_));
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  // --projected: images on the template, blended planar (gdp/sky_projected.h).
  int run_projected(Stats& stats, const SolverOptions& solver) {
    if (!center_.empty() || !options_.toast.empty() || !options_.hips.empty() || !options_.blend ||
        common_.pq_height > 0 || plane_ != 1 || seams_ == "deepest" || !options_.seam_plates.empty())
      throw UsageError("gdp sky --projected takes --header, --seams graphcut and solver options, not --center, "
                       "--toast, --hips, --no-blend, --pq-height, --plane, --seams deepest or --seams-from");
    if (output_.empty()) throw UsageError("gdp sky --projected needs -o OUTPUT");
    ProjectedOptions options;
    options.header = options_.target.header;
    options.fit_backgrounds = options_.fit_backgrounds;
    options.background_damping = options_.background_damping;
    options.graphcut_seams = seams_ == "graphcut";
    options.note = [this](const std::string& m) { note(common_, "gdp sky --projected: " + m); };
    ProjectedSummary summary;
    const std::vector<ProjectedInput> inputs = projected_inputs(plates_);
    stats.time("total", [&] {
      sky_projected(inputs, options, solver, output_, write_options(common_, ImageFileInfo{}), &summary);
    });
    stats.summary(summary.blend.solve);
    stats.set("covered_pixels", std::to_string(summary.covered));
    if (options.graphcut_seams) {
      stats.set("seam_cost_depth", fmt::format("{:.9g}", summary.blend.seam_cost_depth));
      stats.set("seam_cost", fmt::format("{:.9g}", summary.blend.seam_cost));
    }
    std::vector<std::string> names;
    for (const ProjectedInput& in : inputs) names.push_back(in.image);
    report_backgrounds(names, summary.backgrounds, summary.background_rms, stats);
    note(common_, fmt::format("sky --projected: {} image(s) on the {}x{} template; {} pixels covered -> {}",
                              inputs.size(), summary.width, summary.height, summary.covered, output_));
    stats.write(common_.stats_path);
    return 0;
  }

  // The fitted backgrounds plate by plate: a note each with --verbose, and in --stats.
  void report_backgrounds(const std::vector<std::string>& plates, const std::vector<std::array<double, 4>>& backgrounds,
                          const std::vector<double>& rms, Stats& stats) const {
    if (backgrounds.empty()) return;
    std::string json = "[";
    for (std::size_t k = 0; k < backgrounds.size(); ++k) {
      const auto& b = backgrounds[k];
      if (common_.verbose)
        note(common_, fmt::format("gdp sky: {}: background fitted: offset {:.6g}, slope u {:.6g}, slope v {:.6g}, radial "
                                  "{:.6g}",
                                  plates[k], b[0], b[1], b[2], b[3]));
      json += fmt::format("{}\n    {{\"plate\": \"{}\", \"offset\": {:.9g}, \"slope_u\": {:.9g}, \"slope_v\": {:.9g}, "
                          "\"radial\": {:.9g}, \"smooth_rms\": {:.9g}}}",
                          k ? "," : "", json_escaped(plates[k]), b[0], b[1], b[2], b[3], rms[k]);
    }
    stats.set("plate_backgrounds", json + "\n  ]");
  }

  bool projected_ = false;
  std::vector<std::string> plates_;
  std::string output_, center_, size_, seams_ = "stars";
  long plane_ = 1;
  SkyOptions options_;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_sky(CLI::App& root) { return std::make_unique<Sky>(root); }

}  // namespace gdp::cli
