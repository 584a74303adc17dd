// gdp sky --projected: images on one template -> smooth backgrounds and levels from overlaps -> gdp blend's seams and planar solve -> FITS with the template's WCS.
#include <limits>
#include <memory>
#include <numeric>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/sky_projected.h"
#include "sky/header.h"
#include "sky/plate_exchange.h"
#include "sky/projected_levels.h"
#include "sky/projected_place.h"
#include "sky/rank_share.h"
#include "sky/wcs.h"
#include "util/seconds.h"

namespace gdp {
namespace {

// Blend rows (value, alpha) -> one channel, NaN where alpha is 0 (no image covers the pixel).
class NanWhereUncovered final : public RowWriter {
 public:
  NanWhereUncovered(RowWriter& out, int width) : out_(out), width_(width), row_(static_cast<std::size_t>(width)) {}
  void write_row(int y, std::span<const float> row) override {
    for (int x = 0; x < width_; ++x) {
      const bool known = row[static_cast<std::size_t>(width_) + x] > 0.0f;
      row_[x] = known ? row[x] : std::numeric_limits<float>::quiet_NaN();
      if (known && x >= begin_ && x < end_) ++covered_;
    }
    out_.write_row(y, row_);
  }
  void commit() override { out_.commit(); }
  void set_columns(int begin, int end) override {
    columns_ = true;
    begin_ = begin;
    end_ = end;
    out_.set_columns(begin, end);
  }
  // The covered pixels of this rank's columns (rows written whole, without set_columns, are rank 0's).
  long long covered() const { return columns_ || MpiRun::rank() == 0 ? covered_ : 0; }

 private:
  RowWriter& out_;
  int width_, begin_ = 0, end_ = std::numeric_limits<int>::max();
  bool columns_ = false;
  std::vector<float> row_;
  long long covered_ = 0;
};

// The fitted smooth backgrounds into the layers (taken off as they are read) and the summary.
void take_off_backgrounds(const sky::CanvasLevels& levels, const std::vector<ProjectedInput>& inputs, BlendPlan& plan,
                          ProjectedSummary& s, const std::function<void(const std::string&)>& note) {
  if (levels.backgrounds.empty()) return;
  std::vector<std::string> names;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const sky::PlateBackground& b = levels.backgrounds[k];
    const PlacedLayer& l = plan.layers[k];
    plan.sources[k].background = sky::layer_background(l, b);
    s.backgrounds.push_back({levels.offsets[k], b.slope_u, b.slope_v, b.radial});
    s.background_rms.push_back(sky::smooth_rms(l.width, l.height, b));
    names.push_back(inputs[k].image);
  }
  if (note) note(sky::backgrounds_note(names, s.background_rms));
}

}  // namespace

void sky_projected(const std::vector<ProjectedInput>& inputs, const ProjectedOptions& options,
                   const SolverOptions& solver, const std::filesystem::path& out, WriteOptions write,
                   ProjectedSummary* summary) {
  if (inputs.empty()) throw UsageError("gdp sky --projected needs at least one image");
  if (options.header.empty())
    throw UsageError("gdp sky --projected needs --header TEMPLATE.hdr: the template the images were reprojected onto");
  const std::string name = options.header.string(), cards = sky::read_header_template(options.header);
  const auto w = sky::header_number(cards, "NAXIS1"), h = sky::header_number(cards, "NAXIS2");
  if (!w || !h || *w < 1 || *h < 1) throw InputError(fmt::format("{}: no positive NAXIS1 and NAXIS2", name));
  ProjectedSummary s;
  s.width = static_cast<int>(*w);
  s.height = static_cast<int>(*h);
  const sky::Wcs tpl(cards, s.width, s.height, name);
  std::vector<LayerSource> layers;
  for (const ProjectedInput& in : inputs) layers.push_back(sky::projected_layer(in, tpl));
  BlendOptions blending;
  blending.canvas = CanvasRect{0, 0, s.width, s.height};
  blending.seams = options.graphcut_seams ? SeamMethod::Graphcut : SeamMethod::Depth;
  BlendPlan plan = plan_blend(layers, blending);  // InputError for an image outside the template

  // Under mpirun rank 0 fits the levels (reading every image) and the others take its fit; an
  // error there ends every rank with its message (sky/plate_exchange.h).
  const sky::RankShare ranks;
  const sky::PlateShare& share = ranks.share();
  const auto start = util::SteadyClock::now();
  sky::CanvasLevels levels;
  share.run([&] {
    if (share.rank() == 0) levels = sky::canvas_levels(plan, options.fit_backgrounds ? options.background_damping : -1.0);
  });
  sky::share_canvas_levels(share, levels);
  s.seconds_offsets = util::seconds_since(start);
  for (std::size_t k = 0; k < inputs.size() && inputs.size() > 1; ++k)
    if (!levels.overlapped[k])
      throw InputError(fmt::format("{}: overlaps no other image, so its level cannot be matched to the mosaic's "
                                   "(leave it out, or add the images between)",
                                   inputs[k].image));
  for (std::size_t k = 0; k < inputs.size(); ++k) plan.sources[k].offset = static_cast<float>(-levels.offsets[k]);
  s.offsets = levels.offsets;
  take_off_backgrounds(levels, inputs, plan, s, options.note);

  write.fits_header = cards;
  // Under mpirun rank 0 writes the file from every rank's columns.
  const std::unique_ptr<RowWriter> file = MpiRun::gather_file(out, s.width, s.height, 1, write);
  NanWhereUncovered writer(*file, s.width);
  blend(plan, blending, solver, writer, &s.blend);
  const std::vector<long long> covered = sky::counts_by_rank(share, writer.covered());
  s.covered = std::accumulate(covered.begin(), covered.end(), 0LL);
  if (summary) *summary = std::move(s);
}

}  // namespace gdp
