// gdp sky: plates -> seamed PQ mosaic -> spherical gradient-domain stitch -> target grid with its WCS.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "blend/seam_share.h"
#include "blend/seams.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "gdp/mpi_run.h"
#include "gdp/sky.h"
#include "sky/header.h"
#include "sky/hips_geometry.h"
#include "sky/hips_output.h"
#include "sky/mosaic_rows.h"
#include "sky/plate.h"
#include "sky/plate_backgrounds.h"
#include "sky/plate_exchange.h"
#include "sky/plate_passes.h"
#include "sky/plate_sweep.h"
#include "sky/pq_graphcut.h"
#include "sky/pq_store.h"
#include "sky/pq_window.h"
#include "sky/rank_share.h"
#include "sky/reproject.h"
#include "sky/seam_sources.h"
#include "sky/toast_output.h"
#include "sphere/vec3.h"

namespace gdp {
namespace {

constexpr double kMaxPqPixels = double(1 << 30);  // about 20 GiB of scratch
constexpr double kSkySquareDegrees = 4.0 * M_PI * (180.0 / M_PI) * (180.0 / M_PI);

struct TargetGrid {
  std::string cards, name;
  int width = 0, height = 0;
};

// The output image's grid: the header template, --center/--size/--scale/--projection, or, for
// projection HPX without a size, the whole sky on the HEALPix pixels of --scale or of the order
// the plates support (as the HiPS's deepest pixels), in the plates' frame `longitude`.
TargetGrid target_grid(const SkyTarget& t, const std::string& longitude, int pq_height) {
  TargetGrid g;
  if (!t.header.empty()) {
    g.name = t.header.string();
    g.cards = sky::read_header_template(t.header);
    const auto w = sky::header_number(g.cards, "NAXIS1"), h = sky::header_number(g.cards, "NAXIS2");
    if (!w || !h || *w < 1 || *h < 1) throw InputError(fmt::format("{}: no positive NAXIS1 and NAXIS2", g.name));
    g.width = static_cast<int>(*w);
    g.height = static_cast<int>(*h);
    return g;
  }
  if (t.projection == "HPX" && t.width == 0 && t.height == 0) {
    const int order = t.scale > 0.0 ? sky::hpx_order_for_scale(t.scale) : sky::hips_pixel_order(pq_height);
    g.name = fmt::format("the whole sky in HPX (HEALPix order {})", order);
    g.cards = sky::hpx_grid_header(order, longitude);
    g.width = g.height = 5 << order;
    return g;
  }
  if (t.width < 1 || t.height < 1 || !(t.scale > 0.0))
    throw UsageError("gdp sky needs --header, --center with --size W,H and --scale (degrees per pixel) > 0, or "
                     "--projection HPX alone (the whole sky)");
  g.name = "the target (--center, --size, --scale, --projection)";
  g.cards = sky::target_header(t);
  g.width = t.width;
  g.height = t.height;
  return g;
}

// True when some of a 33 x 33 grid of the target's points lies in a plate's footprint.
bool target_reached(const sky::Wcs& target, const std::vector<sky::Plate>& plates) {
  for (int a = 0; a <= 32; ++a)
    for (int b = 0; b <= 32; ++b) {
      double lon = 0, lat = 0;
      if (!target.pixel_to_sky(target.width() * a / 32.0, target.height() * b / 32.0, lon, lat)) continue;
      const sphere::Vec3 d = sky::direction(lon, lat);
      for (const sky::Plate& p : plates)
        if (sphere::dot(d, p.centre) >= p.cos_radius) return true;
    }
  return false;
}

double finest_scale(const std::vector<sky::Plate>& plates) {
  double finest = plates.front().scale;
  for (const sky::Plate& p : plates) finest = std::min(finest, p.scale);
  return finest;
}

// The PQ height whose mean pixel has half the area of the finest plate's pixel (H = m * 2^k,
// even): TOAST pixels differ in area by up to 2.1 (docs/sphere.md), so the largest are about as
// fine as the plate and the two resamplings (plate -> PQ -> target) lose no more than one does
// (docs/sky.md: seam measure and star fluxes against the PQ's size).
int pq_height_for(const std::vector<sky::Plate>& plates) {
  const double finest = finest_scale(plates);
  const double pixels = std::min(4e18, std::ceil(2.0 * kSkySquareDegrees / (finest * finest)));
  return sphere::default_pq_height(static_cast<long long>(pixels));
}

// The PQ height: --pq-height or the finest plate's scale; for TOAST rounded up to 128 * 2^n.
int choose_pq_height(const std::vector<sky::Plate>& plates, const SkyOptions& options) {
  int H = options.pq_height > 0 ? options.pq_height : pq_height_for(plates);
  if (!options.toast.empty()) {
    if (options.pq_height > 0 && sky::toast_height(H) != H)
      throw UsageError(fmt::format("--toast needs --pq-height 128 * 2^n, not {}", H));
    std::error_code ec;
    if (std::filesystem::exists(options.toast, ec) && !std::filesystem::is_empty(options.toast, ec))
      throw UsageError(options.toast.string() + ": exists and is not an empty directory");
    H = sky::toast_height(H);
  }
  if (H % 2 != 0) throw UsageError(fmt::format("--pq-height {} must be even", H));
  return H;
}

// --seams-from: the plates whose stars place the seams, one per plate and on its grid (their
// headers: their pixels are read with the plates', plate_sweep.h).
std::vector<sky::Plate> seam_plates(const std::vector<sky::Plate>& plates, const std::vector<std::string>& paths,
                                    const SkyOptions& options) {
  if (options.seam_plates.empty()) return {};
  if (options.seam_plates.size() != plates.size())
    throw UsageError(fmt::format("--seams-from takes one plate per plate: {} for {}", options.seam_plates.size(),
                                 plates.size()));
  std::vector<sky::Plate> out;
  for (std::size_t k = 0; k < plates.size(); ++k) {
    out.push_back(sky::open_plate(options.seam_plates[k], options.plane));
    if (out[k].width != plates[k].width || out[k].height != plates[k].height)
      throw InputError(fmt::format("{}: {} x {} pixels, but {} is {} x {}; --seams-from takes plates on the same grids",
                                   options.seam_plates[k], out[k].width, out[k].height, paths[k], plates[k].width,
                                   plates[k].height));
  }
  return out;
}

// gdp sky's own scratch (PQ store, coverage, overlap samples) in memory up to 8 MiB, or less as --memory says (0: files).
std::size_t scratch_limit(const SolverOptions& solver) { return std::min(sky::kSmallScratch, solver.scratch_memory); }

// The passes before the solve (docs/sky.md): the stars the seams go around, the plates' smooth
// backgrounds off (with a note), the levels and edges of their extensions; the plates' pixels
// read a few at a time (plate_passes.h).
std::optional<sky::SeamSources> take_in_plates(std::vector<sky::Plate>& plates, sky::PlatePixels& pixels,
                                               const sky::PlateShare& share, const std::vector<std::string>& paths,
                                               const SkyOptions& options, const SolverOptions& solver, SkySummary& s) {
  sky::IntakeOptions o;
  o.star_seams = options.star_seams;
  o.fit_backgrounds = options.fit_backgrounds && options.blend;
  o.damping = options.background_damping;
  o.temp_dir = solver.temp_dir;
  o.memory_limit = scratch_limit(solver);
  sky::PlateIntake in = sky::take_in_plates(plates, pixels, o, share);
  if (in.stars && options.note) options.note(fmt::format("{} star(s) in the overlaps kept whole by the seams", in.stars->size()));
  for (std::size_t k = 0; k < in.backgrounds.size(); ++k) {
    const sky::PlateBackground& b = in.backgrounds[k];
    s.backgrounds.push_back({b.offset, b.slope_u, b.slope_v, b.radial});
    s.background_rms.push_back(sky::smooth_rms(plates[k], b));
  }
  if (!in.backgrounds.empty() && options.note) options.note(sky::backgrounds_note(paths, s.background_rms));
  return std::move(in.stars);
}

// A rank's solved rows on their way to rank 0 (MpiRun::gather_writer), with their coverage as a
// second channel (MosaicRows::coverage_row: the label of the plate a pixel lies inside, 0 where
// none), which each rank has for the columns it computed only.
class WithCoverage final : public RowWriter {
 public:
  WithCoverage(const sky::MosaicRows& rows, std::unique_ptr<RowWriter> out)
      : rows_(rows), out_(std::move(out)), row_(2 * static_cast<std::size_t>(rows.window().width)) {}
  void set_columns(int begin, int end) override { out_->set_columns(begin, end); }
  void write_row(int y, std::span<const float> row) override {
    const std::size_t w = row_.size() / 2;
    std::copy(row.begin(), row.begin() + w, row_.begin());
    rows_.coverage_row(y, std::span(row_).subspan(w));
    out_->write_row(y, row_);
  }
  void commit() override { out_->commit(); }

