// `gdp sharpen` and `gdp smooth`: scale gradients by beta, hold values with weight alpha.
#include <cmath>

#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/strip_files.h"

namespace gdp::cli {
namespace {

class Sharpen final : public Command {
 public:
  Sharpen(CLI::App& root, bool smooth) : smooth_(smooth), beta_(smooth ? 0.5 : 2.0) {
    name_ = smooth ? "smooth" : "sharpen";
    app = root.add_subcommand(name_, smooth ? "gradient-domain smoothing (beta < 1)"
                                            : "gradient-domain sharpening (beta > 1)");
    app->add_option("input", input_, "input image ({rank} in the name: vertical strips 0, 1, ... side by side)")->required();
    app->add_option("-o,--output", output_, "output image")->required();
    app->add_option("--beta,-b", beta_, "gradient scale")->capture_default_str();
    auto* a = app->add_option("--alpha,-a", alpha_, "value weight; detail finer than 1/sqrt(alpha) pixels is scaled");
    auto* s = app->add_option("--scale", scale_.pixels, "scale in pixels (alpha = 1 / scale^2); default 16");
    a->excludes(s);
    auto* at = app->add_option("--scale-at", scale_at_,
                               "--scale is in pixels of an image whose long side is this many pixels (so a "
                               "preview and the full image look the same)");
    auto* deg = app->add_option("--scale-deg", scale_deg_, "the scale in degrees of arc (spherical images)");
    a->excludes(at);
    a->excludes(deg);
    at->excludes(deg);
    app->add_option("--low", low_, "take the values from this image (same size), the gradients from the input");
    add_fidelity_options(*app, fidelity_);
    add_common_options(*app, common_);
  }

  bool runs_under_mpi() const override { return true; }

  int run() override {
    Stats stats(name_);
    if (smooth_ && !(beta_ < 1.0)) throw UsageError(fmt::format("smooth needs --beta below 1, got {}", beta_));
    if (!smooth_ && !(beta_ > 1.0)) throw UsageError(fmt::format("sharpen needs --beta above 1, got {}", beta_));
    if (app->count("--scale-at")) scale_.at = scale_at_;
    if (app->count("--scale-deg")) scale_.degrees = scale_deg_;
    const SolverOptions solver = solver_options(common_, name_);
    scale_.validate(solver.domain);
    StripFilesReader in(input_);
    const auto out = open_output(output_, in.width(), in.height(), in.channels(), write_options(common_, in.info()),
                                 common_.quiet);
    SolveSummary summary;
    stats.time("total", [&] {
      const auto sphere = sphere_rows(common_, in, input_);
      RowReader& r = sphere ? sphere->input(in, input_) : in;
      RowWriter& w = sphere ? sphere->output(*out, in.channels()) : *out;
      if (!app->count("--alpha")) alpha_ = scale_.alpha(solver.domain, in.width(), in.height(), r.width(), r.height());
      const auto fidelity = open_fidelity(fidelity_, in, input_, sphere.get());
      if (low_.empty()) {
        sharpen(r, alpha_, beta_, solver, w, &summary, fidelity->fidelity);
      } else {
        StripFilesReader low_file(low_);
        if (low_file.width() != in.width() || low_file.height() != in.height() || low_file.channels() != in.channels())
          throw InputError(fmt::format("{}: {}x{}x{}, but {} is {}x{}x{}", low_, low_file.width(), low_file.height(),
                                       low_file.channels(), input_, in.width(), in.height(), in.channels()));
        RowReader& low = sphere ? sphere->input(low_file, low_) : low_file;
        sharpen(r, low, alpha_, beta_, solver, w, &summary, fidelity->fidelity);
      }
      w.commit();
    });
    stats.summary(summary);
    stats.set("alpha", fmt::format("{}", alpha_));
    stats.set("scale_pixels", fmt::format("{}", 1.0 / std::sqrt(alpha_)));
    stats.set("beta", fmt::format("{}", beta_));
    note(common_, fmt::format("{}: {}x{}x{}, alpha {:.4g}, beta {:.4g}{} -> {}", name_, summary.width,
                              summary.height, summary.channels, alpha_, beta_, residual_note(summary), output_));
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  bool smooth_;
  std::string name_, input_, output_, low_;
  double beta_, alpha_ = 0.0, scale_deg_ = 0.0;
  int scale_at_ = 0;
  SharpenScale scale_;
  FidelityFiles fidelity_;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_sharpen(CLI::App& root, bool smooth) {
  return std::make_unique<Sharpen>(root, smooth);
}

}  // namespace gdp::cli
