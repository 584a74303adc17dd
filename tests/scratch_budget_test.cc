// The scratch budget (--memory): stores in memory while it has room, in files beyond, same bits.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "gdp/errors.h"
#include "gdp/solver.h"
#include "schedule/row_store.h"
#include "schedule/scratch_budget.h"
#include "test_util.h"

namespace gdp {
namespace {

using schedule::RowStore;
using schedule::ScratchBudget;
using schedule::StorePolicy;

TEST(ScratchBudget, ReservesOnlyWhatFits) {
  ScratchBudget budget(1000);
  EXPECT_TRUE(budget.reserve(600));
  EXPECT_FALSE(budget.reserve(401));
  EXPECT_TRUE(budget.reserve(400));
  EXPECT_FALSE(budget.reserve(1));
  EXPECT_EQ(budget.in_memory(), 1000u);
  budget.release(600);
  EXPECT_EQ(budget.in_memory(), 400u);
  EXPECT_EQ(budget.peak_in_memory(), 1000u);
  EXPECT_FALSE(budget.reserve(std::size_t(-1)));  // no wrap-around
}


// A budget holds at most half of what the system can still give, however large its limit: a
// store that the limit allows goes to a file when memory is short.
TEST(ScratchBudget, HoldsAtMostHalfOfWhatIsAvailable) {
  ScratchBudget budget(std::size_t{1} << 30, [] { return std::size_t{1000}; });
  EXPECT_FALSE(budget.reserve(501));
  EXPECT_TRUE(budget.reserve(300));
  EXPECT_FALSE(budget.reserve(201));
  EXPECT_TRUE(budget.reserve(200));
  EXPECT_EQ(budget.in_memory(), 500u);
  ScratchBudget short_of_memory(std::size_t{1} << 30, [] { return std::size_t{4096}; });
  StorePolicy policy;
  policy.budget = &short_of_memory;
  RowStore<float> store(policy, 100, 200, "short");  // 80000 bytes, within the limit
  EXPECT_TRUE(store.on_disk());
  EXPECT_EQ(short_of_memory.spilled(), 1u);
  EXPECT_GT(ScratchBudget::system_available(), 0u);  // this machine's MemAvailable
}
TEST(ScratchBudget, StoresSpillToFilesBeyondTheBudget) {
  ScratchBudget budget(100000);
  StorePolicy policy;
  policy.budget = &budget;
  const std::size_t n = 100, rows = 200;  // 80000 bytes as float
  std::vector<float> row(n);
  {
    RowStore<float> first(policy, n, rows, "first");
    EXPECT_FALSE(first.on_disk());
    EXPECT_EQ(budget.in_memory(), n * rows * sizeof(float));
    RowStore<float> second(policy, n, rows, "second");  // 80000 more do not fit
    EXPECT_TRUE(second.on_disk());
    EXPECT_EQ(budget.spilled(), 1u);
    for (std::size_t r = 0; r < rows; ++r) {
      std::fill(row.begin(), row.end(), static_cast<float>(r));
      first.append(row);
      second.append(row);
    }
    first.rewind();
    second.rewind();  // flushes: the file holds every row
    EXPECT_EQ(budget.on_disk(), n * rows * sizeof(float));
    for (std::size_t r = 0; r < rows; ++r) {
      first.read(row);
      ASSERT_EQ(row[n - 1], static_cast<float>(r));
      second.read(row);
      ASSERT_EQ(row[0], static_cast<float>(r));
    }
  }
  EXPECT_EQ(budget.in_memory(), 0u);  // given back with the stores
  EXPECT_EQ(budget.on_disk(), 0u);
  EXPECT_EQ(budget.peak_on_disk(), n * rows * sizeof(float));
}

// In-memory stores are memfds written through a buffer like files: rows larger than the buffer,
// and a store written again after clear(), read back exactly; they hold their budget and no disk.
TEST(ScratchBudget, MemoryStoresKeepRowsAcrossTheirBufferFlushes) {
  ScratchBudget budget(std::size_t{64} << 20);
  StorePolicy policy;
  policy.budget = &budget;
  const std::size_t n = 100003, rows = 27;  // 10.8 MB of 400 KB rows: no row ends on a page
  RowStore<float> store(policy, n, rows, "steps");
  ASSERT_FALSE(store.on_disk());
  EXPECT_EQ(budget.in_memory(), n * rows * sizeof(float));
  std::vector<float> row(n);
  for (int pass = 0; pass < 2; ++pass) {
    store.clear();
    for (std::size_t r = 0; r < rows; ++r) {
      for (std::size_t i = 0; i < n; ++i) row[i] = static_cast<float>(pass * 1000003 + r * n + i);
      store.append(row);
    }
    store.rewind();
    EXPECT_EQ(store.bytes(), n * rows * sizeof(float));
    EXPECT_EQ(budget.on_disk(), 0u);
    for (std::size_t r = 0; r < rows; ++r) {
      store.read(row);
      for (std::size_t i = 0; i < n; i += 997) ASSERT_EQ(row[i], static_cast<float>(pass * 1000003 + r * n + i));
      ASSERT_EQ(row[n - 1], static_cast<float>(pass * 1000003 + r * n + n - 1));
    }
  }
}

// A store in memory told that its read is the last gives its pages back as the read passes them
// (the stream's length stays), so that nothing is left to free at the close; one read again keeps
// them. Rewinding a spent store is an error until it is cleared and written anew.
TEST(ScratchBudget, AMemoryStoreGivesItsPagesBackOnItsLastRead) {
  ScratchBudget budget(std::size_t{64} << 20);
  StorePolicy policy;
  policy.budget = &budget;
  const std::size_t n = 3001, rows = 1200;  // 14.4 MB of 12 kB rows
  RowStore<float> store(policy, n, rows, "last");
  ASSERT_FALSE(store.on_disk());
  std::vector<float> row(n);
  const auto write = [&](float k) {
    for (std::size_t r = 0; r < rows; ++r) {
      std::fill(row.begin(), row.end(), k + static_cast<float>(r));
      store.append(row);
    }
  };
  const auto read = [&](std::size_t from, std::size_t to, float k) {
    for (std::size_t r = from; r < to; ++r) {
      store.read(row);
      ASSERT_EQ(row[0], k + static_cast<float>(r));
      ASSERT_EQ(row[n - 1], k + static_cast<float>(r));
    }
  };
  const std::size_t total = n * rows * sizeof(float);
  write(0.0f);
  store.rewind();  // not the last: every page stays
  read(0, rows, 0.0f);
  EXPECT_GE(store.allocated(), total);
  store.rewind(true);
  EXPECT_GE(store.allocated(), total);
  read(0, rows / 2, 0.0f);
  const std::size_t page = 4096;  // (the last one partly filled)
  EXPECT_LE(store.allocated(), total + page - io::ScratchStream::kReturnBytes);  // whole runs behind the read
  EXPECT_GE(store.allocated(), total / 2 - io::ScratchStream::kReturnBytes);  // not those ahead of it
  read(rows / 2, rows, 0.0f);
  EXPECT_EQ(store.allocated(), 0u);
  EXPECT_EQ(store.bytes(), total);
  EXPECT_THROW(store.rewind(), std::logic_error);
  store.clear();  // written anew into the holes
  write(5.0f);
  store.rewind(true);
  read(0, rows, 5.0f);
  EXPECT_EQ(store.allocated(), 0u);
}

// A store in a file (through the page cache or O_DIRECT) gives its blocks back on its last read
// too, on its read-ahead thread (the close then frees nothing: "Scratch files given back on their
// last read", docs/how-streaming-works.md); a plain rewind keeps them, and a checkpoint's file
// keeps them on its last read (a resume reads them again).
TEST(ScratchBudget, AFileStoreGivesItsBlocksBackOnItsLastRead) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "gdp-budget-test-last-file";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::size_t n = 3001, rows = 1200, total = n * rows * sizeof(float);  // 14.4 MB of 12 kB rows
  std::vector<float> row(n);
  const auto write = [&](RowStore<float>& store, float k) {
    for (std::size_t r = 0; r < rows; ++r) {
      std::fill(row.begin(), row.end(), k + static_cast<float>(r));
      store.append(row);
    }
  };
  const auto read = [&](RowStore<float>& store, float k) {
    for (std::size_t r = 0; r < rows; ++r) {
      store.read(row);
      ASSERT_EQ(row[0], k + static_cast<float>(r));
      ASSERT_EQ(row[n - 1], k + static_cast<float>(r));
    }
  };
  for (const bool direct : {false, true}) {
    SCOPED_TRACE(direct ? "O_DIRECT where the directory takes it" : "page cache");
    ScratchBudget budget(1);  // no room in memory: a file
    budget.set_direct(direct, static_cast<std::size_t>(-1));
    StorePolicy policy;
    policy.budget = &budget;
    policy.dir = dir;
    RowStore<float> store(policy, n, rows, "last-file");
    ASSERT_TRUE(store.on_disk());
    write(store, 0.0f);
    store.rewind();  // not the last: every block stays
    read(store, 0.0f);
    EXPECT_GE(store.allocated(), total);
    store.rewind(true);
    read(store, 0.0f);
    store.clear();  // waits for the read-ahead thread, which punched the blocks out as it read
    EXPECT_EQ(store.allocated(), 0u);
    EXPECT_EQ(store.bytes(), 0u);
    write(store, 7.0f);  // written anew into the holes
    store.rewind(true);
    read(store, 7.0f);
    EXPECT_THROW(store.rewind(), std::logic_error);
  }
  {
    ScratchBudget budget(1);
    StorePolicy policy;
    policy.budget = &budget;
    policy.keep_dir = dir;
    RowStore<float> kept(policy, n, rows, "kept-last");
    write(kept, 3.0f);
    kept.rewind(true);
    read(kept, 3.0f);
    kept.rewind();  // not spent: its rows are all there
    read(kept, 3.0f);
    EXPECT_GE(kept.allocated(), total);
  }
  std::filesystem::remove_all(dir);
}

TEST(ScratchBudget, CheckpointStoresAreFilesWhateverTheBudget) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "gdp-budget-test-keep";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ScratchBudget budget(std::size_t{1} << 30);
  StorePolicy policy;
  policy.budget = &budget;
  policy.keep_dir = dir;
  {
    RowStore<float> store(policy, 10, 10, "kept");
    EXPECT_TRUE(store.on_disk());
    EXPECT_TRUE(std::filesystem::exists(dir / "kept.store"));
  }
  EXPECT_EQ(budget.in_memory(), 0u);
  std::filesystem::remove_all(dir);
}

