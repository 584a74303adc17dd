// Seam cost on a grid of labelled cells, and alpha-expansion moves solved as minimum cuts with Boost Graph.
#include "blend/seam_grid.h"

#include <algorithm>
#include <cmath>

// Boost 1.74's edge iterators trip GCC 12's -Wmaybe-uninitialized at -O3 (a boost::optional false positive).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>

namespace gdp::blending {
namespace {

using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
using Graph = boost::adjacency_list<
    boost::vecS, boost::vecS, boost::directedS,
    boost::property<boost::vertex_color_t, boost::default_color_type,
                    boost::property<boost::vertex_distance_t, long,
                                    boost::property<boost::vertex_predecessor_t, Traits::edge_descriptor>>>,
    boost::property<boost::edge_capacity_t, double,
                    boost::property<boost::edge_residual_capacity_t, double,
                                    boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;

// The grid's right neighbour of column x (-1: none), wrapping when the canvas does.
int right_of(const SeamGrid& g, int x) {
  if (x + 1 < g.width) return x + 1;
  return g.wrap_x && g.width > 2 ? 0 : -1;
}

// A binary graph for one expansion move: x = 0 keeps a cell's label (source side), x = 1 takes alpha.
class MoveGraph {
 public:
  explicit MoveGraph(std::size_t nodes) : g_(nodes + 2), unary_(nodes, 0.0), s_(nodes), t_(nodes + 1) {}
  // Cost `c` added when node n takes alpha (negative: when it keeps its label, -c).
  void unary(int n, double c) { unary_[n] += c; }
  // Costs a = E(0,0), b = E(0,1), c = E(1,0), d = E(1,1) of nodes p, q.
  void pair(int p, int q, double a, double b, double c, double d) {
    unary_[p] += c - a;
    unary_[q] += d - c;
    edge(p, q, std::max(0.0, b + c - a - d), 0.0);  // metric costs keep this >= 0; others are truncated
  }
  // Solves; true for the nodes that take alpha.
  std::vector<char> solve() {
    for (std::size_t n = 0; n < unary_.size(); ++n) {
      if (unary_[n] > 0) edge(s_, static_cast<int>(n), unary_[n], 0.0);
      else if (unary_[n] < 0) edge(static_cast<int>(n), t_, -unary_[n], 0.0);
    }
    boost::boykov_kolmogorov_max_flow(g_, s_, t_);
    auto colour = boost::get(boost::vertex_color, g_);
    std::vector<char> alpha(unary_.size());
    for (std::size_t n = 0; n < unary_.size(); ++n)
      alpha[n] = boost::get(colour, n) != boost::color_traits<boost::default_color_type>::black();
    return alpha;
  }

 private:
  void edge(int from, int to, double forward, double backward) {
    auto cap = boost::get(boost::edge_capacity, g_);
    auto rev = boost::get(boost::edge_reverse, g_);
    const auto e = boost::add_edge(from, to, g_).first, r = boost::add_edge(to, from, g_).first;
    cap[e] = forward;
    cap[r] = backward;
    rev[e] = r;
    rev[r] = e;
  }
  Graph g_;
  std::vector<double> unary_;
  int s_, t_;
};

// One expansion move of layer `alpha` (0-based) over its patch. Returns the cells changed.
long expand(SeamGrid& g, int alpha, std::vector<int>& node) {
  const Patch& p = *g.layers[alpha];
  const Label a = static_cast<Label>(alpha + 1);
  const int ybegin = std::max(p.y0, g.row0), yend = std::min(p.y0 + p.h, g.row0 + g.height);
  std::vector<std::pair<int, int>> cells;
  for (int y = ybegin; y < yend; ++y)
    for (int x = p.x0; x < p.x0 + p.w; ++x) {
      const int r = y - g.row0;
      const std::size_t i = static_cast<std::size_t>(r) * g.width + x;
      if (g.free[i] && g.labels[i] != a && p.has(x, y)) {
        node[i] = static_cast<int>(cells.size());
        cells.emplace_back(x, r);
      }
    }
  if (cells.empty()) return 0;
  MoveGraph graph(cells.size());
  auto neighbour = [&](int n, int x, int r, int qx, int qr, bool count_pair) {
    if (qx < 0 || qr < 0 || qr >= g.height) return;
    const Label fp = g.label(x, r), fq = g.label(qx, qr);
    const int m = node[static_cast<std::size_t>(qr) * g.width + qx];
    if (m < 0) {  // a fixed neighbour
      if (fq != 0) graph.unary(n, pair_cost(g, x, r, qx, qr, a, fq) - pair_cost(g, x, r, qx, qr, fp, fq));
    } else if (count_pair) {
      graph.pair(n, m, pair_cost(g, x, r, qx, qr, fp, fq), pair_cost(g, x, r, qx, qr, fp, a),
                 pair_cost(g, x, r, qx, qr, a, fq), 0.0);
    }
  };
  for (int n = 0; n < static_cast<int>(cells.size()); ++n) {
    const auto [x, r] = cells[n];
    const int right = right_of(g, x);
    int left = x - 1;
    if (left < 0 && g.wrap_x && g.width > 2) left = g.width - 1;
    neighbour(n, x, r, right, r, true);
    neighbour(n, x, r, x, r + 1, true);
    if (left != right) neighbour(n, x, r, left, r, false);
    neighbour(n, x, r, x, r - 1, false);
  }
  const std::vector<char> take = graph.solve();
  long changed = 0;
  for (int n = 0; n < static_cast<int>(cells.size()); ++n) {
    const std::size_t i = static_cast<std::size_t>(cells[n].second) * g.width + cells[n].first;
    node[i] = -1;
    if (take[n]) {
      g.labels[i] = a;
      ++changed;
    }
  }
  return changed;
}

}  // namespace

double cell_cost(const SeamGrid& g, int x, int r, Label a, Label b) {
  const Patch* pa = g.layers[a - 1];
  const Patch* pb = g.layers[b - 1];
  const int y = g.row0 + r;
  if (!pa || !pb || !pa->has(x, y) || !pb->has(x, y)) return g.uncovered;
  const float* ca = pa->at(x, y, g.channels);
  const float* cb = pb->at(x, y, g.channels);
  double d = 0;
  for (int c = 0; c < g.channels; ++c) d += std::fabs(ca[c] - cb[c]);
  return d;
}

double pair_cost(const SeamGrid& g, int x0, int r0, int x1, int r1, Label a, Label b) {
  if (a == b || a == 0 || b == 0) return 0.0;
  return cell_cost(g, x0, r0, a, b) + cell_cost(g, x1, r1, a, b);
}

double grid_cost(const SeamGrid& g, int begin, int end) {
  double sum = 0;
  for (int r = begin; r < end; ++r)
    for (int x = 0; x < g.width; ++x) {
      const Label l = g.label(x, r);
      const int right = right_of(g, x);
      if (right >= 0 && right != x) sum += pair_cost(g, x, r, right, r, l, g.label(right, r));
      if (r > 0) sum += pair_cost(g, x, r, x, r - 1, l, g.label(x, r - 1));
    }
  return sum;
}

long expand_labels(SeamGrid& g, int sweeps) {
  std::vector<int> node(g.labels.size(), -1);
  long total = 0;
  for (int s = 0; s < sweeps; ++s) {
    long changed = 0;
    for (int k = 0; k < static_cast<int>(g.layers.size()); ++k)
      if (g.layers[k]) changed += expand(g, k, node);
    total += changed;
    if (changed == 0) break;
  }
  return total;
}

}  // namespace gdp::blending
