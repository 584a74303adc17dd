// The plate passes shared by ranks: which rank runs each plate's part, and the exchanges that give every rank the whole result.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bands/transport.h"
#include "sky/overlap_samples.h"
#include "sky/plate.h"
#include "sky/plate_backgrounds.h"
#include "sky/plate_offsets.h"
#include "sky/projected_levels.h"
#include "sky/seam_sources.h"

namespace gdp::sky {

// How the passes before the solve are shared (docs/sky.md, "Memory, bands and mpirun"): plate k's
// own part (its sources, stars, edge corrections, mean) and the pairs (k, q > k) are run by rank
// owners[k] only, which sweeps its plates and their neighbours; the exchanges below then give
// every rank every plate's results, in plate and pair order, so that all ranks end with the one
// process's bits. Default: one process (no transport, every plate its own).
struct PlateShare {
  bands::Transport* net = nullptr;
  std::vector<int> owners;  // per plate (plate_owners); empty: every plate rank 0's
  // Called on every rank with its error ("" when none) before each exchange: returns when no rank
  // has one, else throws the same error on every rank (gdp::MpiRun::agree), so none waits forever.
  std::function<void(const std::string&)> agree;

  int rank() const { return net ? net->rank() : 0; }
  int size() const { return net ? net->size() : 1; }
  bool owns(std::size_t k) const { return owners.empty() || owners[k] == rank(); }
  // Runs `step`; under several ranks its exception becomes the agreed error of all (agree).
  void run(const std::function<void()>& step) const;
};

// Every rank's detections of the plates it owns to every rank (`detections` indexed by plate).
void share_detections(const PlateShare& share, std::vector<std::vector<SourceDetection>>& detections);

// One pair's overlap samples, as a rank other than 0 sends them to rank 0 (gather_samples).
class SampleBlocks {
 public:
  void add(int a, int b, const std::vector<OverlapSample>& samples);
  schedule::Bytes take();  // the message: the count of blocks, then the blocks

 private:
  schedule::ByteWriter out_;
  std::size_t count_ = 0;
};

// Rank 0 gets every other rank's blocks (in rank order) through `add`; the others send `mine`.
void gather_samples(const PlateShare& share, SampleBlocks& mine,
                    const std::function<void(int a, int b, const std::vector<OverlapSample>&)>& add);

// Rank 0's fitted backgrounds and its count of samples fitted, to every rank.
void share_backgrounds(const PlateShare& share, std::vector<PlateBackground>& backgrounds, std::size_t& samples);

// Every owned plate's mean and edge corrections, and every owned pair's overlap sum, to every rank.
void share_levels(const PlateShare& share, std::vector<Plate>& plates, std::map<std::pair<int, int>, OverlapSum>& sums);

// Rank 0's fitted levels of gdp sky --projected's images, to every rank.
void share_canvas_levels(const PlateShare& share, CanvasLevels& levels);

// Every rank's `mine`, in rank order, on every rank.
std::vector<long long> counts_by_rank(const PlateShare& share, long long mine);

}  // namespace gdp::sky
