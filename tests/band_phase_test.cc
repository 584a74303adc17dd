// The phase schedule is a Gauss-Seidel ordering: every (row, sweep, column) relaxed once, reading the right sweeps.
//
// Simulates every band's plan_phase on version numbers instead of values: each band keeps its own
// copy (its columns plus halo) of which sweep every sample has had, strips copy those numbers as
// the real ones copy values, and each relaxation checks what it reads: rows above after the same
// sweep, rows below after the previous one, its own row's neighbours after either (with no cycle
// in the order that implies), b present. Rows are checked final (halos too) when the schedule
// says they are, strips must never replace a sample by an older one, and every row arrived, read or
// in a strip must be in the ring (BandLayout::ring_rows slots above the first row not restricted).
#include <gtest/gtest.h>

#include <deque>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "bands/band_phase.h"

namespace gdp::bands {
namespace {

struct Case {
  int width, height, bands, sweeps, groups;
  bool periodic;
  int level;  // 0: rows arrive with b in the halo (and the lead region starts in the neighbour's band); 1: without
  bool folded = false;  // a spherical layout (G = 1): each band must hold its own columns' latest sweep after every phase
};

BandLayout layout_for(const Case& c) {
  BandLayout L;
  L.bands = c.bands;
  L.sweeps = c.sweeps;
  L.phase_groups = c.groups;
  L.halo = band_halo(c.sweeps, c.groups);
  L.green_lane = 2 * L.edge();
  L.levels = 1;
  L.periodic = c.periodic;
  L.folded = c.folded;
  L.bounds.resize(2);
  for (int b = 0; b <= c.bands; ++b) {
    const int at = c.width * b / c.bands;
    L.bounds[0].push_back(c.level == 0 ? at : 2 * at);
    L.bounds[1].push_back(c.level == 0 ? at / 2 : at);
  }
  return L;
}

struct Op {
  enum Kind { Relax, Send, Receive } kind;
  Tile tile;
  bool left = false;
};

struct Message {
  std::vector<int> u_cols, b_cols;  // global (wrapped) columns, row-major over the shape
  std::vector<int> versions;
  std::vector<char> b;
  StripShape shape;
};

class Simulation {
 public:
  explicit Simulation(const Case& c) : c_(c), L_(layout_for(c)), l_(c.level) {
    for (int b = 0; b < c.bands; ++b) {
      Band band;
      band.origin = L_.origin(l_, b);
      band.len = L_.row_length(l_, b);
      band.version.assign(static_cast<std::size_t>(c.height) * band.len, 0);
      band.has_b.assign(static_cast<std::size_t>(c.height) * band.len, 0);
      for (int j = 0; j < c.height; ++j)  // level 0: b in the halo too; coarser: only in the band's columns
        for (int i = band.origin; i < band.origin + band.len; ++i)
          if (l_ == 0 || (i >= L_.begin(l_, b) && i < L_.end(l_, b))) band.has_b[j * band.len + i - band.origin] = 1;
      bands_.push_back(std::move(band));
    }
    done_.assign(static_cast<std::size_t>(c.height) * (c.sweeps + 1) * c.width, 0);
    after_.resize(static_cast<std::size_t>(c.height) * (c.sweeps + 1));
  }

