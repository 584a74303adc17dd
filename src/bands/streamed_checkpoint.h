// The streamed solve's checkpoint (docs/resume.md): one lane per worker (band, channel group) of this process.
#pragma once

#include <algorithm>
#include <iterator>
#include <vector>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bands/band_layout.h"
#include "bands/transport.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "bands/cycle_worker.h"

namespace gdp::bands {

// Lane numbers are global: band b's channel group g is lane b * groups + g, so that ranks sharing a
// directory never write the same files (each rank keeps its own manifest, rank 0's named
// "manifest"). The problem's sizes, the band count and the rank count are in every manifest: a
// resume with other counts is refused, naming them.
class StreamedCheckpoint {
 public:
  // In opt.checkpoint_dir (its group count replaces `groups` when resuming); scratch kept there
  // under each lane's names.
  template <class T>
  StreamedCheckpoint(const SolverOptions& opt, const multigrid::Operators<T>& ops, int channels, int bands, int local,
                     int first, int& groups, schedule::StorePolicy& stores)
      : first_(first), local_(local) {
    const std::string sizes = fmt::format("{} {} {} {} {} {} | {} bands on {} ranks", ops.levels[0].width,
                                          ops.levels[0].height, channels, ops.count(), sizeof(T),
                                          stores.half.any() ? "half" : "native", bands, MpiRun::size());
    int lanes = local * groups;
    cp_ = std::make_unique<io::Checkpoint>(opt, sizes, lanes, first * groups, MpiRun::rank(), lanes * MpiRun::size());
    if (lanes < 1 || lanes % local != 0)
      throw InputError(fmt::format("--resume {}: the manifest is corrupt (lanes)", opt.checkpoint_dir.string()));
    groups = groups_ = lanes / local;
    stores.keep_dir = opt.checkpoint_dir;
  }
  // Resuming: the bands of a plan go back to the newest save they all made (a kill may have come
  // between two bands' saves; none is two saves ahead, StreamedVCycle::saved). Under mpirun
  // (`net`: this rank's first band) the ranks' newest common save is agreed on through band 0.
  void agree(Transport* net) {
    if (!cp_->resuming()) return;
    for (int g = 0; g < groups_; ++g) {
      std::vector<long long> common = cp_->generations(lane(0, g));
      for (int i = 1; i < local_; ++i) common = intersect(common, cp_->generations(lane(i, g)));
      if (net) common = across_ranks(*net, common);
      for (int i = 0; i < local_; ++i) cp_->choose(lane(i, g), common.back());
    }
  }
  // Row stores of local band i's group g are named with this prefix.
  std::string prefix(int i, int g) const { return fmt::format("lane{}-", lane(i, g)); }
  // Local band i's group g (worker, V-cycle) saves here; when resuming, its
  // state is restored. Returns the input rows it already has.
  template <class T>
  int attach(CycleWorker<T>& worker, int i, int g, int width) {
    // A unit of the first pass stores about four times what a save writes (the rows held). The
    // bands of a plan must save at the same rows: theirs is a function of the plan, about four
    // times the rows its levels' rings hold (twice level 0's), not of the band.
    const BandLayout& plan = worker.vcycle.layout();
    const double row_bytes = 2.0 * worker.n * width * sizeof(T);
    const double rows_held = plan.single ? static_cast<double>(worker.vcycle.window_bytes()) / row_bytes
                                         : 2.0 * (4 * plan.phase_groups + 2 * plan.sweeps + 16);
    const int rows = static_cast<int>(std::min(1e9, 4.0 * rows_held));
    return worker.use_checkpoint(*cp_, lane(i, g), cp_->unit_rows(std::max(16, rows)));
  }

 private:
  int lane(int i, int g) const { return (first_ + i) * groups_ + g; }
  static std::vector<long long> intersect(const std::vector<long long>& a, const std::vector<long long>& b) {
    std::vector<long long> out;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return out;  // both hold 0
  }
  // The generations every rank has (ranks are every local_-th worker of `net`).
  std::vector<long long> across_ranks(Transport& net, std::vector<long long> mine) const {
    constexpr int kGenerations = 2001;  // below the V-cycle's tags, beside solve's 2000
    ByteWriter w;
    w.io(mine);
    for (Bytes& part : all_gather(net, kGenerations, std::move(w.bytes), local_)) {
      ByteReader r(std::move(part));
      std::vector<long long> theirs;
      r.io(theirs);
      mine = intersect(mine, theirs);
    }
    return mine;
  }
  std::unique_ptr<io::Checkpoint> cp_;
  int first_, local_, groups_ = 1;
};

}  // namespace gdp::bands
