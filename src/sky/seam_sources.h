// Compact sources (stars) in the plates' overlaps, each given wholly to one plate so that no seam cuts it.
#pragma once

#include <unordered_map>
#include <vector>

#include "gdp/sphere.h"
#include "sky/plate.h"
#include "sky/seams.h"

namespace gdp::sky {

// A compact bright source of one plate, in plate pixels: its peak and the radius beyond which
// its profile is flat (docs/sky.md, "Seams around stars").
struct PlateSource {
  int x = 0, y = 0;
  double radius = 0.0;
};

// The sources of a plate: local maxima whose curvature (the value less the mean of its 8
// neighbours) exceeds `threshold` times the plate's robust spread of that curvature (1.4826 x
// its median absolute deviation), each with its radius: along 4 lines through the peak, where
// the mean of both sides (a linear sky cancels) stops falling by more than 1e-3 of its drop from
// the peak per pixel or, past its steepest point, falls faster again (a curved sky, noise); the
// median of the 4, plus one pixel, at most max(2, min(32, plate size / 8)) pixels.
std::vector<PlateSource> plate_sources(const Plate& plate, double threshold = 20.0);

// A plate's source on the sphere, and the plates reaching within its radius of its centre (their
// hits there: pixel coordinates and whether the plate has a value), gathered while their pixels
// are held (plate_sweep.h: every such plate crosses the source's PQ row).
struct SourceDetection {
  sphere::Vec3 centre;
  double radius = 0.0;         // radians
  std::vector<PlateHit> hits;  // any order (SeamSources sorts them by plate)
};

// A plate's sources (plate_sources of it) on the sphere, by its WCS; no hits yet.
std::vector<SourceDetection> source_detections(const Plate& plate, const std::vector<PlateSource>& sources);

// Adds plate k's hit at d's centre when the plate (with its pixels) reaches within d's radius.
void add_reach(SourceDetection& d, const Plate& plate, int k);

// The sources of all plates that lie in overlaps (within their radius of two plates), merged
// (largest first; a source whose centre lies in a kept disk widens that disk to hold it whole:
// the same star seen by another plate, or a close neighbour), each assigned the plate it lies
// deepest inside at its centre (a disk widened for a neighbour: only if it still fits inside
// that plate with 2 pixels to spare, else none). plate_at(d) gives the plate of the source whose disk holds d (the
// nearest centre when several do), or -1; the seam rule then gives the whole disk to that plate,
// so that a star is never composed of two plates' resamplings (which differ at a star by a few
// percent of its peak, and the solve would spread that difference around it).
class SeamSources {
 public:
  // `detections`: per plate, its source_detections with every reaching plate's hit added;
  // `sizes`: each plate's width and height, {w0, h0, w1, h1, ...}; `scales`: degrees per pixel.
  SeamSources(const std::vector<std::vector<SourceDetection>>& detections, const std::vector<int>& sizes,
              const std::vector<double>& scales);
  int plate_at(const sphere::Vec3& d) const;
  std::size_t size() const { return sources_.size(); }

 private:
  struct Source {
    sphere::Vec3 centre;
    double cos_radius = 1.0;
    int plate = -1;     // -1: a widened disk that does not fit in its plate; the plain rule there
    double room = 0.0;  // how far a widened disk may reach inside its plate (radians)
  };
  long long cell_key(long long i, long long j, long long k) const;
  void cell_of(const sphere::Vec3& d, long long c[3]) const;
  void insert(const Source& s);
  // Index of the source whose disk holds d with the nearest centre, or -1.
  int find(const sphere::Vec3& d) const;

  std::vector<Source> sources_;
  double cell_ = 1.0;  // of the hash grid over unit vectors: at least every disk's chord radius
  std::unordered_map<long long, std::vector<int>> cells_;
};

}  // namespace gdp::sky
