// `gdp clone`: seamless cloning of a masked source region into a target image.
#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "gdp/apps.h"
#include "gdp/image_stream.h"

namespace gdp::cli {
namespace {

class Clone final : public Command {
 public:
  explicit Clone(CLI::App& root) {
    app = root.add_subcommand("clone", "seamless cloning: the source's gradients inside the mask, the target elsewhere");
    app->add_option("--source,-s", source_, "image to take the region from")->required();
    app->add_option("--target,-t", target_, "image to paste into (sets the output's size)")->required();
    app->add_option("--mask,-m", mask_, "the region, on the source's grid: pixels above 0.5 (first channel)")
        ->required();
    app->add_option("--offset", offset_, "X,Y: where the source's top-left pixel lands in the target")
        ->delimiter(',')
        ->expected(2);
    app->add_flag("--mixed", options_.mixed, "keep the target's gradient where it is stronger than the source's");
    app->add_option("-o,--output", output_, "output image")->required();
    add_common_options(*app, common_);
  }

  bool runs_under_mpi() const override { return true; }

  int run() override {
    Stats stats("clone");
    // Pinned pixels slow each V-cycle's convergence: iterate to a tolerance unless told otherwise.
    if (app->count("--vcycles") == 0 && app->count("--tolerance") == 0) common_.solver.tolerance = kCloneTolerance;
    const SolverOptions solver = solver_options(common_, "clone");
    if (!offset_.empty()) {
      options_.offset_x = offset_[0];
      options_.offset_y = offset_[1];
    }
    options_.target_name = target_;
    options_.source_name = source_;
    options_.mask_name = mask_;
    ImageFileReader target(target_), source(source_), mask(mask_);
    check_clone_inputs(target, source, mask, options_);
    const auto out = open_output(output_, target.width(), target.height(), target.channels(),
                                 write_options(common_, target.info()), common_.quiet);
    SolveSummary summary;
    stats.time("total", [&] {
      clone(target, source, mask, options_, solver, *out, &summary);
      out->commit();
    });
    stats.summary(summary);
    note(common_, fmt::format("clone: {}x{}x{}, {} V-cycle(s){} -> {}", summary.width, summary.height,
                              summary.channels, summary.vcycles, residual_note(summary), output_));
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  std::string source_, target_, mask_, output_;
  std::vector<int> offset_;
  CloneOptions options_;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_clone(CLI::App& root) { return std::make_unique<Clone>(root); }

}  // namespace gdp::cli
