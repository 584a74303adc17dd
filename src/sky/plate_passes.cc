// The plate passes before the solve as sweeps: stars and background equations, the fit, then levels and edges.
#include "sky/plate_passes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "blend/scratch.h"
#include "sky/overlap_samples.h"
#include "sky/plate_extension.h"
#include "sphere/vec3.h"
#include "sky/plate_offsets.h"

namespace gdp::sky {
namespace {

// The background fit's overlap samples, pair after pair, in scratch (in memory up to a limit,
// else an unlinked file), read back as equations in pair order for each pass of the fit.
class OverlapStore {
 public:
  OverlapStore(std::size_t capacity, const std::filesystem::path& dir, std::size_t limit)
      : scratch_(dir, capacity * sizeof(OverlapSample), "gdp-sky-overlaps", limit) {}

  void add(int a, int b, const std::vector<OverlapSample>& samples) {
    if (samples.empty()) return;
    scratch_.write(used_ * sizeof(OverlapSample), samples.data(), samples.size() * sizeof(OverlapSample));
    blocks_.push_back({a, b, used_, samples.size()});
    used_ += samples.size();
  }
  std::size_t size() const { return used_; }

  // Every sample's equation, pairs in (a, b) order (as plate_backgrounds gives them).
  void visit(const std::vector<Plate>& plates, const std::function<void(const BackgroundEquation&)>& f) {
    std::sort(blocks_.begin(), blocks_.end(), [](const Block& x, const Block& y) {
      return std::pair(x.a, x.b) < std::pair(y.a, y.b);
    });
    std::vector<OverlapSample> chunk;
    for (const Block& b : blocks_)
      for (std::size_t done = 0; done < b.count; done += chunk.size()) {
        chunk.resize(std::min<std::size_t>(4096, b.count - done));
        scratch_.read((b.first + done) * sizeof(OverlapSample), chunk.data(), chunk.size() * sizeof(OverlapSample));
        for (const OverlapSample& s : chunk) f(background_equation(plates[b.a], b.a, plates[b.b], b.b, s));
      }
  }

