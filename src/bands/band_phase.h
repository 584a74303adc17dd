// The order in which a band relaxes its tiles in one phase of G row groups, and the strips it exchanges.
//
// Group t holds sweep s of row t - 2s (s = 1 .. k); phase p holds groups [pG, pG + G). Step
// u = t - pG + s - 1 (0 .. G + k - 2) numbers the (group, sweep) pairs of a phase. At every
// boundary between two bands one of them *leads* in a phase and the other *follows*: in even
// phases every band leads at its left edge, in odd phases at its right edge. A band runs a phase
// as: its lead region for every step, send the strip to the neighbour it leads against, its
// interior group by group, receive the strip from the neighbour it follows, its follow region
// for every step. Region boundaries move 2 columns a step (the stencil's reach), so each region
// reads only values that exist at that point of the Gauss-Seidel ordering; the follow region
// reaches 2u columns into the leading neighbour's band (docs/how-bands-work.md).
#pragma once

#include <vector>

#include "bands/band_layout.h"

namespace gdp::bands {

// Phases of a level with `height` rows: relaxing ones, then one that only exchanges strips.
int phase_count(const BandLayout& L, int height);
// Row j is final in a band's copy (halos included) once phase `final_phase(L, height, j)` is done.
int final_phase(const BandLayout& L, int height, int j);

struct Tile {
  int row = 0, sweep = 0, lo = 0, hi = 0;  // columns [lo, hi), global numbering (periodic: unwrapped)
  bool forward = true;
};

// Calls relax(Tile), send(bool to_left) and receive(bool from_left) in the band's order for
// phase p of level l (rows [0, height)). Send and receive are not called at an image edge.
template <class Relax, class Send, class Receive>
void plan_phase(const BandLayout& L, int l, int band, int height, int p, Relax&& relax, Send&& send,
                Receive&& receive);

// One strip's extent: u of rows [u_rows[0], u_rows[1]] at columns [u_cols[0], u_cols[1]); b (and
// w, d) of rows [b_rows[0], b_rows[1]] at columns [b_cols[0], b_cols[1]). Empty row ranges have
// first > last. `outgoing`: the sender's columns, else where the receiver stores them.
struct StripShape {
  int u_rows[2], u_cols[2], b_rows[2], b_cols[2];
};
StripShape strip_shape(const BandLayout& L, int l, int band, int height, int p, bool left, bool outgoing);

// ---- implementation of plan_phase ----

struct PhaseRegions {  // one step's regions: lead, interior (before lane splitting), follow
  int lead[2], mid[2], follow[2];
};
PhaseRegions phase_regions(const BandLayout& L, int l, int band, int p, int u);
// Interior lane boundaries (without the per-sweep shift), first and last excluded.
std::vector<int> interior_lanes(const BandLayout& L, int l, int band);

template <class Relax, class Send, class Receive>
void plan_phase(const BandLayout& L, int l, int band, int height, int p, Relax&& relax, Send&& send,
                Receive&& receive) {
  const int G = L.phase_groups, k = L.sweeps, t0 = p * G;
  if (L.single) {  // the one-band plan: whole rows, forward, nothing to exchange
    for (int t = t0; t < t0 + G; ++t)
      for (int s = 1; s <= k; ++s)
        if (t - 2 * s >= 0 && t - 2 * s < height) relax(Tile{t - 2 * s, s, L.begin(l, band), L.end(l, band), true});
    return;
  }
  const bool lead_left = p % 2 == 0;
  const auto each = [&](auto&& f) {  // every (group, sweep) of the phase whose row exists
    for (int t = t0; t < t0 + G; ++t)
      for (int s = 1; s <= k; ++s)
        if (t - 2 * s >= 0 && t - 2 * s < height) f(t, s, t - t0 + s - 1);
  };
  const auto tile = [&](int t, int s, int lo, int hi) {
    if (lo < hi) relax(Tile{t - 2 * s, s, lo, hi, t % 2 == 0});
  };
  each([&](int t, int s, int u) {
    const PhaseRegions r = phase_regions(L, l, band, p, u);
    tile(t, s, r.lead[0], r.lead[1]);
  });
  const int ahead = lead_left ? L.left(band) : L.right(band);
  if (ahead >= 0) send(lead_left);
  const std::vector<int> inner = interior_lanes(L, l, band);
  const int lanes = static_cast<int>(inner.size()) + 1;
  for (int t = t0; t < t0 + G; ++t) {
    const bool forward = t % 2 == 0;
    for (int i = 0; i < lanes; ++i) {
      const int q = forward ? i : lanes - 1 - i;
      for (int s = 1; s <= k; ++s) {
        if (t - 2 * s < 0 || t - 2 * s >= height) continue;
        // Inner lane boundaries move with the traversal, 2(k - s) columns (section 6.2).
        const PhaseRegions r = phase_regions(L, l, band, p, t - t0 + s - 1);
        const int d = forward ? L.shift(s) : -L.shift(s);
        const int lo = q == 0 ? r.mid[0] : inner[q - 1] + d;
        const int hi = q == lanes - 1 ? r.mid[1] : inner[q] + d;
        tile(t, s, lo, hi);
      }
    }
  }
  const int behind = lead_left ? L.right(band) : L.left(band);
  if (behind >= 0) receive(!lead_left);
  each([&](int t, int s, int u) {
    const PhaseRegions r = phase_regions(L, l, band, p, u);
    tile(t, s, r.follow[0], r.follow[1]);
  });
}

}  // namespace gdp::bands
