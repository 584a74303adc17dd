// Phase order and geometry of the band schedule: region boundaries per step, interior lanes, tiles, strip extents.
#include "bands/band_phase.h"

#include <algorithm>
#include <array>
#include <utility>

namespace gdp::bands {
namespace {

// One step's regions, columns [first, second): lead, interior (before lane splitting), follow. Every
// boundary moves 2 columns a step (the stencil's reach); the follow region reaches 2u columns into
// the leading neighbour's band.
using Columns = std::pair<int, int>;
enum { kLead, kMid, kFollow };
std::array<Columns, 3> phase_regions(const BandLayout& L, int l, int band, int p, int u) {
  const int A = L.begin(l, band), B = L.end(l, band), C = L.edge(), o = L.lead_offset(l);
  const int left = L.left(band) >= 0 ? 2 * u - o : 0, right = L.right(band) >= 0 ? 2 * u - o : 0;
  if (p % 2 == 0)  // lead at the left edge, follow at the right one
    return {{{A + left, A + C - 2 * u}, {A + C - 2 * u, B - C - 2 * u}, {B - C - 2 * u, B + right}}};
  return {{{B - C + 2 * u, B - right}, {A + C + 2 * u, B - C + 2 * u}, {A - left, A + C + 2 * u}}};
}

}  // namespace

// Group t is sweep s of row t - 2s; the one-band plan (G = 1) has no phase that only exchanges strips.
int phase_count(const BandLayout& L, int height) {
  return (height - 1 + 2 * L.sweeps) / L.phase_groups + (L.single ? 1 : 2);
}

int final_phase(const BandLayout& L, int height, int j) {
  // Rows j - 2 .. j + 2 have had their last sweep (group row + 2k) and, one phase later, the
  // neighbour's writes into this band's edge have come back in its strip (no neighbour: at once).
  return (std::min(j + 2, height - 1) + 2 * L.sweeps) / L.phase_groups + (L.single ? 0 : 1);
}

void plan_phase(const BandLayout& L, int l, int band, int height, int p, const std::function<void(const Tile&)>& relax,
                const std::function<void(bool)>& send, const std::function<void(bool)>& receive) {
  const int G = L.phase_groups, k = L.sweeps, t0 = p * G;
  const auto each = [&](auto&& f) {  // every (group, sweep) of the phase whose row exists, group by group
    for (int t = t0; t < t0 + G; ++t)
      for (int s = 1; s <= k; ++s)
        if (t - 2 * s >= 0 && t - 2 * s < height) f(t, s, t - t0 + s - 1);
  };
  if (L.single)  // the one-band plan: whole rows, forward, nothing to exchange
    return each([&](int t, int s, int) { relax(Tile{t - 2 * s, s, L.begin(l, band), L.end(l, band), true}); });
  const bool lead_left = p % 2 == 0;
  const auto tile = [&](int t, int s, Columns c) {
    if (c.first < c.second) relax(Tile{t - 2 * s, s, c.first, c.second, t % 2 == 0});
  };
  const auto region = [&](int which) {  // the lead or follow region, every step
    each([&](int t, int s, int u) { tile(t, s, phase_regions(L, l, band, p, u)[which]); });
  };
  region(kLead);
  if ((lead_left ? L.left(band) : L.right(band)) >= 0) send(lead_left);
  // The interior [a, a + width) in lanes of about green_lane columns; bound(q): boundary q, unshifted.
  const int a = L.begin(l, band) + L.edge(), width = L.end(l, band) - L.edge() - a;
  const int lanes = std::max(1, (width + L.green_lane / 2) / std::max(L.green_lane, 1));
  const auto bound = [&](int q) { return a + static_cast<int>(static_cast<long long>(width) * q / lanes); };
  for (int t = t0; t < t0 + G; ++t) {
    const bool forward = t % 2 == 0;
    for (int i = 0; i < lanes; ++i) {
      const int q = forward ? i : lanes - 1 - i;
      for (int s = 1; s <= k; ++s) {
        if (t - 2 * s < 0 || t - 2 * s >= height) continue;
        // Inner lane boundaries move with the traversal, 2(k - s) columns (section 6.2).
        const auto [lo, hi] = phase_regions(L, l, band, p, t - t0 + s - 1)[kMid];
        const int d = forward ? 2 * (k - s) : -2 * (k - s);
        tile(t, s, {q == 0 ? lo : bound(q) + d, q == lanes - 1 ? hi : bound(q + 1) + d});
      }
    }
  }
  if ((lead_left ? L.right(band) : L.left(band)) >= 0) receive(!lead_left);
  region(kFollow);
}

StripShape strip_shape(const BandLayout& L, int l, int band, int height, int p, bool left, bool outgoing) {
  const int G = L.phase_groups, k = L.sweeps, t0 = p * G, H = L.halo, ext = 2 * (L.steps() - 1);
  // The edge E between the two bands, and the way (d = 1: right, -1: left) from it into the sender's band.
  const int E = left ? L.begin(l, band) : L.end(l, band), d = left == outgoing ? 1 : -1;
  StripShape s;
  // u: every row the sender relaxed since its last strip that way (phases p - 1 and p) and the
  // rows the follower reads around them; the columns it may have written last: its own H
  // columns by the edge and `ext` of the neighbour's (written as follower in phase p - 1).
  s.u_rows[0] = std::max(0, t0 - G - 2 * k - 2), s.u_rows[1] = std::min(t0 + G - 1, height - 1);
  s.u_cols[0] = std::min(E - d * ext, E + d * H), s.u_cols[1] = std::max(E - d * ext, E + d * H);
  // b (w, d): the rows that arrived since the last strip that way, H columns of the sender's.
  s.b_rows[0] = std::max(0, t0 - G), s.b_rows[1] = std::min(t0 + G - 1, height - 1);
  s.b_cols[0] = std::min(E, E + d * H), s.b_cols[1] = std::max(E, E + d * H);
  return s;
}

}  // namespace gdp::bands
