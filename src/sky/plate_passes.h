// The passes over the plates before the solve (stars, background fit, extension levels) as sweeps over the PQ rows.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include "sky/plate.h"
#include "sky/plate_backgrounds.h"
#include "sky/plate_exchange.h"
#include "sky/plate_sweep.h"
#include "sky/seam_sources.h"

namespace gdp::sky {

struct IntakeOptions {
  bool star_seams = true;       // find the stars the seams go around
  bool fit_backgrounds = true;  // fit and take off the smooth backgrounds
  double damping = 1e-3;        // fit_backgrounds' damping
  std::filesystem::path temp_dir;  // the overlap samples go there beyond `memory_limit` bytes
  std::size_t memory_limit = 0;
};

struct PlateIntake {
  std::optional<SeamSources> stars;          // with star_seams
  std::vector<PlateBackground> backgrounds;  // with fit_backgrounds: per plate, taken off
  std::size_t overlap_samples = 0;           // background equations (overlap samples) fitted
};

// What gdp sky does to the plates before the solve, holding only the plates' pixels that the
// current PQ rows reach (`pixels.sweep`; docs/sky.md, "Memory, bands and mpirun"):
//  1. a sweep over the raw plates: each plate's compact sources (plate_sources of its finder),
//     the stars' reaching plates (SourceDetection), and the background equations of each
//     overlapping pair (into scratch: 40 bytes a sample, about 64 x 64 samples of a plate per
//     pair at most);
//  2. the stars (SeamSources) and the robust background fit (fit_backgrounds over the stored
//     equations), then `pixels` takes the backgrounds off every plate read after;
//  3. a sweep over the corrected plates: their means, edge corrections (plate_extension.h) and
//     the overlap sums of the levels (plate_offsets.h), then every plate's fade level.
// Without a background fit, passes 1 and 3 are one sweep. Pairs and detections are visited in
// plate order, so the results are those of the plates held whole. Shared by ranks (`share`), each
// sweeps only the plates it owns and their neighbours, runs the owned plates' and pairs' parts,
// and the exchanges (plate_exchange.h: rank 0 fits every pair's samples) leave every rank with
// the one process's results, bit for bit.
PlateIntake take_in_plates(std::vector<Plate>& plates, PlatePixels& pixels, const IntakeOptions& options,
                           const PlateShare& share = {});

}  // namespace gdp::sky
