// `gdp blend`: seamless mosaics from N aligned layers, a drop-in for enblend (docs/blend.md).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/strip_files.h"
#include "size_guard.h"

namespace gdp::cli {
namespace {

// "IMAGE" or, when no such file exists, "IMAGE:MASK" (split at the last colon).
LayerSource layer_argument(const std::string& arg) {
  LayerSource s;
  s.image = arg;
  std::error_code ec;
  const auto colon = arg.rfind(':');
  if (!std::filesystem::exists(arg, ec) && colon != std::string::npos && colon > 0 && colon + 1 < arg.size()) {
    s.image = arg.substr(0, colon);
    s.mask = arg.substr(colon + 1);
  }
  return s;
}

bool integer(const std::string& s, long long& v) {
  static const std::regex number("[+-]?[0-9]+");
  if (!std::regex_match(s, number)) return false;
  v = std::stoll(s);
  return true;
}

// One line of a list file: its number, its text and its words ("double quotes" keep spaces).
struct ListLine {
  int number = 0;
  std::string text;
  std::vector<std::string> words;
};

// The lines of a list file that have words and are not # comments; InputError naming `what`
// when the file cannot be read.
std::vector<ListLine> list_lines(const std::string& path, const char* what) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot read the {}", path, what));
  std::vector<ListLine> lines;
  int number = 0;
  for (std::string text; std::getline(in, text);) {
    ListLine l{++number, text, {}};
    std::istringstream words(text);
    for (std::string w; words >> std::quoted(w);) l.words.push_back(w);
    if (!l.words.empty() && l.words[0][0] != '#') lines.push_back(std::move(l));
  }
  return lines;
}

// --layers LIST: per line "IMAGE [MASK] [X Y]". Relative paths are taken from the current directory.
std::vector<LayerSource> layer_list(const std::string& path) {
  std::vector<LayerSource> layers;
  for (const ListLine& l : list_lines(path, "layer list")) {
    const std::vector<std::string>& t = l.words;
    LayerSource s;
    s.image = t[0];
    const bool placed = t.size() >= 3 && integer(t[t.size() - 2], s.x) && integer(t.back(), s.y);
    s.placed = placed;
    if (t.size() == 2 || t.size() == 4) s.mask = t[1];
    if (t.size() > 4 || ((t.size() == 3 || t.size() == 4) && !placed))
      throw InputError(fmt::format("{}:{}: expected IMAGE [MASK] [X Y], got '{}'", path, l.number, l.text));
    layers.push_back(s);
  }
  return layers;
}

// enblend's -f: WxH, WxH+X+Y (also +xX+yY; offsets may be negative).
CanvasRect canvas_argument(const std::string& text) {
  static const std::regex form("([0-9]+)x([0-9]+)(?:([+-])x?([0-9]+)([+-])y?([0-9]+))?");
  std::smatch m;
  if (!std::regex_match(text, m, form))
    throw UsageError(fmt::format("-f/--canvas: '{}' is not WIDTHxHEIGHT or WIDTHxHEIGHT+X+Y", text));
  CanvasRect c;
  c.width = std::stoi(m[1]);
  c.height = std::stoi(m[2]);
  if (m[3].matched) {
    c.x = std::stoll(m[4]) * (m[3] == "-" ? -1 : 1);
    c.y = std::stoll(m[6]) * (m[5] == "-" ? -1 : 1);
  }
  return c;
}

// One decimal number (sign, digits, point, exponent) into `value`; false for anything else.
bool number(const std::string& text, double& value) {
  static const std::regex form("[+-]?([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][+-]?[0-9]+)?");
  if (!std::regex_match(text, form)) return false;
  value = std::stod(text);
  return true;
}

// "1,0.5,2": numbers separated by commas, into `values`; false for anything else.
bool number_list(const std::string& text, std::vector<double>& values) {
  std::vector<double> v;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!number(item, v.emplace_back())) return false;
  if (v.empty() || text.back() == ',') return false;
  values = v;
  return true;
}