  void run() {
    const int phases = phase_count(L_, c_.height);
    for (int p = 0; p < phases; ++p) {
      // The ring (BandLayout::ring_rows): rows below live_ are restricted; the phase's rows have arrived.
      live_ = 0;
      while (live_ < c_.height && final_phase(L_, c_.height, live_) < p) ++live_;
      in_ring(std::min(p * c_.groups + c_.groups - 1, c_.height - 1), "arrives");
      std::vector<std::deque<Op>> ops(c_.bands);
      for (int b = 0; b < c_.bands; ++b)
        plan_phase(
            L_, l_, b, c_.height, p, [&](const Tile& t) { ops[b].push_back({Op::Relax, t, false}); },
            [&](bool left) { ops[b].push_back({Op::Send, {}, left}); },
            [&](bool left) { ops[b].push_back({Op::Receive, {}, left}); });
      for (bool progress = true; progress;) {  // run each band until it waits for a strip
        progress = false;
        for (int b = 0; b < c_.bands; ++b)
          while (!ops[b].empty()) {
            const Op& op = ops[b].front();
            if (op.kind == Op::Receive && !receive(b, p, op.left)) break;
            if (op.kind == Op::Relax) relax(b, p, op.tile);
            if (op.kind == Op::Send) send(b, p, op.left);
            ops[b].pop_front();
            progress = true;
          }
      }
      for (int b = 0; b < c_.bands; ++b) ASSERT_TRUE(ops[b].empty()) << "band " << b << " stuck in phase " << p;
      for (int b = 0; b < c_.bands; ++b)
        for (int j = 0; j < c_.height; ++j)
          if (final_phase(L_, c_.height, j) == p) check_final(b, j);
      if (c_.folded) check_own_columns_current(p);
    }
    for (int j = 0; j < c_.height; ++j)
      for (int s = 1; s <= c_.sweeps; ++s)
        for (int i = 0; i < c_.width; ++i) ASSERT_EQ(done(j, s, i), 1) << "row " << j << " sweep " << s << " col " << i;
    check_acyclic();
  }

 private:
  struct Band {
    int origin = 0, len = 0;
    std::vector<int> version;
    std::vector<char> has_b;
  };

  // -1 outside the image (non-periodic), else the wrapped column.
  int wrap(int i) const {
    if (c_.periodic) return ((i % c_.width) + c_.width) % c_.width;
    return i >= 0 && i < c_.width ? i : -1;
  }
  int& done(int j, int s, int i) { return done_[(static_cast<std::size_t>(j) * (c_.sweeps + 1) + s) * c_.width + i]; }
  int& version(int b, int j, int i) {
    Band& band = bands_[b];
    EXPECT_TRUE(i >= band.origin && i < band.origin + band.len) << "band " << b << " reads column " << i;
    return band.version[static_cast<std::size_t>(j) * band.len + (i - band.origin)];
  }
  char& has_b(int b, int j, int i) {
    Band& band = bands_[b];
    return band.has_b[static_cast<std::size_t>(j) * band.len + (i - band.origin)];
  }

  void in_ring(int row, const char* what) {
    ASSERT_GE(row, live_) << "row " << row << " " << what << " after its restriction";
    ASSERT_LT(row - live_, L_.ring_rows()) << "row " << row << " " << what << " in the slot of live row " << row - L_.ring_rows();
  }

  void relax(int b, int p, const Tile& t) {
    const int j = t.row, s = t.sweep;
    for (int r = std::max(0, j - 2); r <= std::min(j + 2, c_.height - 1); ++r) in_ring(r, "is read");
    ASSERT_LE(j, p * c_.groups + c_.groups - 1) << "relaxes a row not arrived";
    ASSERT_GE(t.lo - 2, bands_[b].origin);
    ASSERT_LE(t.hi + 2, bands_[b].origin + bands_[b].len);
    for (int n = 0; n < t.hi - t.lo; ++n) {
      const int i = t.forward ? t.lo + n : t.hi - 1 - n, gi = wrap(i);
      ASSERT_GE(gi, 0) << "relaxes outside the image";
      ASSERT_EQ(++done(j, s, gi), 1) << "row " << j << " sweep " << s << " column " << gi << " twice";
      ASSERT_EQ(version(b, j, i), s - 1) << "band " << b << " row " << j << " sweep " << s << " col " << i;
      ASSERT_TRUE(has_b(b, j, i)) << "band " << b << " has no b at row " << j << " col " << i;
      for (int dj = -2; dj <= 2; ++dj)
        for (int di = -2; di <= 2; ++di) {
          const int r = j + dj, gc = wrap(i + di);
          if (r < 0 || r >= c_.height || gc < 0 || (dj == 0 && di == 0)) continue;
          ASSERT_LE(r, std::min(p * c_.groups + c_.groups - 1, c_.height - 1)) << "reads a row not arrived";
          const int v = version(b, r, i + di);
          const int want = dj < 0 ? s : s - 1;
          if (dj != 0) {
            ASSERT_EQ(v, want) << "band " << b << " row " << j << " sweep " << s << " col " << i << " reads row " << r
                               << " col " << i + di;
          }
          if (dj == 0) {
            ASSERT_TRUE(v == s || v == s - 1) << "band " << b << " row " << j << " col " << i << " reads own row at " << v;
            // v == s: column gc came first in this sweep of row j; else after.
            auto& edges = after_[static_cast<std::size_t>(j) * (c_.sweeps + 1) + s];
            if (v == s) edges.insert({gc, gi});
            else edges.insert({gi, gc});
          }
        }
      version(b, j, i) = s;
    }
  }

