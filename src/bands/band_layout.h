// Where the bands lie on every level, and the lanes inside them (docs/how-bands-work.md).
#pragma once

#include <algorithm>
#include <memory>
#include <vector>

#include "multigrid/hierarchy.h"

namespace gdp::bands {

struct BandLayout {
  int bands = 1;
  int sweeps = 3;        // k: Gauss-Seidel sweeps of the pass this plan runs (the restriction pass's)
  int post_sweeps = 3;   // those of the prolongation pass (post_pass() is its plan)
  int phase_groups = 1;  // G: row groups per phase (one strip each way per phase)
  int halo = 4;          // columns kept of each neighbour: band_halo(k, G) for the larger k
  int green_lane = 0;    // the interior is split into lanes of about this width (cache locality)
  int levels = 0;        // levels 0 .. levels - 1 are banded; level `levels` is merged or gathered
  int first_level = 0;   // the hierarchy level of this layout's level 0 (a merged stage's is deeper)
  bool periodic = false;  // the hierarchy's rows wrap around (cylindrical and spherical images)
  // Spherical (PQ) levels: rows 0, 1, h-2 and h-1 read rows mirrored across the fold, at columns
  // other bands own (band_fold.h); G = 1 and every level's lead region reaches into the neighbour's.
  bool folded = false;
  // The one-band plan (single_band_layout): no neighbour (a periodic level closes inside the
  // kernels), no halo, whole rows always forward, G = 1: plain streaming, in-core's bits.
  bool single = false;
  // bounds[l][b] .. bounds[l][b + 1]: the columns band b owns on level l (l = 0 .. levels).
  std::vector<std::vector<int>> bounds;
  // Where bands grow too narrow before a level is small enough to gather, they merge in pairs (the
  // last three when odd): level `levels` is this stage's level 0, merged band g run by worker 2g.
  // Null: gathered to worker 0.
  std::shared_ptr<const BandLayout> merged;

  int begin(int l, int b) const { return bounds[l][b]; }
  int end(int l, int b) const { return bounds[l][b + 1]; }
  int origin(int l, int b) const { return begin(l, b) - halo; }              // global column of a row's [0]
  int row_length(int l, int b) const { return end(l, b) - begin(l, b) + 2 * halo; }
  int left(int b) const { return single ? -1 : b > 0 ? b - 1 : periodic ? bands - 1 : -1; }  // -1: none
  int right(int b) const { return single ? -1 : b + 1 < bands ? b + 1 : periodic ? 0 : -1; }
  // The prolongation pass's plan: the same bands, halo and lanes' bounds, post_sweeps sweeps.
  BandLayout post_pass() const {
    BandLayout P = *this;
    P.sweeps = post_sweeps;
    return P;
  }
  // G + k - 1: the (group, sweep) steps u = t - t0 + s - 1 of a phase; tiles move 2 columns a step.
  int steps() const { return phase_groups + sweeps - 1; }
  // How far a band's lead region reaches into the neighbour's band at a phase's first step:
  // 2(G + k - 2) where the halo's b is there (level 0 of the top stage; folded layouts), else 0.
  int lead_offset(int l) const { return (l == 0 && top()) || folded ? 2 * (steps() - 1) : 0; }
  // Rows of a banded level's ring (check_slot in streamed_vcycle.cc). Row r is restricted at the end of phase
  // (r + 2 + 2k) / G + 1 and phase p runs once row pG + G - 1 has come: a row arrives at most 2(G + k) + 1
  // rows after the first live one, a strip reaches 2(G + k) + 1 back. 8 more for the coarse rows being
  // zeroed and pulled (k: the larger of the passes'); the one-band plan's 2k + 12 is streaming's pipeline.
  int ring_rows() const { return 2 * (phase_groups + std::max(sweeps, post_sweeps)) + 10; }
  // Width of a band's lead and follow regions at a phase's first step (4 columns at its last).
  int edge() const { return 4 * steps(); }
  int min_band_width() const { return 2 * edge() + 4; }
  // The merged stage's band that band b's columns join (merged: non-null).
  int group_of(int b) const { return std::min(b / 2, merged->bands - 1); }
  // The worker of this stage that runs merged band g, and the first band after its group.
  int group_owner(int g) const { return 2 * g; }
  int group_end(int g) const { return g + 1 == merged->bands ? bands : 2 * g + 2; }
  // The finest stage: its level 0's rows are the input, pushed with the neighbours' b in their
  // halo; a merged stage's come from the stage above every cycle, and it measures no residual.
  bool top() const { return first_level == 0; }
  // Banded levels in this stage and the merged ones below it.
  int banded_levels() const { return levels + (merged ? merged->banded_levels() : 0); }
};

// The halo a band keeps of each neighbour for k sweeps and G groups per phase: max(2(G + k - 1), 4).
inline int band_halo(int sweeps, int phase_groups) { return std::max(2 * (phase_groups + sweeps - 1), 4); }

// Row groups per phase where the bands are wide enough: enough rows between a strip's sending and
// its use to hide about a millisecond of network latency on the images of docs/how-bands-work.md.
constexpr int kDefaultPhaseGroups = 16;

// Bands of (nearly) equal width, boundaries on multiples of 2^(levels - 1) so that each level's
// bands halve into the next one's, banded up to `max_levels` (the first level held whole, on worker
// 0), merging where they would grow narrower than min_band_width() (not on spherical images: there
// the level is gathered); `pre` and `post` sweeps. G is lowered while the finest bands are narrower
// than 16 min_band_width(). Throws UsageError when even the finest level is too narrow for G = 1.
BandLayout make_band_layout(const multigrid::Hierarchy& h, int bands, int pre, int post, int max_levels);
// The one-band plan (`single`) over levels 0 .. levels - 1, level `levels` held whole.
BandLayout single_band_layout(const multigrid::Hierarchy& h, int pre, int post, int levels);

}  // namespace gdp::bands
