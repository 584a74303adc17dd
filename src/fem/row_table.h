// Per-row data of an axis in memory independent of its length: the rows near the ends, and one
// row standing for the identical interior ones.
#pragma once

#include <vector>

namespace gdp::fem {

// Rows within kEdge of either end are stored; every other row equals the row at kEdge. Holds
// for the folded and Galerkin matrices of gdp's axes (boundary effects reach at most a few
// rows at every level; tests/axis_test.cc compares against tables built in full).
template <class Row>
class RowTable {
 public:
  static constexpr int kEdge = 8;

  RowTable() = default;
  // Calls make(i) for the rows it keeps (every row when n <= 2 * edge + 1).
  template <class Make>
  RowTable(int n, Make make, int edge = kEdge) : n_(n) {
    if (n <= 2 * edge + 1) {
      head_ = n;
      for (int i = 0; i < n; ++i) rows_.push_back(make(i));
      return;
    }
    head_ = edge;
    for (int i = 0; i <= edge; ++i) rows_.push_back(make(i));
    for (int i = n - edge; i < n; ++i) rows_.push_back(make(i));
  }
  const Row& operator[](int i) const {
    if (i < head_) return rows_[i];
    if (i >= n_ - head_) return rows_[i - (n_ - head_) + head_ + 1];
    return rows_[head_];
  }
  int size() const { return n_; }

 private:
  int n_ = 0, head_ = 0;
  std::vector<Row> rows_;
};

}  // namespace gdp::fem