  void send(int b, int p, bool left) {
    const int to = left ? L_.left(b) : L_.right(b);
    Message m;
    m.shape = strip_shape(L_, l_, b, c_.height, p, left, true);
    for (int j = m.shape.u_rows[0]; j <= m.shape.u_rows[1]; ++j) in_ring(j, "is in a strip");
    for (int j = m.shape.u_rows[0]; j <= m.shape.u_rows[1]; ++j)
      for (int i = m.shape.u_cols[0]; i < m.shape.u_cols[1]; ++i) {
        m.u_cols.push_back(wrap(i));
        m.versions.push_back(version(b, j, i));
      }
    for (int j = m.shape.b_rows[0]; j <= m.shape.b_rows[1]; ++j)
      for (int i = m.shape.b_cols[0]; i < m.shape.b_cols[1]; ++i) {
        m.b_cols.push_back(wrap(i));
        m.b.push_back(has_b(b, j, i));
      }
    queues_[{b, to}].push_back(std::move(m));
  }

  bool receive(int b, int p, bool left) {
    const int from = left ? L_.left(b) : L_.right(b);
    auto& q = queues_[{from, b}];
    if (q.empty()) return false;
    const Message m = std::move(q.front());
    q.pop_front();
    const StripShape s = strip_shape(L_, l_, b, c_.height, p, left, false);
    EXPECT_EQ(s.u_rows[0], m.shape.u_rows[0]);
    EXPECT_EQ(s.u_rows[1], m.shape.u_rows[1]);
    EXPECT_EQ(s.b_rows[0], m.shape.b_rows[0]);
    EXPECT_EQ(s.b_rows[1], m.shape.b_rows[1]);
    std::size_t n = 0;
    for (int j = s.u_rows[0]; j <= s.u_rows[1]; ++j)
      for (int i = s.u_cols[0]; i < s.u_cols[1]; ++i, ++n) {
        EXPECT_LT(n, m.u_cols.size());
        if (n >= m.u_cols.size()) return true;
        EXPECT_EQ(wrap(i), m.u_cols[n]) << "strip columns differ";
        if (wrap(i) < 0) continue;
        int& v = version(b, j, i);
        EXPECT_GE(m.versions[n], v) << "strip replaces row " << j << " col " << i << " by an older sweep";
        v = m.versions[n];
      }
    EXPECT_EQ(n, m.u_cols.size());
    n = 0;
    for (int j = s.b_rows[0]; j <= s.b_rows[1]; ++j)
      for (int i = s.b_cols[0]; i < s.b_cols[1]; ++i, ++n) {
        EXPECT_EQ(wrap(i), m.b_cols[n]);
        if (wrap(i) < 0) continue;
        EXPECT_TRUE(m.b[n]) << "strip carries b the sender does not have";
        has_b(b, j, i) = has_b(b, j, i) || m.b[n];
      }
    return true;
  }