// --vignetting-centres LIST: per layer a line "X Y [RADIUS]" in the layer's own pixels.
std::vector<VignettingCentre> centre_list(const std::string& path) {
  std::vector<VignettingCentre> centres;
  for (const ListLine& l : list_lines(path, "vignetting centres")) {
    const std::vector<std::string>& t = l.words;
    VignettingCentre c;
    if ((t.size() != 2 && t.size() != 3) || !number(t[0], c.x) || !number(t[1], c.y) ||
        (t.size() == 3 && !number(t[2], c.radius)))
      throw InputError(fmt::format("{}:{}: expected X Y [RADIUS], got '{}'", path, l.number, l.text));
    centres.push_back(c);
  }
  return centres;
}

// --pin / --weights: a file (an image of the canvas's size, as gdp stitch takes) when one exists
// by that name or the text is not a list of numbers, else per layer: `values` filled.
bool per_layer(const std::string& text, std::vector<double>& values) {
  std::error_code ec;
  return !text.empty() && !std::filesystem::exists(text, ec) && number_list(text, values);
}

class Blend final : public Command {
 public:
  explicit Blend(CLI::App& root) {
    app = root.add_subcommand("blend", "seamless mosaic of aligned layers (enblend's options accepted; docs/blend.md)");
    app->add_option("layers", layers_, "layer images (multi-page TIFF: a layer per page; IMAGE:MASK; @LISTFILE)");
    app->add_option("-o,--output", output_, "output image")->capture_default_str();
    app->add_option("--layers", list_, "a file listing layers, one a line: IMAGE [MASK] [X Y]");
    app->add_option("--canvas", canvas_, "canvas WxH[+X+Y] in the layers' coordinates (enblend's -f); default: "
                                         "the layers' union and their TIFF canvas size");
    app->add_option("--wrap", wrap_, "none | horizontal (360-degree panorama; enblend's -w) | both (full sphere)")
        ->check(CLI::IsMember({"none", "horizontal", "vertical", "both"}))
        ->capture_default_str();
    app->add_option("--seam-guidance", guidance_, "gradients across seams: mean (of both layers') | zero")
        ->check(CLI::IsMember({"mean", "zero"}))
        ->capture_default_str();
    app->add_option("--seams", seams_, "where seams run: depth (deepest layer) | graphcut (where the layers agree)")
        ->check(CLI::IsMember({"depth", "distance", "graphcut"}))
        ->capture_default_str();
    app->add_option("--space", space_, "blend in: values | log | lab (as gdp stitch)")
        ->check(CLI::IsMember({"values", "log", "lab"}))
        ->capture_default_str();
    app->add_option("--anchor", anchor_, "keep layer K's values (1 = the first layer given) and level the rest to "
                                         "it; add --tolerance 1e-4, pinned problems converge more slowly")
        ->check(CLI::PositiveNumber);
    app->add_option("--pin", pin_, "keep values: layer numbers (1,3: their pixels keep their values) or a mask "
                                   "image of the canvas's size (pixels above 0.5), as gdp stitch's --pin");
    app->add_option("--weights", weights_, "weight of the layers' values: one per layer (1,0,0.5), one for all, or "
                                           "an image of the canvas's size, as gdp stitch's --weights (added)");
    app->add_option("--correction", correction_, "also write the additive correction (output minus the layers), "
                                                 "float samples (.tif or .exr)");
    app->add_option("--save-seams", save_seams_, "write the seams: a grey image of layer numbers (1 = the first, "
                                                 "0 = none), lossless (PNG, TIFF)");
    app->add_option("--load-seams", load_seams_, "take the seams from such an image (edited, or kept from a "
                                                   "run before) instead of computing them");
    app->add_flag("--photometric", photometric_, "calibrate the layers first: exposure (gain, offset) and a "
                                                 "vignetting falloff fitted to their overlaps (docs/blend.md)");
    app->add_option("--vignetting-terms", vignetting_terms_, "--photometric's falloff 1 + a1 r^2 + ...: 0 (exposure "
                                                            "only) to 3 terms")
        ->capture_default_str();
    app->add_option("--vignetting-centres", centres_, "--photometric: a file of each layer's optical centre, a line "
                                                     "per layer: X Y [RADIUS] in its own pixels (default: its centre, "
                                                     "half its diagonal)");
    app->add_flag("--version,-V", version_, "print the version and exit (Hugin asks its blender for it)");
    add_common_options(*app, common_);
    app->get_option("--iters")
        ->description("Gauss-Seidel sweeps per level: K before restriction and K after prolongation, or PRE/POST; "
                      "default 2/3 for one V-cycle to 8-bit output (its rounding hides the difference; no --correction, "
                      "--anchor, --pin or --weights), else 3/3 (docs/blend.md, \"The solver's sweeps\")")
        ->default_str("");
  }