TEST(ScratchBudget, QuantityEncodingsPickTheLongestMatchingName) {
  StorePolicy policy;
  policy.half.named["u"] = true;
  policy.half.named["level0-u"] = false;
  EXPECT_TRUE(policy.half.rounds("level3-u"));
  EXPECT_FALSE(policy.half.rounds("level0-u"));
  EXPECT_TRUE(policy.half.rounds("u"));
  EXPECT_FALSE(policy.half.rounds("level1-mu"));  // "-mu" is not "-u"
  EXPECT_FALSE(policy.half.rounds("level1-b"));
  RowStore<float> store(policy, 4, 4, "level2-u");
  EXPECT_TRUE(store.half());
  EXPECT_FALSE(RowStore<float>(policy, 4, 4, "level0-u").half());
}

TEST(ScratchBudget, MemorySizesParse) {
  EXPECT_EQ(parse_memory_size("512M"), std::size_t{512} << 20);
  EXPECT_EQ(parse_memory_size("4G"), std::size_t{4} << 30);
  EXPECT_EQ(parse_memory_size("4GB"), std::size_t{4} << 30);
  EXPECT_EQ(parse_memory_size("1.5g"), std::size_t{3} << 29);
  EXPECT_EQ(parse_memory_size("1000"), 1000u);
  EXPECT_EQ(parse_memory_size("0"), 0u);
  EXPECT_EQ(parse_memory_size("files"), 0u);
  for (const char* bad : {"", "abc", "-1", "5X", "4GiB", "G", " 4G", "1e400"})
    EXPECT_THROW(parse_memory_size(bad), UsageError) << bad;
  EXPECT_GT(default_scratch_memory(), 0u);
}

