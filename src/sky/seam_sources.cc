// Stars for the seam rule: detected in each plate (curvature peaks), merged on the sphere, each given to one plate.
#include "sky/seam_sources.h"

#include <algorithm>
#include <cmath>

#include "sky/seams.h"
#include "sphere/vec3.h"

namespace gdp::sky {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kFlat = 1e-3;           // a ray ends where the profile falls by less than this of its drop
constexpr std::size_t kSpreadSamples = 1 << 20;  // curvature values the robust spread is taken from

// The value less the mean of its 8 neighbours; NaN where any is blank or off the plate.
double curvature(const Plate& p, int x, int y) {
  if (x < 1 || y < 1 || x + 1 >= p.width || y + 1 >= p.height) return NAN;
  double sum = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (dx || dy) sum += p.pixels[static_cast<std::size_t>(y + dy) * p.width + x + dx];
  return p.pixels[static_cast<std::size_t>(y) * p.width + x] - sum / 8.0;
}

// 1.4826 x the median absolute deviation of the plate's curvature (on at most kSpreadSamples pixels).
double curvature_spread(const Plate& p) {
  const std::size_t n = static_cast<std::size_t>(p.width) * p.height;
  const std::size_t stride = std::max<std::size_t>(1, n / kSpreadSamples);
  std::vector<double> c;
  for (std::size_t k = 0; k < n; k += stride) {
    const double v = curvature(p, static_cast<int>(k % p.width), static_cast<int>(k / p.width));
    if (std::isfinite(v)) c.push_back(v);
  }
  if (c.empty()) return 0.0;
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const double m = median(c);
  for (double& v : c) v = std::abs(v - m);
  return 1.4826 * median(c);
}

// Whether (x, y) is a local maximum (ties go to the first in raster order).
bool local_maximum(const Plate& p, int x, int y) {
  const float v = p.pixels[static_cast<std::size_t>(y) * p.width + x];
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float n = p.pixels[static_cast<std::size_t>(y + dy) * p.width + x + dx];
      const bool before = dy < 0 || (dy == 0 && dx < 0);
      if ((dx || dy) && (n > v || (before && n == v))) return false;
    }
  return true;
}

// The value at (x, y), NaN off the plate.
double value_at(const Plate& p, int x, int y) {
  if (x < 0 || y < 0 || x >= p.width || y >= p.height) return NAN;
  return p.pixels[static_cast<std::size_t>(y) * p.width + x];
}

// Along 4 lines through the peak (the axes and diagonals), the mean of both sides at distance d
// (a linear sky cancels) until it stops falling by more than kFlat of its drop from the peak per
// pixel, or, past its steepest point, falls faster again (the sky's curvature or noise taking
// over); the median of the 4 distances, plus one pixel, at most `cap`.
double source_radius(const Plate& p, int x, int y, double cap) {
  const double peak = value_at(p, x, y);
  const int lines[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  double lengths[4];
  for (int l = 0; l < 4; ++l) {
    const int dx = lines[l][0], dy = lines[l][1];
    const double step = std::hypot(dx, dy);
    double prev = peak, prev_fall = 0.0;
    bool shrinking = false;  // past the steepest point
    int d = 1;
    for (; d * step < cap; ++d) {
      const double mean = 0.5 * (value_at(p, x + d * dx, y + d * dy) + value_at(p, x - d * dx, y - d * dy));
      const double fall = prev - mean;
      // Flat, or falling faster again: the sky's curvature (or noise) outweighs the star's slope.
      if (!std::isfinite(mean) || fall <= kFlat * (peak - mean) || (shrinking && fall > prev_fall)) break;
      shrinking = shrinking || fall < prev_fall;
      prev = mean;
      prev_fall = fall;
    }
    lengths[l] = d * step;
  }
  std::sort(lengths, lengths + 4);
  return std::min(cap, 0.5 * (lengths[1] + lengths[2]) + 1.0);
}

}  // namespace

std::vector<PlateSource> plate_sources(const Plate& plate, double threshold) {
  std::vector<PlateSource> out;
  const double floor = threshold * curvature_spread(plate);
  const double cap = std::max(2.0, std::min(32.0, std::min(plate.width, plate.height) / 8.0));
  for (int y = 1; y + 1 < plate.height; ++y)
    for (int x = 1; x + 1 < plate.width; ++x) {
      const double c = curvature(plate, x, y);
      if (!(c > floor) || !(c > 0.0) || !local_maximum(plate, x, y)) continue;
      out.push_back({x, y, source_radius(plate, x, y, cap)});
    }
  return out;
}

std::vector<SourceDetection> source_detections(const Plate& plate, const std::vector<PlateSource>& sources) {
  std::vector<SourceDetection> out;
  for (const PlateSource& s : sources) {
    double lon = 0, lat = 0;
    if (plate.wcs->pixel_to_sky(s.x + 0.5, s.y + 0.5, lon, lat))
      out.push_back({direction(lon, lat), s.radius * plate.scale * kDeg, {}});
  }
  return out;
}

