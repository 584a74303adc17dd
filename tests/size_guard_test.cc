// The size guard's scratch bounds (tools/gdp/scratch_split.h) against what real streamed solves keep where.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>

#include "gdp/solver.h"
#include "scratch_split.h"
#include "test_util.h"

namespace gdp {
namespace {

// A 160x120 RGB solve streamed on one thread, every level but the coarsest streamed: its largest
// store is one plane of the finest level.
constexpr int w = 160, h = 120, c = 3;
constexpr double plane = static_cast<double>(w) * h * c * sizeof(float);
SolverOptions streamed() {
  SolverOptions o;
  o.schedule = Schedule::Streaming;
  o.threads = 1;
  o.coarsest_size = 5;
  o.incore_bytes = 0;
  return o;
}

// Stores go to memory while the budget has room for the whole store, else to a file whole: the
// budget left unused can be up to one store, so the disk takes up to that much more than
// scratch - budget. Every budget from none to all of it, on a solve whose largest store is one
// plane of the finest level (one lane, every level but the coarsest streamed, a carried result).
TEST(SizeGuard, ScratchBoundsHoldForEveryBudget) {
  const Image img = test::random_image(w, h, c, 4);
  SolverOptions o = streamed();
  o.vcycles = 2;
  std::size_t total = 0;
  int split_unevenly = 0;
  for (int step = 0; step <= 24; ++step) {
    o.scratch_memory = total * step / 20;  // the first run (budget 0) measures the total
    test::ExactGradients src(img, Domain::Cylindrical);
    SolveSummary s;
    solve(src, o, nullptr, &s);
    if (step == 0) total = s.scratch_bytes;
    ASSERT_EQ(s.scratch_bytes, total);
    const cli::ScratchSplit bound =
        cli::split_scratch(static_cast<double>(total), static_cast<double>(o.scratch_memory), plane);
    EXPECT_LE(static_cast<double>(s.scratch_disk_peak), bound.disk) << o.scratch_memory << " of " << total;
    EXPECT_LE(static_cast<double>(s.scratch_memory_peak), bound.memory) << o.scratch_memory << " of " << total;
    EXPECT_EQ(s.scratch_disk_peak + s.scratch_memory_peak, total) << o.scratch_memory;  // every store lives to the end
    if (s.scratch_disk_peak > total - std::min(total, o.scratch_memory)) ++split_unevenly;
  }
  EXPECT_GT(total, 2 * plane);
  EXPECT_GT(split_unevenly, 0) << "no budget left room unused: the test shows nothing";
}

// Stores as large as the O_DIRECT threshold are files even when the budget holds everything: the
// bound counts all the scratch on disk then, and the solve keeps within it.
TEST(SizeGuard, DirectStoresCountOnDisk) {
  const Image img = test::random_image(w, h, c, 4);
  SolverOptions o = streamed();
  o.scratch_memory = std::size_t{1} << 30;
  o.direct_scratch_from = static_cast<std::size_t>(plane / 2);
  test::ExactGradients src(img, Domain::Cylindrical);
  SolveSummary s;
  solve(src, o, nullptr, &s);
  const cli::ScratchSplit bound = cli::split_scratch(static_cast<double>(s.scratch_bytes),
                                                     static_cast<double>(o.scratch_memory), plane, plane / 2);
  EXPECT_GT(s.scratch_disk_peak, 0u) << "no store went to a file: the test shows nothing";
  EXPECT_LE(static_cast<double>(s.scratch_disk_peak), bound.disk);
  EXPECT_LE(static_cast<double>(s.scratch_memory_peak), bound.memory);
}

TEST(SizeGuard, ScratchSplitsAtTheBudget) {
  EXPECT_EQ(cli::split_scratch(100, 200, 40).disk, 0.0);  // all fits
  EXPECT_EQ(cli::split_scratch(100, 200, 40).memory, 100.0);
  EXPECT_EQ(cli::split_scratch(100, 70, 40).disk, 70.0);  // a 40-byte store refused with just over 30 held
  EXPECT_EQ(cli::split_scratch(100, 70, 40).memory, 70.0);
  EXPECT_EQ(cli::split_scratch(100, 30, 40).disk, 100.0);  // no store need fit
  EXPECT_EQ(cli::split_scratch(100, 0, 40).disk, 100.0);
  EXPECT_EQ(cli::split_scratch(100, 200, 40, 40).disk, 100.0);  // a store as large as direct_from: a file anyway
  EXPECT_EQ(cli::split_scratch(100, 200, 40, 41).disk, 0.0);
  EXPECT_EQ(cli::split_scratch(100, 70, 40, 40).disk, 100.0);
}

}  // namespace
}  // namespace gdp