// Two V-cycles with every level but the coarsest streamed (so that every kind of store is made).
SolverOptions every_level_streamed() {
  SolverOptions o;
  o.coarsest_size = 5;
  o.incore_bytes = 0;
  o.vcycles = 2;
  return o;
}

// The same streaming solve with every store in files, some and all in memory: the same bits as
// in-core, and the budget held.
TEST(ScratchBudget, EveryBudgetGivesTheSameBits) {
  const Image img = test::random_image(160, 120, 3, 4);
  SolverOptions o = every_level_streamed();
  o.threads = 3;  // lanes make their stores concurrently
  o.schedule = Schedule::InCore;
  test::ExactGradients reference_source(img, Domain::Cylindrical, 0.0, 1.0);
  const Image reference = solve(reference_source, o);
  o.schedule = Schedule::Streaming;
  for (std::size_t budget : {std::size_t{0}, std::size_t{60000}, std::size_t{1} << 30}) {
    test::ExactGradients src(img, Domain::Cylindrical, 0.0, 1.0);
    o.scratch_memory = budget;
    SolveSummary s;
    const Image out = solve(src, o, nullptr, &s);
    ASSERT_EQ(out.data.size(), reference.data.size());
    EXPECT_EQ(std::memcmp(out.data.data(), reference.data.data(), out.data.size() * sizeof(float)), 0) << budget;
    EXPECT_LE(s.scratch_memory_peak, budget);
    if (budget < s.scratch_bytes) {
      EXPECT_GT(s.scratch_spilled, 0u) << budget;
    }
    if (budget == 0) {
      EXPECT_EQ(s.scratch_memory_peak, 0u);
    } else {
      EXPECT_GT(s.scratch_memory_peak, 0u) << budget;
    }
    if (budget >= (std::size_t{1} << 30)) {
      EXPECT_EQ(s.scratch_disk_peak, 0u);
      EXPECT_EQ(s.scratch_spilled, 0u);
    }
    EXPECT_EQ(ScratchBudget::process().in_memory(), 0u);  // all given back
  }
}

