// `gdp reconstruct`: rebuild an image from its own gradients and report the error.
#include <cstdio>

#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "gdp/apps.h"

namespace gdp::cli {
namespace {

class Reconstruct final : public Command {
 public:
  explicit Reconstruct(CLI::App& root) {
    app = root.add_subcommand("reconstruct", "rebuild an image from its own gradients (solver self-test)");
    app->add_option("input", input_, "input image")->required();
    app->add_option("-o,--output", output_, "output image (optional)");
    add_common_options(*app, common_);
  }

  int run() override {
    Stats stats("reconstruct");
    const SolverOptions solver = solver_options(common_, "reconstruct");
    ReadResult in = stats.time("read", [&] { return read_image(input_); });
    // --sphere on an equirectangular image: reconstruct its PQ resampling (errors are measured
    // there), and write the result back as equirectangular.
    const sphere::Projection equirect{sphere::Layout::Equirect}, pq{sphere::Layout::Pq};
    const auto sphere = sphere_rows(common_, ImageRowReader(in.image), input_);
    const int width = in.image.width, height = in.image.height;
    if (sphere && sphere->resampled())
      in.image = stats.time("resample", [&] {
        return sphere::resample(in.image, equirect, pq, 4 * sphere->pq_height(), sphere->pq_height());
      });
    SolveSummary summary;
    ReconstructResult r = reconstruct(in.image, solver, &summary);
    if (!output_.empty()) {
      if (sphere && sphere->resampled())
        r.image = stats.time("resample", [&] { return sphere::resample(r.image, pq, equirect, width, height); });
      stats.time("write", [&] { write_image(output_, r.image, write_options(common_, in.info)); });
    }
    stats.summary(summary);
    stats.set("rms_error", fmt::format("{:.6e}", r.rms_error));
    stats.set("max_error", fmt::format("{:.6e}", r.max_error));
    std::printf("%s: %dx%dx%d, %d V-cycle(s): rms error %.3e, max error %.3e\n", input_.c_str(), summary.width,
                summary.height, summary.channels, summary.vcycles, r.rms_error, r.max_error);
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  std::string input_, output_;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_reconstruct(CLI::App& root) { return std::make_unique<Reconstruct>(root); }

}  // namespace gdp::cli
