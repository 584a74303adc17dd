// What an application hands the solver: per-row gradient and value fields of every channel.
#pragma once

#include <vector>

namespace gdp {

// One row j of the guidance fields, channel-major: gx[c * x_edges + e] is the desired
// difference u(e+1, j) - u(e, j) (x_edges = width - 1, or width on a periodic domain where
// the last edge joins column width-1 to column 0); gy[c * width + i] is the desired
// u(i, j+1) - u(i, j) (unused on the last row); value[c * width + i] is the desired value
// (used only when alpha > 0 or the source has per-pixel weights).
//
// On a spherical (PQ) domain, whose top and bottom edges fold onto themselves (pixel (i, 0)
// meets (W-1-i, 0) across the top edge; (i, H-1) meets (i', H-1), i' = (W/2-1-i) mod W, across
// the bottom edge; docs/sphere-solver.md), `spherical` is set and two more edges are used: gy
// on the last row is the desired u(i', H-1) - u(i, H-1), and gy_above (row 0 only) the desired
// u(i, 0) - u(W-1-i, 0). Both are differences of one pair of pixels seen from either side, so
// sources give values that change sign under the pairing (i and its partner).
struct GuidanceRow {
  int x_edges = 0;
  bool spherical = false;  // set by the solver
  std::vector<double> gx, gy, value;
  std::vector<double> gy_above;  // spherical domains, row 0
  // Sources with has_weights(): the per-pixel weight of the value term, added to alpha (a
  // lumped mass: weight 1 costs as much as alpha = 1 there), or kPinned to hold the pixel at
  // its value (docs/weights.md).
  std::vector<double> weight;
  // Sources with has_initial(): the starting guess (unless start_from_initial() is false), and
  // the values whose mean, over the counted pixels, a solution keeps when alpha == 0.
  std::vector<float> initial;
  // Per pixel: 1 where the pixel counts towards the mean the solution keeps when alpha == 0
  // (the solver sets every entry to 1 before each read_row; sources may clear some).
  std::vector<unsigned char> counted;
  // Working space a source may use while it fills the row (per-edge flags).
  std::vector<unsigned char> edges;
};

// A weight that holds a pixel at its value (within about 1e-6 of the range).
inline constexpr double kPinned = 1e30;

// A source of guidance rows. Rows are requested once each, in order j = 0, 1, ..., so a
// source may stream from files; read_row fills every field of `out` (already sized).
class GuidanceSource {
 public:
  virtual ~GuidanceSource() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual int channels() const = 0;
  // Weight of the value term (0: pure gradient problem, solution defined up to a constant).
  virtual double alpha() const { return 0.0; }
  // True when read_row fills `weight` (the problem then has a unique solution wherever some
  // weight is positive, and the solver keeps no mean).
  virtual bool has_weights() const { return false; }
  // True when read_row fills `initial`.
  virtual bool has_initial() const { return false; }
  // False: start from zero all the same (initial then only sets the mean to keep).
  virtual bool start_from_initial() const { return true; }
  virtual void read_row(int j, GuidanceRow& out) = 0;
  // A hint before the first read_row: only columns [begin, end) of every row's fields are needed
  // (edges gx[i] for i in [begin, end - 1)); sources may then read only those columns of their
  // images (RowReader::set_columns) and leave the other entries as they are.
  virtual void set_columns(int /*begin*/, int /*end*/) {}

  // Sources that split: reading their inputs (decode, one thread, rows in order) apart from the
  // per-column work (compute, on several threads at once), so that the solver's input pass makes
  // each band's columns on its own thread. set_slots(n), once before the first decode: decode(y)
  // reads input row y into slot y % n. compute(j, out, begin, end) then fills columns [begin, end)
  // of row j's fields as read_row would (horizontal edges [begin, end - 1), or to the row's last
  // edge where end == width) from the decoded rows j and j + 1, which must stay in their slots
  // until it returns; calls for other rows or columns may run at once, beside decode of other
  // slots. read_row is then decode and compute.
  virtual bool splits() const { return false; }
  virtual void set_slots(int /*slots*/) {}
  virtual void decode(int /*y*/) {}
  virtual void compute(int /*j*/, GuidanceRow& /*out*/, int /*begin*/, int /*end*/) const {}
};

}  // namespace gdp