// Narrow scratch is every quantity as half floats, named one by one, but for the finest b and u
// when more V-cycles may run.
TEST(ScratchBudget, NarrowScratchIsEveryQuantityHalfButTheFinestWhenMoreCyclesRun) {
  const Image img = test::random_image(90, 70, 1, 8);
  for (int cycles : {1, 2}) {
    SolverOptions o = every_level_streamed();
    o.vcycles = cycles;
    o.scratch = ScratchPrecision::Narrow;
    test::ExactGradients src1(img, Domain::Planar), src2(img, Domain::Planar), src3(img, Domain::Planar);
    const Image all = solve(src1, o);
    o.scratch = ScratchPrecision::Float;
    o.half_quantities = {"w", "result"};
    for (int l = 1; l < 8; ++l)
      for (const char* q : {"-u", "-b"}) o.half_quantities.push_back("level" + std::to_string(l) + q);
    if (cycles == 1) o.half_quantities.insert(o.half_quantities.end(), {"level0-u", "level0-b"});
    const Image named = solve(src2, o);
    EXPECT_EQ(std::memcmp(all.data.data(), named.data.data(), all.data.size() * sizeof(float)), 0) << cycles;
    o.half_quantities = {"level0-u"};
    const Image some = solve(src3, o);
    EXPECT_NE(std::memcmp(all.data.data(), some.data.data(), all.data.size() * sizeof(float)), 0) << cycles;
  }
}

}  // namespace
}  // namespace gdp