void add_reach(SourceDetection& d, const Plate& p, int k) {
  double lon = 0, lat = 0, x = 0, y = 0;
  lon_lat(d.centre, lon, lat);
  if (sphere::dot(d.centre, p.centre) < p.cos_reach || !p.wcs->sky_to_pixel(lon, lat, x, y)) return;
  if (depth_inside(x, y, p.width, p.height) <= -d.radius / (p.scale * kDeg)) return;
  d.hits.push_back({k, x, y, p.has_value(x, y)});
}

namespace {

// The plate a source goes to: the valid plate deepest at its centre, when at least two plates
// reach within its radius (else plate -1: no seam can cut it); `room`: how far a disk grown for
// a neighbour may reach and stay inside that plate with 2 of its pixels to spare (its edge pixels
// are resampled bilinearly and its extension beyond them is no sky), in radians.
struct Owner {
  int plate = -1;
  double room = 0.0;
};

Owner source_plate(const SourceDetection& d, const std::vector<int>& sizes, const std::vector<double>& scales) {
  if (d.hits.size() < 2) return {};
  std::vector<PlateHit> hits = d.hits;
  std::sort(hits.begin(), hits.end(), [](const PlateHit& a, const PlateHit& b) { return a.plate < b.plate; });
  const int best = choose_plate(hits, sizes);
  if (best < 0) return {};
  const PlateHit& h = hits[best];
  const double depth = depth_inside(h.x, h.y, sizes[2 * h.plate], sizes[2 * h.plate + 1]);
  return {h.plate, (depth - 2.0) * scales[h.plate] * kDeg};
}

}  // namespace

SeamSources::SeamSources(const std::vector<std::vector<SourceDetection>>& detections, const std::vector<int>& sizes,
                         const std::vector<double>& scales) {
  // Every plate's sources, largest first (plate order, then the plate's, among equals).
  std::vector<const SourceDetection*> all;
  for (const auto& plate : detections)
    for (const SourceDetection& d : plate) all.push_back(&d);
  std::stable_sort(all.begin(), all.end(), [](const SourceDetection* a, const SourceDetection* b) {
    return a->radius > b->radius;
  });
  if (all.empty()) return;
  // Chords are shorter than angles; a kept disk grows to hold the smaller ones inside it, to at
  // most twice the largest radius.
  cell_ = 2.0 * all.front()->radius * 1.001;
  for (const SourceDetection* s : all) {
    if (const int n = find(s->centre); n >= 0) {
      Source& kept = sources_[n];
      const double apart = std::acos(std::min(1.0, sphere::dot(s->centre, kept.centre)));
      if (apart < 0.3 * s->radius) continue;  // the same star in another plate
      // A neighbour: the disk grows to hold it whole; where that no longer fits inside its plate,
      // the pair keeps the plain rule (a seam along the plate's edge would cut the neighbour).
      const double reach = apart + s->radius;
      kept.cos_radius = std::min(kept.cos_radius, std::cos(std::min(reach, 2.0 * all.front()->radius)));
      if (reach > kept.room) kept.plate = -1;
      continue;
    }
    const Owner owner = source_plate(*s, sizes, scales);
    if (owner.plate >= 0) insert({s->centre, std::cos(s->radius), owner.plate, owner.room});
  }
}

void SeamSources::cell_of(const sphere::Vec3& d, long long c[3]) const {
  c[0] = static_cast<long long>(std::floor(d.x / cell_));
  c[1] = static_cast<long long>(std::floor(d.y / cell_));
  c[2] = static_cast<long long>(std::floor(d.z / cell_));
}

long long SeamSources::cell_key(long long i, long long j, long long k) const {
  return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);  // collisions only cost distance checks
}

void SeamSources::insert(const Source& s) {
  long long c[3];
  cell_of(s.centre, c);
  cells_[cell_key(c[0], c[1], c[2])].push_back(static_cast<int>(sources_.size()));
  sources_.push_back(s);
}

int SeamSources::find(const sphere::Vec3& d) const {
  if (sources_.empty()) return -1;
  long long c[3];
  cell_of(d, c);
  int best = -1;
  double nearest = -2.0;
  for (long long i = c[0] - 1; i <= c[0] + 1; ++i)
    for (long long j = c[1] - 1; j <= c[1] + 1; ++j)
      for (long long k = c[2] - 1; k <= c[2] + 1; ++k) {
        const auto it = cells_.find(cell_key(i, j, k));
        if (it == cells_.end()) continue;
        for (const int n : it->second) {
          const double cosine = sphere::dot(d, sources_[n].centre);
          if (cosine >= sources_[n].cos_radius && cosine > nearest) {
            best = n;
            nearest = cosine;
          }
        }
      }
  return best;
}

int SeamSources::plate_at(const sphere::Vec3& d) const {
  const int n = find(d);
  return n < 0 ? -1 : sources_[n].plate;
}

}  // namespace gdp::sky
