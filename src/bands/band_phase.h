// The order in which a band relaxes its tiles in one phase of G row groups, and the strips it
// exchanges (docs/how-bands-work.md, "Groups, phases, regions").
#pragma once

#include <functional>

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
// phase p of level l (rows [0, height)): its lead region for every (group, sweep) step, the strip
// to the neighbour it leads against, its interior group by group in lanes, the strip from the
// neighbour it follows, its follow region. Send and receive are not called at an image edge.
void plan_phase(const BandLayout& L, int l, int band, int height, int p, const std::function<void(const Tile&)>& relax,
                const std::function<void(bool)>& send, const std::function<void(bool)>& receive);

// One strip's extent: u of rows [u_rows[0], u_rows[1]] at columns [u_cols[0], u_cols[1]); b (and
// w, d) of rows [b_rows[0], b_rows[1]] at columns [b_cols[0], b_cols[1]). Empty row ranges have
// first > last. `outgoing`: the sender's columns, else where the receiver stores them.
struct StripShape {
  int u_rows[2], u_cols[2], b_rows[2], b_cols[2];
};
StripShape strip_shape(const BandLayout& L, int l, int band, int height, int p, bool left, bool outgoing);

}  // namespace gdp::bands
