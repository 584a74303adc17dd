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
    const ReadResult in = stats.time("read", [&] { return read_image(input_); });
    SolveSummary summary;
    const ReconstructResult r = reconstruct(in.image, solver, &summary);
    if (!output_.empty())
      stats.time("write", [&] { write_image(output_, r.image, write_options(common_, in.info)); });
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
