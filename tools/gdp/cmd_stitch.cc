// `gdp stitch`: seamless stitching of a composite with its label map.
#include <fmt/format.h>

#include "cli_common.h"
#include "commands.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/strip_files.h"

namespace gdp::cli {
namespace {

class Stitch final : public Command {
 public:
  explicit Stitch(CLI::App& root) {
    app = root.add_subcommand("stitch", "seamless stitching: composite gradients, cut where labels change");
    app->add_option("--composite,-c", composite_, "composite image (any format OpenImageIO reads; {rank} in the name: vertical strips 0, 1, ... side by side)")->required();
    app->add_option("--labels,-l", labels_, "label map: one colour per source image; white = unknown")->required();
    app->add_option("-o,--output", output_, "output image")->required();
    app->add_option("--unknown", unknown_, "pixels labelled white: black | harmonic | label | extend (the composite's own differences into and inside them)")
        ->check(CLI::IsMember({"black", "harmonic", "label", "extend"}))
        ->capture_default_str();
    app->add_flag("--deramp", options_.deramp, "subtract each label's mean gradient");
    app->add_option("--space", space_,
                    "blend in: values (as stored) | log (exposure differences vanish) | lab (CIE L*a*b*; 8/16-bit "
                    "inputs are taken as sRGB-encoded, float ones as linear)")
        ->check(CLI::IsMember({"values", "log", "lab"}))
        ->capture_default_str();
    app->add_flag("!--zero-start", options_.start_from_composite, "start from zero instead of the composite");
    add_fidelity_options(*app, fidelity_);
    add_common_options(*app, common_);
  }

  bool runs_under_mpi() const override { return true; }

  int run() override {
    Stats stats("stitch");
    const SolverOptions solver = solver_options(common_, "stitch");
    options_.unknown = parse_unknown_mode(unknown_);
    options_.labels_name = labels_;
    options_.composite_name = composite_;
    StripFilesReader composite(composite_), labels(labels_);
    check_stitch_inputs(composite, labels, options_);
    // Both files decode (on their own threads) while the output is opened and the solver sets up,
    // so that their first rows wait for no one. A rank of a distributed solve decodes only its
    // columns (set_columns, later): it starts at its first read.
    if (MpiRun::size() == 1) {
      composite.read_ahead();
      labels.read_ahead();
    }
    options_.space.kind = parse_blend_space(space_);
    const SampleType stored = composite.info().sample_type;
    options_.space.srgb_encoded = stored == SampleType::UInt8 || stored == SampleType::UInt16;
    if (labels.info().lossy || is_lossy_extension(labels_))
      note(common_, fmt::format("gdp: warning: {}: label map in a lossy format ({}); compression noise "
                                "creates spurious labels",
                                labels_, labels.info().format_name));
    const auto out = open_output(output_, composite.width(), composite.height(), composite.channels(),
                                 write_options(common_, composite.info()), common_.quiet);
    SolveSummary summary;
    stats.time("total", [&] {
      const auto sphere = sphere_rows(common_, composite, composite_);
      RowReader& c = sphere ? sphere->input(composite, composite_) : composite;
      RowReader& l = sphere ? sphere->input(labels, labels_, true) : labels;
      RowWriter& w = sphere ? sphere->output(*out, composite.channels()) : *out;
      const auto fidelity = open_fidelity(fidelity_, composite, composite_, sphere.get());
      stitch(c, l, options_, solver, w, &summary, fidelity->fidelity);
      w.commit();
    });
    stats.summary(summary);
    note(common_, fmt::format("stitch: {}x{}x{}, {} levels, {} V-cycle(s){} -> {}", summary.width, summary.height,
                              summary.channels, summary.levels, summary.vcycles, residual_note(summary), output_));
    stats.write(common_.stats_path);
    return 0;
  }

 private:
  std::string composite_, labels_, output_, unknown_ = "harmonic", space_ = "values";
  StitchOptions options_;
  FidelityFiles fidelity_;
  CommonOptions common_;
};

}  // namespace

std::unique_ptr<Command> make_stitch(CLI::App& root) { return std::make_unique<Stitch>(root); }

}  // namespace gdp::cli
