// Tone mapping's last passes: the solved log luminance kept in a row store, its percentiles, display rows.
#pragma once

#include <memory>
#include <span>

#include "apps/tonemap_colour.h"
#include "gdp/rows.h"
#include "schedule/row_store.h"

namespace gdp::apps::tonemap {

// Receives the solver's rows (log luminance u, one channel) into a store (in memory or an
// unlinked scratch file) and notes their range, so that percentiles can be taken once the
// solve is over and the output written in a last pass.
class SolvedRows final : public RowWriter {
 public:
  SolvedRows(int width, int height, const schedule::StorePolicy& policy);
  void write_row(int y, std::span<const float> row) override;
  // u at the given percentiles (0..100) of the pixels with a finite u, from a histogram of
  // 65536 bins over the range: one more pass over the store. {0, 0} when none is finite.
  std::pair<double, double> percentiles(double low, double high);
  // Reads `in` (from row 0) and the store in step, writing display rows to `out`.
  void write_display(RowReader& in, const DisplayMap& map, RowWriter& out);

 private:
  int width_, height_;
  schedule::RowStore<float> store_;
  double min_, max_;
};

}  // namespace gdp::apps::tonemap