  bool runs_under_mpi() const override { return true; }

  int run() override {
    if (version_) {
      std::printf("gdp blend (gdp-blend): gradient-domain blending, accepts enblend's options\n");
      return 0;
    }
    Stats stats("blend");
    blend_defaults();
    SolverOptions solver = solver_options(common_, "blend");
    BlendOptions options = blend_options();
    const std::vector<LayerSource> sources = layer_sources();
    const BlendPlan plan = stats.time("plan", [&] { return plan_blend(sources, options); });
    options.space.srgb_encoded = plan.sample_type == SampleType::UInt8 || plan.sample_type == SampleType::UInt16;
    options.alpha = !is_lossy_extension(output_);  // JPEG and the like store no alpha
    for (const std::string& n : plan.notes) note(common_, "gdp blend: " + n);
    const int W = plan.canvas.width, H = plan.canvas.height, channels = plan.colour_channels + (options.alpha ? 1 : 0);
    // The canvas is solved but read from no file header: checked here, with the label planes (2 bytes a pixel each).
    check_canvas_size(fmt::format("canvas of {} layer(s)", plan.layers.size()), common_, solver, W, H,
                      plan.colour_channels, seams_ == "graphcut" ? 4.0 : 2.0);
    const ImageFileInfo info{plan.sample_type, "tiff", false};
    WriteOptions write = write_options(common_, info);
    write.geo = plan.geo;  // GeoTIFF layers: the output is georeferenced too
    write.frame = frame_placement(plan);  // OpenEXR: the canvas as the data window in the layers' frame
    const auto fidelity = fidelity_images(plan, options);
    const auto out = open_output(output_, W, H, channels, write, common_.quiet);
    std::unique_ptr<RowWriter> correction;
    if (!correction_.empty() && MpiRun::size() > 1)
      throw UsageError("--correction: not under mpirun yet (one gathered output per run)");
    if (!correction_.empty()) {
      WriteOptions f = write_options(common_, info);
      f.sample_type = SampleType::Float;
      correction = open_output(correction_, W, H, plan.colour_channels, f, common_.quiet);
      options.correction = correction.get();
    }
    // No --iters: fewer sweeps where the output is 8-bit (JPEG always is; docs/blend.md, "The solver's sweeps").
    if (common_.iters.empty())
      set_default_blend_sweeps(is_lossy_extension(output_) ? SampleType::UInt8 : write.sample_type.value_or(plan.sample_type),
                               options, solver);
    options.progress = progress_line(common_, "blend: seams");
    BlendReport report;
    stats.time("total", [&] { blend(plan, options, solver, *out, &report); });
    if (!report.isolated.empty()) {
      std::string list;
      for (std::size_t k = 0; k < report.isolated.size() && k < 8; ++k) list += (k ? ", " : "") + report.isolated[k];
      if (report.isolated.size() > 8) list += fmt::format(", ... ({} in all)", report.isolated.size());
      note(common_, fmt::format("blend: layer(s) overlapping no other, placed as they are: {}", list));
    }
    if (photometric_) note_photometry(report);
    stats.summary(report.solve);
    stats.image(W, H, channels);
    stats.set("layers", std::to_string(plan.layers.size()));
    stats.set("sweeps", fmt::format("\"{}/{}\"", solver.sweeps, solver.post_sweeps));
    stats.set("seconds_seams", fmt::format("{:.3f}", report.seconds_seams));
    stats.set("seconds_solve", fmt::format("{:.3f}", report.seconds_solve));
    if (seams_ == "graphcut") {
      stats.set("seam_cost", fmt::format("{:.6g}", report.seam_cost));
      stats.set("seam_cost_depth", fmt::format("{:.6g}", report.seam_cost_depth));
    }
    if (photometric_) {
      stats.set("photometric_points", std::to_string(report.photometric_points));
      stats.set("photometric_rms_before", fmt::format("{:.6g}", report.photometric_rms_before));
      stats.set("photometric_rms_after", fmt::format("{:.6g}", report.photometric_rms_after));
      stats.set("seconds_photometry", fmt::format("{:.3f}", report.seconds_photometry));
    }
    stats.set("blend_scratch_bytes", std::to_string(report.scratch_bytes));
    stats.set("seam_layers_read", std::to_string(report.seam_layers_read));
    stats.set("isolated_layers", std::to_string(report.isolated.size()));
    stats.set("seam_columns", fmt::format("[{}, {}]", report.seam_columns.first, report.seam_columns.second));
    note(common_, fmt::format("blend: {} layer(s), {}x{} canvas at ({}, {}); seams {:.1f}s, solve {:.1f}s{} -> {}",
                              plan.layers.size(), W, H, plan.canvas.x, plan.canvas.y, report.seconds_seams, report.seconds_solve,
                              residual_note(report.solve), output_));
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  // Where blend's defaults differ from the other commands' (docs/blend.md, "Defaults and speed"):
  // the solver's scratch rows go to files (--memory 0: the page cache holds them, the process's
  // peak stays the blend's own), and a TIFF output is deflated at level 1 (a quarter less CPU than
  // level 6 for 8 % more bytes; still smaller than enblend's LZW).
  void blend_defaults() {
    if (common_.memory.empty()) common_.memory = "0";
    std::string ext = std::filesystem::path(output_).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (common_.compression.empty() && (ext == ".tif" || ext == ".tiff")) common_.compression = "zip:1";
  }

  // The fitted calibration, on stderr: the falloff, the gains' range, the overlaps' disagreement.
  void note_photometry(const BlendReport& r) const {
    const Photometry& p = r.photometry;
    if (p.layers.empty()) return note(common_, "blend: --photometric: no overlaps to calibrate on; layers as they are");
    std::string falloff = "1";
    for (std::size_t j = 0; j < p.vignetting.size(); ++j) falloff += fmt::format(" {:+.4f} r^{}", p.vignetting[j], 2 * j + 2);
    double lo = p.layers[0].gain, hi = lo;
    for (const LayerPhotometry& l : p.layers) lo = std::min(lo, l.gain), hi = std::max(hi, l.gain);
    note(common_, fmt::format("blend: photometric calibration on {} overlap points ({:.1f}s): vignetting {}, gains "
                              "{:.4f}..{:.4f}; overlap disagreement {:.5f} -> {:.5f}",
                              r.photometric_points, r.seconds_photometry, falloff, lo, hi, r.photometric_rms_before,
                              r.photometric_rms_after));
  }

  BlendOptions blend_options() const {
    if (common_.domain != "planar")
      throw UsageError("--domain: gdp blend's domain follows --wrap (horizontal: cylindrical, both: the sphere)");
    if (wrap_ == "vertical") throw UsageError("--wrap vertical: gdp wraps horizontally or both ways, not vertically alone");
    BlendOptions o;
    o.wrap = common_.sphere || wrap_ == "both" ? Wrap::Both : wrap_ == "horizontal" ? Wrap::Horizontal : Wrap::None;
    o.seam_guidance = guidance_ == "zero" ? SeamGuidance::Zero : SeamGuidance::Mean;
    o.seams = seams_ == "graphcut" ? SeamMethod::Graphcut : SeamMethod::Depth;
    o.space.kind = space_ == "log" ? BlendSpace::Kind::Log : space_ == "lab" ? BlendSpace::Kind::Lab
                                                                             : BlendSpace::Kind::Values;
    o.pq_height = common_.pq_height;
    o.anchor = anchor_ - 1;
    o.load_seams = load_seams_;
    if (MpiRun::rank() == 0) o.save_seams = save_seams_;  // every rank has the same seams
    if (!canvas_.empty()) o.canvas = canvas_argument(canvas_);
    if (!photometric_ && (!centres_.empty() || app->count("--vignetting-terms") > 0))
      throw UsageError("--vignetting-terms and --vignetting-centres go with --photometric");
    if (vignetting_terms_ < 0 || vignetting_terms_ > 3)
      throw UsageError(fmt::format("--vignetting-terms {}: 0 to 3 (r^2, r^4, r^6)", vignetting_terms_));
    o.photometric.enabled = photometric_;
    o.photometric.vignetting_terms = vignetting_terms_;
    if (!centres_.empty()) o.photometric.centres = centre_list(centres_);
    return o;
  }

  // --pin and --weights: per-layer numbers into `options`, images opened and size-checked.
  std::vector<std::unique_ptr<StripFilesReader>> fidelity_images(const BlendPlan& plan, BlendOptions& options) const {
    std::vector<std::unique_ptr<StripFilesReader>> files;
    const auto image = [&](const std::string& path, RowReader*& reader, std::string& name) {
      auto file = std::make_unique<StripFilesReader>(path);
      if (file->width() != plan.canvas.width || file->height() != plan.canvas.height)
        throw InputError(fmt::format("{}: {}x{}, but the canvas is {}x{}", path, file->width(), file->height(),
                                     plan.canvas.width, plan.canvas.height));
      reader = file.get();
      name = path;
      files.push_back(std::move(file));
    };
    std::vector<double> values;
    if (per_layer(pin_, values)) {
      for (const double v : values) {
        if (v < 1 || v != std::floor(v)) throw UsageError(fmt::format("--pin {}: layers are numbered from 1", pin_));
        options.pinned.push_back(static_cast<int>(v) - 1);
      }
    } else if (!pin_.empty()) {
      image(pin_, options.fidelity.pins, options.fidelity.pins_name);
    }
    if (per_layer(weights_, values))
      options.weights = values.size() == 1 ? std::vector<double>(plan.layers.size(), values[0]) : values;
    else if (!weights_.empty())
      image(weights_, options.fidelity.weights, options.fidelity.weights_name);
    return files;
  }

  std::vector<LayerSource> layer_sources() const {
    std::vector<LayerSource> sources;
    for (const std::string& a : layers_) sources.push_back(layer_argument(a));
    if (!list_.empty())
      for (const LayerSource& s : layer_list(list_)) sources.push_back(s);
    if (sources.empty()) throw UsageError("no layers to blend (give image files, @LISTFILE or --layers LIST)");
    return sources;
  }

  std::vector<std::string> layers_;
  std::string pin_, weights_;
  std::string output_ = "a.tif", correction_, save_seams_, load_seams_, list_, canvas_, wrap_ = "none", guidance_ = "mean", seams_ = "depth", space_ = "values";
  std::string centres_;
  int anchor_ = 0, vignetting_terms_ = 3;
  bool version_ = false, photometric_ = false;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_blend(CLI::App& root) { return std::make_unique<Blend>(root); }

}  // namespace gdp::cli