 private:
  const sky::MosaicRows& rows_;
  std::unique_ptr<RowWriter> out_;
  std::vector<float> row_;
};

// Rank 0's rows (value and coverage, WithCoverage) into the PQ store, blank where no plate is
// (extensions and the unknown region are no sky), counting each plate's pixels.
class MaskedPqWriter final : public RowWriter {
 public:
  MaskedPqWriter(sky::PqStore& store, std::vector<long long>& chosen)
      : store_(store), chosen_(chosen), row_(store.window().width) {}
  void write_row(int y, std::span<const float> row) override {
    const std::size_t w = row_.size();
    for (std::size_t i = 0; i < w; ++i) {
      const float label = row[w + i];
      row_[i] = label > 0.0f ? row[i] : std::numeric_limits<float>::quiet_NaN();
      if (label > 0.0f) ++chosen_[static_cast<std::size_t>(label) - 2];
    }
    store_.write_row(y, row_);
  }

 private:
  sky::PqStore& store_;
  std::vector<long long>& chosen_;
  std::vector<float> row_;
};

// --seams graphcut on `win`: rank 0 cuts (a cut spans the window), the others wait and take its
// labels (blend/seam_share.h), as gdp blend does.
std::unique_ptr<blending::LabelPlane> graphcut_seams(std::vector<sky::Plate>& plates, sky::PlatePixels& pixels,
                                                     const sky::PqWindow& win, const sky::SeamSources* stars,
                                                     const SkyOptions& options, const SolverOptions& solver,
                                                     SkySummary& s) {
  if (MpiRun::rank() != 0) {
    auto labels = std::make_unique<blending::LabelPlane>(solver.temp_dir, win.width, win.rows);
    blending::share_labels(*labels);
    return labels;
  }
  sky::PqSeams cut = sky::graphcut_pq_seams(plates, pixels, win, stars, solver.temp_dir, scratch_limit(solver));
  s.seam_cost_depth = cut.depth_cost;
  s.seam_cost = cut.cost;
  if (options.note)
    options.note(fmt::format("graph-cut seams: cost {:.6g} ({:.3g} of the distance seams' {:.6g})", cut.cost,
                             cut.depth_cost > 0 ? cut.cost / cut.depth_cost : 1.0, cut.depth_cost));
  blending::share_labels(*cut.labels);
  return std::move(cut.labels);
}

// The seamed mosaic on `win`, solved unless options.blend is off, into `store` (NaN where no
// plate is). Under mpirun every rank solves its columns, computing the mosaic rows over those
// and their halo only where the solve says which (a planar window), and rank 0 gathers the rows
// and their coverage into its store (the others' stay empty: they write no output).
void solve_pq(std::vector<sky::Plate>& plates, sky::PlatePixels& pixels, sky::PqStore& store, const SkyOptions& options,
              SolverOptions solver, const std::optional<sky::SeamSources>& stars, const std::vector<std::string>& paths,
              SkySummary& s) {
  const sky::PqWindow& win = store.window();
  const sky::SeamSources* star_disks = stars ? &*stars : nullptr;
  const auto cut = options.graphcut_seams ? graphcut_seams(plates, pixels, win, star_disks, options, solver, s) : nullptr;
  sky::MosaicRows rows(plates, pixels, win, star_disks, solver.temp_dir, scratch_limit(solver));
  rows.use_seams(cut.get());
  std::vector<long long> chosen(plates.size(), 0);  // rank 0's: every rank's columns
  const auto pq_rows = std::make_unique<WithCoverage>(
      rows, MpiRun::gather_writer([&] { return std::make_unique<MaskedPqWriter>(store, chosen); }, win.width, win.rows, 2));
  if (options.blend) {
    solver.domain = win.whole() ? Domain::Spherical : Domain::Planar;
    StitchOptions stitch_options;
    stitch_options.unknown = UnknownMode::Harmonic;
    stitch_options.across = &rows.across();  // seams: the mean of both plates' gradients
    stitch(rows.composite(), rows.labels(), stitch_options, solver, *pq_rows, &s.solve);
  } else {
    std::vector<float> row(win.width);
    for (int j = 0; j < win.rows; ++j) {
      rows.composite().read_row(j, row);
      pq_rows->write_row(j, row);
    }
  }
  pq_rows->commit();
  for (std::size_t k = 0; k < plates.size() && MpiRun::rank() == 0; ++k)
    if (chosen[k] == 0 && options.note)
      options.note(fmt::format("{}: not used (other plates lie deeper everywhere it reaches)", paths[k]));
  s.plate_pixels = chosen;
  s.mosaic_pixels = rows.pixels_computed();
}

// The HiPS's tile width and the properties' obs_description and prov_progenitor (the plates' names).
sky::HipsOptions hips_options(const std::vector<std::string>& paths, const SkyOptions& options) {
  sky::HipsOptions h;
  h.tile_width = options.hips_tile;
  h.description = fmt::format("{} FITS plate(s) reprojected onto a PQ sphere of the sky and blended there in the "
                              "gradient domain (gdp sky): each plate's structure kept, background differences removed",
                              paths.size());
  for (std::size_t k = 0; k < paths.size() && k < 20; ++k)
    h.progenitor += (k ? ", " : "") + std::filesystem::path(paths[k]).filename().string();
  if (paths.size() > 20) h.progenitor += fmt::format(" and {} more", paths.size() - 20);
  return h;
}

bool target_given(const SkyTarget& t) {
  return !t.header.empty() || t.lon != 0.0 || t.lat != 0.0 || t.width > 0 || t.height > 0 || t.scale > 0.0 ||
         t.projection != SkyTarget{}.projection;
}

}  // namespace

void sky_mosaic(const std::vector<std::string>& paths, const SkyOptions& options, SolverOptions solver,
                const std::filesystem::path& out, WriteOptions write, SkySummary* summary) {
  if (paths.empty()) throw UsageError("gdp sky needs at least one plate");
  if (out.empty() && options.hips.empty() && options.toast.empty())
    throw UsageError("gdp sky needs an output: -o IMAGE, --hips DIR or --toast DIR");
  if (out.empty() && target_given(options.target))
    throw UsageError("--header, --center, --size, --scale and --projection describe the -o image: give -o");
  const auto note = [&](const std::string& m) { if (options.note) options.note(m); };
  std::vector<sky::Plate> plates;
  for (const std::string& path : paths) {
    plates.push_back(sky::open_plate(path, options.plane));
    if (plates.back().planes > 1)
      note(fmt::format("{}: {} planes; plane {} taken (--plane)", path, plates.back().planes, options.plane + 1));
  }
  const int H = choose_pq_height(plates, options);
  // The frame every plate must share: the target's, else the first plate's.
  std::optional<TargetGrid> grid;
  std::unique_ptr<sky::Wcs> target;
  std::string frame = plates.front().wcs->frame(), frame_of = paths.front();
  if (!out.empty()) {
    grid = target_grid(options.target, frame, H);
    target = std::make_unique<sky::Wcs>(grid->cards, grid->width, grid->height, grid->name);
    frame = target->frame();
    frame_of = "the target";
  }
  for (std::size_t k = 0; k < plates.size(); ++k)
    if (plates[k].wcs->frame() != frame)
      throw InputError(fmt::format("{}: longitude axis {} but {}'s is {}; gdp sky does not convert frames", paths[k],
                                   plates[k].wcs->frame(), frame_of, frame));
  if (target && !target_reached(*target, plates)) throw InputError(fmt::format("{}: no plate reaches the target", grid->name));
  if (!options.hips.empty()) sky::check_hips_output(options.hips, hips_options(paths, options), frame);
  // Plates covering a small part of the sky are solved on their PQ window (planar: it meets no
  // fold); TOAST output needs the whole sphere.
  const auto window = options.toast.empty() ? sky::plate_window(plates, H, sky::kExtension) : std::nullopt;
  const sky::PqWindow win = window ? *window : sky::whole_pq(H);
  // The PQ image (or window) streams through scratch (about 20 bytes a pixel with the solve's, on
  // disk when large; docs/sky.md, "Memory"): a sanity bound against absurd plate scales.
  if (double(win.width) * win.rows > kMaxPqPixels)
    throw UsageError(fmt::format("the finest plate scale ({:.3g} arcsec) needs {} x {} pixels of a PQ sphere of height "
                                 "{}; gdp sky takes at most {:.0f} Mpixels (about 20 bytes of scratch each): give a "
                                 "smaller --pq-height",
                                 finest_scale(plates) * 3600.0, win.width, win.rows, H, kMaxPqPixels / 1e6));
  // The plates' pixels come and go with the PQ rows (plate_sweep.h); --seams-from plates are
  // checked before anything is fitted or noted.
  std::vector<sky::Plate> finders = seam_plates(plates, paths, options);
  sky::PlatePixels pixels(plates, finders, win, sky::kReleaseLag);
  // Under mpirun each rank runs the passes for the plates whose centres lie in its share of the
  // columns, reading only those and their neighbours (plate_exchange.h).
  const sky::RankShare ranks([&](int n) { return sky::plate_owners(plates, win, n); });
  const sky::PlateShare& share = ranks.share();
  SkySummary s;
  const std::optional<sky::SeamSources> stars = take_in_plates(plates, pixels, share, paths, options, solver, s);
  s.pq_height = H;
  s.pq_window = {win.i0, win.j0, win.width, win.rows};
  sky::PqStore pq(win, solver.temp_dir, scratch_limit(solver));
  solve_pq(plates, pixels, pq, options, solver, stars, paths, s);
  s.plates_held = pixels.most_held();
  s.plates_crossing = pixels.most_crossing();
  s.plate_pixels_read = sky::counts_by_rank(share, pixels.pixels_read());
  for (std::size_t k = 0; k < plates.size(); ++k)
    s.plate_pixels_in_files += (finders.empty() ? 1LL : 2LL) * plates[k].width * plates[k].height;
  if (MpiRun::rank() != 0) return;  // rank 0 gathered the solve and writes the outputs
  if (!options.toast.empty()) sky::write_sky_toast(pq, options.toast);
  if (!options.hips.empty()) {
    const auto h = sky::write_sky_hips(pq, frame, options.hips, hips_options(paths, options));
    s.hips_order = h.order;
    s.hips_tiles = h.tiles;
    note(fmt::format("HiPS order {} ({} tiles of {} pixels there, {} in all) -> {}", h.order, h.deepest_tiles,
                     options.hips_tile, h.tiles, options.hips.string()));
  }
  if (target) {
    write.fits_header = grid->cards;
    ImageFileWriter writer(out, grid->width, grid->height, 1, write);
    s.covered = sky::reproject_pq(pq, *target, writer);
    if (s.covered == 0) throw InputError(fmt::format("{}: no plate reaches the target", grid->name));
    writer.commit();
    s.target_pixels = static_cast<long long>(grid->width) * grid->height;
  }
  if (summary) *summary = std::move(s);
}

}  // namespace gdp
