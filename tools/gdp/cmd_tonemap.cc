// `gdp tonemap`: gradient-domain dynamic-range compression of an HDR image to display values.
#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"

namespace gdp::cli {
namespace {

class Tonemap final : public Command {
 public:
  explicit Tonemap(CLI::App& root) {
    app = root.add_subcommand("tonemap", "gradient-domain dynamic-range compression (Fattal et al. 2002)");
    app->add_option("input", input_, "input HDR image (linear RGB: .exr, .hdr, .tif, ...)")->required();
    app->add_option("-o,--output", output_, "output image (display values in [0, 1], gamma-encoded)")->required();
    app->add_option("--alpha,-a", options_.alpha, "gradients above alpha * mean gradient (per level) are compressed")
        ->capture_default_str();
    app->add_option("--beta,-b", options_.beta, "attenuation exponent (1: none; smaller compresses more)")
        ->capture_default_str();
    app->add_option("--scales", options_.scales, "pyramid levels (0: down to ~32 pixels on the short side)")
        ->capture_default_str();
    app->add_option("--resolution", options_.resolution,
                    "attenuate only at levels at most this many pixels on the long side (0: all), so previews match")
        ->capture_default_str();
    app->add_option("--saturation,-s", options_.saturation, "colour saturation exponent")->capture_default_str();
    app->add_option("--gamma,-g", options_.gamma, "display gamma (values are raised to 1/gamma)")
        ->capture_default_str();
    app->add_option("--low", options_.low_percentile, "percentile of the output luminance mapped to 0 (0: none)")
        ->capture_default_str();
    app->add_option("--high", options_.high_percentile, "percentile of the output luminance mapped to 1")
        ->capture_default_str();
    common_.solver.vcycles = 2;
    add_common_options(*app, common_);
  }

  int run() override {
    Stats stats("tonemap");
    options_.validate();
    const SolverOptions solver = solver_options(common_, "tonemap");
    ImageFileReader in(input_);
    WriteOptions w = write_options(common_, in.info());
    if (common_.depth.empty()) w.sample_type.reset();  // the output format's own default (8-bit PNG, float EXR)
    ImageFileWriter out(output_, in.width(), in.height(), in.channels(), w);
    SolveSummary summary;
    stats.time("total", [&] {
      const auto sphere = sphere_rows(common_, in, input_);
      RowReader& r = sphere ? sphere->input(in, input_) : in;
      RowWriter& o = sphere ? sphere->output(out, in.channels()) : out;
      tonemap(r, options_, solver, o, &summary);
      o.commit();
    });
    stats.summary(summary);
    stats.image(in.width(), in.height(), in.channels());  // the solve itself has one channel
    stats.set("alpha", fmt::format("{}", options_.alpha));
    stats.set("beta", fmt::format("{}", options_.beta));
    stats.set("saturation", fmt::format("{}", options_.saturation));
    stats.set("gamma", fmt::format("{}", options_.gamma));
    note(common_, fmt::format("tonemap: {}x{}x{}, alpha {:.3g}, beta {:.3g}{} -> {}", summary.width, summary.height,
                              in.channels(), options_.alpha, options_.beta, residual_note(summary), output_));
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  std::string input_, output_;
  TonemapOptions options_;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_tonemap(CLI::App& root) { return std::make_unique<Tonemap>(root); }

}  // namespace gdp::cli