  // Restriction reads u at [A - 4, B + 4) of rows j - 2 .. j + 2 and b at [A - 2, B + 2) of row j;
  // row j is stored (and prolonged into in the next pass) with its whole halo.
  void check_final(int b, int j) {
    const int A = L_.begin(l_, b), B = L_.end(l_, b);
    for (int i = bands_[b].origin; i < bands_[b].origin + bands_[b].len; ++i)
      if (wrap(i) >= 0) {
        ASSERT_EQ(version(b, j, i), c_.sweeps) << "band " << b << " stores row " << j << " col " << i << " early";
      }
    for (int r = std::max(0, j - 2); r <= std::min(c_.height - 1, j + 2); ++r)
      for (int i = A - 4; i < B + 4; ++i)
        if (wrap(i) >= 0) {
          ASSERT_EQ(version(b, r, i), c_.sweeps) << "band " << b << " finishes row " << j << " early (row " << r << " col " << i << ")";
        }
    for (int i = A - 2; i < B + 2; ++i)
      if (wrap(i) >= 0) {
        ASSERT_TRUE(has_b(b, j, i)) << "band " << b << " row " << j << " col " << i << " without b";
      }
  }

  // Folded layouts: what a band shows its mirror partners between phases, its own columns, holds
  // every sweep done so far anywhere.
  void check_own_columns_current(int p) {
    for (int b = 0; b < c_.bands; ++b)
      for (int j = 0; j < c_.height; ++j)
        for (int i = L_.begin(l_, b); i < L_.end(l_, b); ++i) {
          int latest = 0;
          while (latest < c_.sweeps && done(j, latest + 1, i)) ++latest;
          ASSERT_EQ(version(b, j, i), latest) << "after phase " << p << " band " << b << " row " << j << " col " << i;
        }
  }

  // The in-row orders the reads imply must be consistent (no cycle) for every (row, sweep).
  void check_acyclic() {
    for (std::size_t rs = 0; rs < after_.size(); ++rs) {
      std::vector<int> indegree(c_.width, 0);
      std::vector<std::vector<int>> next(c_.width);
      for (auto [a, b] : after_[rs]) {
        next[a].push_back(b);
        ++indegree[b];
      }
      std::vector<int> ready;
      for (int i = 0; i < c_.width; ++i)
        if (!indegree[i]) ready.push_back(i);
      int seen = 0;
      while (!ready.empty()) {
        const int i = ready.back();
        ready.pop_back();
        ++seen;
        for (int n : next[i])
          if (--indegree[n] == 0) ready.push_back(n);
      }
      ASSERT_EQ(seen, c_.width) << "row/sweep " << rs << ": the in-row order has a cycle";
    }
  }

  Case c_;
  BandLayout L_;
  int l_, live_ = 0;  // live_: the first row not yet restricted
  std::vector<Band> bands_;
  std::vector<int> done_;
  std::vector<std::set<std::pair<int, int>>> after_;
  std::map<std::pair<int, int>, std::deque<Message>> queues_;
};

class BandPhaseTest : public ::testing::TestWithParam<Case> {};

TEST_P(BandPhaseTest, IsAGaussSeidelOrdering) {
  const Case c = GetParam();
  ASSERT_GE(c.width / c.bands, layout_for(c).min_band_width());
  Simulation sim(c);
  sim.run();
}

INSTANTIATE_TEST_SUITE_P(Cases, BandPhaseTest,
                         ::testing::Values(Case{300, 40, 2, 3, 4, false, 0}, Case{300, 40, 2, 3, 4, false, 1},
                                           Case{400, 41, 3, 3, 5, true, 0}, Case{400, 41, 3, 3, 5, true, 1},
                                           Case{200, 30, 1, 3, 3, true, 0}, Case{200, 30, 1, 2, 1, false, 1},
                                           Case{420, 37, 4, 2, 7, false, 0}, Case{120, 25, 2, 1, 2, true, 1},
                                           Case{400, 10, 2, 3, 16, false, 0}, Case{340, 23, 2, 3, 16, true, 0},
                                           Case{340, 23, 2, 3, 16, true, 1}, Case{180, 33, 3, 3, 1, true, 0},
                                           Case{180, 33, 3, 3, 1, true, 1}, Case{180, 33, 3, 3, 1, true, 0, true},
                                           Case{180, 33, 3, 3, 1, true, 1, true}, Case{240, 20, 4, 2, 1, true, 1, true},
                                           Case{200, 30, 1, 3, 1, true, 1, true}));

}  // namespace
}  // namespace gdp::bands
