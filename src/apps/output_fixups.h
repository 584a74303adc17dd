// Per-pixel corrections applied to solved rows on their way out: blanks restored, pixels blacked out.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "gdp/rows.h"
#include "gdp/solver.h"
#include "schedule/row_store.h"

namespace gdp::apps {

// Records, while the input is read, which output samples must not keep the solved value:
// channels whose input sample was not finite (FITS blanks: they come out as NaN again) and
// pixels to output as zero. Then, as a RowWriter in front of the real one, applies them.
// Flags are kept in a row store (one byte per pixel: in memory or in a scratch file) from the
// first row with one on. After set_columns (a rank of a distributed solve, before the first
// record) only those columns are recorded, stored and fixed: the rows written hold no others.
class OutputFixups final : public RowWriter {
 public:
  OutputFixups(RowWriter& out, int width, int height, int channels, const SolverOptions& solver);
  ~OutputFixups() override;
  // Row y of the input (in order): marks its non-finite samples; `zero` (width flags, indexed by
  // column, may be empty) marks pixels to output as zero.
  void record(int y, std::span<const float> input, std::span<const unsigned char> zero = {});
  void write_row(int y, std::span<const float> row) override;
  void commit() override { out_.commit(); }
  void set_columns(int begin, int end) override;

 private:
  RowWriter& out_;
  int width_, height_, channels_;
  int begin_ = 0, end_;  // the columns recorded and fixed
  schedule::StorePolicy policy_;
  int unflagged_ = 0;  // leading rows without flags (not stored)
  std::unique_ptr<schedule::RowStore<unsigned char>> flags_;
  std::vector<unsigned char> flag_row_;
  std::vector<float> row_;
  bool any_ = false, reading_ = false;
};

}  // namespace gdp::apps