 private:
  struct Block {
    int a = 0, b = 0;
    std::size_t first = 0, count = 0;
  };
  blending::Scratch scratch_;
  std::vector<Block> blocks_;
  std::size_t used_ = 0;
};

bool rows_meet(const PlatePixels& pixels, std::size_t a, std::size_t b) {
  return pixels.rows(a)[0] <= pixels.rows(b)[1] && pixels.rows(b)[0] <= pixels.rows(a)[1];
}

// The most overlap samples the pairs can give (the store's size).
std::size_t sample_bound(const std::vector<Plate>& plates, const PlatePixels& pixels) {
  std::size_t n = 0;
  for (std::size_t a = 0; a < plates.size(); ++a)
    for (std::size_t b = a + 1; b < plates.size(); ++b)
      if (cones_meet(plates[a], plates[b]) && rows_meet(pixels, a, b)) n += overlap_sample_bound(plates[a]);
  return n;
}

// Each overlapping pair (lower index first) among plate k and `others`, all held: f(a, b).
template <class F>
void each_pair(const std::vector<Plate>& plates, std::size_t k, const std::vector<std::size_t>& others, F&& f) {
  for (const std::size_t q : others) {
    const std::size_t a = std::min(k, q), b = std::max(k, q);
    if (cones_meet(plates[a], plates[b])) f(a, b);
  }
}

// Pass 3's work on plate k (held, backgrounds off): its edge corrections and the overlap sums
// with the plates held with it (those this rank owns); the plate's mean was set as it was read.
void level_plate(std::vector<Plate>& plates, std::size_t k, const std::vector<std::size_t>& others,
                 const std::vector<std::vector<PlateSource>>& sources, std::map<std::pair<int, int>, OverlapSum>& sums,
                 const PlateShare& share) {
  if (share.owns(k)) plates[k].edge_correction = edge_corrections(plates[k], sources[k]);
  each_pair(plates, k, others, [&](std::size_t a, std::size_t b) {
    if (!share.owns(a)) return;
    const OverlapSum o = overlap_sum(plates[a], static_cast<int>(a), plates[b], static_cast<int>(b));
    if (o.n > 0) sums[{o.a, o.b}] = o;
  });
}

// Plate k's stars on the sphere, and the reach of every held plate over them and of k over theirs.
void detect_stars(const PlatePixels& pixels, std::size_t k, const std::vector<std::size_t>& others,
                  const std::vector<PlateSource>& sources, std::vector<std::vector<SourceDetection>>& detections) {
  detections[k] = source_detections(pixels.finder(k), sources);
  for (SourceDetection& d : detections[k]) add_reach(d, pixels.finder(k), static_cast<int>(k));
  for (const std::size_t q : others) {
    for (SourceDetection& d : detections[k]) add_reach(d, pixels.finder(q), static_cast<int>(q));
    for (SourceDetection& d : detections[q]) add_reach(d, pixels.finder(k), static_cast<int>(k));
  }
}

// A star of plate k's finder (radius at most max(2, min(32, size / 8)) + 1 of its pixels, seam_sources.h)
// may be reached by plate q (add_reach) only if their centres lie within this angle (radians):
// both footprints' cones and twice that radius.
double star_reach(const Plate& k, const Plate& q) {
  const double radius = std::max(2.0, std::min(32.0, std::min(k.width, k.height) / 8.0)) + 1.0;
  return std::acos(std::clamp(k.cos_radius, -1.0, 1.0)) + std::acos(std::clamp(q.cos_radius, -1.0, 1.0)) +
         2.0 * radius * k.scale * M_PI / 180.0;
}

// The plates this rank sweeps (empty: every plate, one process): those it owns and every plate
// whose rows meet theirs and that could share a point or reach a star with one (cones_meet,
// star_reach), so that its plates' pairs and stars see every plate they would see in one process.
std::vector<char> swept_plates(const std::vector<Plate>& plates, const PlatePixels& pixels, const PlateShare& share) {
  if (share.size() == 1) return {};
  std::vector<char> swept(plates.size(), 0);
  for (std::size_t k = 0; k < plates.size(); ++k) {
    if (!share.owns(k)) continue;
    swept[k] = 1;
    for (std::size_t q = 0; q < plates.size(); ++q) {
      if (swept[q] || !rows_meet(pixels, k, q)) continue;
      const Plate &fk = pixels.finder(k), &fq = pixels.finder(q);
      const double apart = sphere::angle(fk.centre, fq.centre);
      if (cones_meet(plates[k], plates[q]) || apart <= star_reach(fk, fq) || apart <= star_reach(fq, fk)) swept[q] = 1;
    }
  }
  return swept;
}

}  // namespace

PlateIntake take_in_plates(std::vector<Plate>& plates, PlatePixels& pixels, const IntakeOptions& options,
                           const PlateShare& share) {
  const std::size_t n = plates.size();
  PlateIntake out;
  std::vector<std::vector<PlateSource>> sources(n);
  std::vector<std::vector<SourceDetection>> detections(n);
  std::map<std::pair<int, int>, OverlapSum> sums;
  const bool gathers = options.fit_backgrounds && share.rank() == 0;  // rank 0 fits every pair's samples
  OverlapStore store(gathers ? sample_bound(plates, pixels) : 0, options.temp_dir, options.memory_limit);
  SampleBlocks outgoing;  // the other ranks' samples, for rank 0
  const std::vector<char> swept = swept_plates(plates, pixels, share);
  share.run([&] {
    pixels.sweep([&](std::size_t k, const std::vector<std::size_t>& others) {
      if (share.owns(k)) sources[k] = plate_sources(pixels.finder(k));  // no sources: no stars of k here
      if (options.star_seams) detect_stars(pixels, k, others, sources[k], detections);
      if (!options.fit_backgrounds) return level_plate(plates, k, others, sources, sums, share);
      each_pair(plates, k, others, [&](std::size_t a, std::size_t b) {
        if (!share.owns(a)) return;
        const auto samples = overlap_samples(plates[a], plates[b]);
        if (gathers) store.add(static_cast<int>(a), static_cast<int>(b), samples);
        else if (!samples.empty()) outgoing.add(static_cast<int>(a), static_cast<int>(b), samples);
      });
    }, swept);
  });
  if (options.star_seams) {
    share_detections(share, detections);
    std::vector<int> sizes;
    std::vector<double> scales;
    for (std::size_t k = 0; k < n; ++k) {
      sizes.insert(sizes.end(), {pixels.finder(k).width, pixels.finder(k).height});
      scales.push_back(pixels.finder(k).scale);
    }
    out.stars.emplace(detections, sizes, scales);
  }
  if (options.fit_backgrounds) {
    gather_samples(share, outgoing, [&](int a, int b, const auto& samples) { store.add(a, b, samples); });
    share.run([&] {
      if (!gathers) return;
      std::vector<std::array<double, 4>> energy;
      for (const Plate& p : plates) energy.push_back(background_energy(p));
      out.overlap_samples = store.size();
      out.backgrounds = fit_backgrounds(energy, [&](const auto& visit) { store.visit(plates, visit); }, options.damping);
    });
    share_backgrounds(share, out.backgrounds, out.overlap_samples);
    pixels.set_backgrounds(out.backgrounds);
    share.run([&] {
      pixels.sweep([&](std::size_t k, const std::vector<std::size_t>& others) {
        level_plate(plates, k, others, sources, sums, share);
      }, swept);
    });
  }
  share_levels(share, plates, sums);
  std::vector<OverlapSum> pairs;
  for (const auto& [ab, o] : sums) pairs.push_back(o);
  set_fade_levels(plates, offsets_from_overlaps(n, pairs));
  return out;
}

}  // namespace gdp::sky
