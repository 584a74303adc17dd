// Scratch files: a window of the stream in the page cache (drop-behind), or none (O_DIRECT, checkpoints too).
#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/magic.h>
#include <sys/mman.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "io/scratch_stream.h"
#include "schedule/row_store.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// A new descriptor of this process's scratch file whose name contains `name` (-1 if none).
int open_scratch_again(const std::string& name) {
  int found = -1;
  DIR* dir = ::opendir("/proc/self/fd");
  while (dirent* e = dir ? ::readdir(dir) : nullptr) {
    const std::string link = "/proc/self/fd/" + std::string(e->d_name);
    char target[4096] = {};
    if (::readlink(link.c_str(), target, sizeof target - 1) > 0 && std::strstr(target, name.c_str())) {
      found = ::open(link.c_str(), O_RDONLY);
      break;
    }
  }
  if (dir) ::closedir(dir);
  return found;
}

// Bytes of the file's first `bytes` that are in the page cache.
std::size_t resident(int fd, std::size_t bytes) {
  const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  void* map = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, fd, 0);
  if (map == MAP_FAILED) return bytes;
  std::vector<unsigned char> in((bytes + page - 1) / page);
  ::mincore(map, bytes, in.data());
  ::munmap(map, bytes);
  std::size_t n = 0;
  for (unsigned char v : in) n += (v & 1) ? page : 0;
  return n;
}

// Writes and reads back 8 MB through a file store with the given drop-behind window; returns the
// bytes of the file in the page cache after writing and after reading.
std::pair<std::size_t, std::size_t> cached_bytes(std::size_t drop_behind, const std::string& name) {
  schedule::ScratchBudget none(0);  // no memory: a file through the page cache
  none.set_direct(false, 0);
  schedule::StorePolicy policy;
  policy.budget = &none;
  policy.drop_behind = drop_behind;
  const std::size_t n = 1000, rows = 2100;  // 8.4 MB of floats, rows not a multiple of a page
  schedule::RowStore<float> store(policy, n, rows, name);
  std::vector<float> row(n);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < n; ++i) row[i] = static_cast<float>(r * n + i);
    store.append(row);
  }
  store.rewind();  // flushes the tail
  const int fd = open_scratch_again(name);
  EXPECT_GE(fd, 0);
  const std::size_t after_writing = resident(fd, store.bytes());
  for (std::size_t r = 0; r < rows; ++r) {
    store.read(row);
    for (std::size_t i = 0; i < n; i += 101) EXPECT_EQ(row[i], static_cast<float>(r * n + i)) << r;
  }
  const std::size_t after_reading = resident(fd, store.bytes());
  ::close(fd);
  return {after_writing, after_reading};
}

TEST(ScratchFiles, KeepOnlyAWindowOfTheStreamInThePageCache) {
  struct statfs info{};
  ASSERT_EQ(::statfs(fs::temp_directory_path().c_str(), &info), 0);
  if (info.f_type == TMPFS_MAGIC) GTEST_SKIP() << "the temp directory is tmpfs: its pages are the file";
  const std::size_t total = 1000 * 2100 * sizeof(float);
  const auto [kept_written, kept_read] = cached_bytes(0, "keep-all");
  const auto [dropped_written, dropped_read] = cached_bytes(std::size_t{1} << 20, "drop-behind");
  // Without drop-behind the whole stream stays cached (this machine has memory to spare for 8 MB);
  // with a 1 MB window at most the last few windows (and the reads' readahead) do.
  EXPECT_GE(kept_written, total * 9 / 10);
  EXPECT_GE(kept_read, total * 9 / 10);
  EXPECT_LE(dropped_written, total / 2);
  EXPECT_LE(dropped_read, total / 2);
}

// True where the temp directory takes O_DIRECT files (not tmpfs).
bool temp_takes_direct() {
  const int fd = io::open_unlinked(fs::temp_directory_path(), "probe");
  const bool direct = io::make_direct(fd);
  ::close(fd);
  return direct;
}

// Row r, sample i: exact in half floats too (small integers).
float sample(std::size_t pass, std::size_t r, std::size_t i) { return static_cast<float>((pass * 7 + r * 3 + i) % 2000); }

// A store from the budget's direct_from() on is an O_DIRECT file even when the budget has room
// for it: rows that straddle its 4 KB blocks and chunks read back exactly, native and half,
// rewound twice, cleared and written again, and none of it in the page cache.
TEST(ScratchFiles, LargeStoresAreDirectFilesThatBypassThePageCache) {
  if (!temp_takes_direct()) GTEST_SKIP() << "the temp directory takes no O_DIRECT";
  schedule::ScratchBudget budget(std::size_t{1} << 30);
  budget.set_direct(true, std::size_t{4} << 20);
  schedule::StorePolicy policy;
  policy.budget = &budget;
  const std::size_t n = 3001, rows = 1500;  // 18 MB (9 as half floats): rows of 12004 and 6002 bytes
  for (const char* name : {"direct-native", "direct-half"}) {
    policy.half.all = name == std::string("direct-half");
    schedule::RowStore<float> store(policy, n, rows, name);
    ASSERT_TRUE(store.direct()) << name;
    EXPECT_EQ(budget.in_memory(), 0u);
    const int fd = open_scratch_again(name);
    std::vector<float> row(n);
    for (std::size_t pass = 0; pass < 2; ++pass) {
      store.clear();
      for (std::size_t r = 0; r < rows - pass; ++r) {
        for (std::size_t i = 0; i < n; ++i) row[i] = sample(pass, r, i);
        store.append(row);
      }
      for (int again = 0; again < 2; ++again) {
        store.rewind();
        for (std::size_t r = 0; r < rows - pass; ++r) {
          store.read(row);
          for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(row[i], sample(pass, r, i)) << name << " row " << r;
        }
      }
      EXPECT_EQ(store.bytes(), (rows - pass) * n * (store.half() ? 2 : 4));
      EXPECT_EQ(budget.on_disk(), rows * n * (store.half() ? 2 : 4));
      EXPECT_LE(resident(fd, store.bytes()), store.bytes() / 10) << name;
    }
    ::close(fd);
  }
  budget.set_direct(false, 0);  // off: the same store in memory
  EXPECT_FALSE(schedule::RowStore<float>(policy, n, rows, "off").on_disk());
}

// A solve's options set where direct files start: the library's default (kDirectScratchFrom) sends
// a large store to a file though the budget has room; a budget given (the CLI's --memory, which sets
// direct_scratch_from to SIZE_MAX) keeps it in memory while it fits and sends it to a file past it.
TEST(ScratchFiles, AGivenBudgetKeepsLargeStoresInMemoryWhileTheyFit) {
  if (!temp_takes_direct()) GTEST_SKIP() << "the temp directory takes no O_DIRECT";
  schedule::ScratchBudget budget;
  schedule::StorePolicy policy;
  policy.budget = &budget;
  const std::size_t n = 8192, rows = 2048;  // 64 MiB of floats: kDirectScratchFrom exactly
  SolverOptions options;
  options.scratch_memory = std::size_t{1} << 30;
  budget.apply(options);
  EXPECT_EQ(schedule::ScratchBudget::direct_from(options), kDirectScratchFrom);
  EXPECT_TRUE(schedule::RowStore<float>(policy, n, rows, "default").direct());
  options.direct_scratch_from = SIZE_MAX;
  budget.apply(options);
  EXPECT_EQ(schedule::ScratchBudget::direct_from(options), SIZE_MAX);
  EXPECT_FALSE(schedule::RowStore<float>(policy, n, rows, "given").on_disk());
  options.scratch_memory = std::size_t{32} << 20;  // past the budget: a file all the same
  budget.apply(options);
  EXPECT_TRUE(schedule::RowStore<float>(policy, n, rows, "past").direct());
}

// Rows longer than an O_DIRECT chunk (2 MiB): each spans several, and comes back whole.
TEST(ScratchFiles, DirectRowsLongerThanAChunkComeBackWhole) {
  if (!temp_takes_direct()) GTEST_SKIP() << "the temp directory takes no O_DIRECT";
  schedule::ScratchBudget budget(0);  // no memory: past the budget, a file (O_DIRECT from 1 MiB)
  schedule::StorePolicy policy;
  policy.budget = &budget;
  const std::size_t n = 1300001, rows = 5;  // rows of 5.2 MB
  schedule::RowStore<float> store(policy, n, rows, "long-rows");
  ASSERT_TRUE(store.direct());
  std::vector<float> row(n);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t i = 0; i < n; ++i) row[i] = sample(0, r, i);
    store.append(row);
  }
  store.rewind();
  for (std::size_t r = 0; r < rows; ++r) {
    store.read(row);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(row[i], sample(0, r, i)) << "row " << r << " sample " << i;
  }
}

// A checkpoint's O_DIRECT store made for `capacity` rows (its chunk follows): made durable at a
// length inside a block, written on, restored by a new store to that length (the padded file
// truncated), written on again: every row as written, and the kept file as long as the stream
// once it is made durable... and restored.
void restore_to_an_unaligned_length(std::size_t capacity) {
  const fs::path dir = fs::temp_directory_path() / ("gdp-direct-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  schedule::ScratchBudget budget(0);
  schedule::StorePolicy policy;
  policy.budget = &budget;
  policy.keep_dir = dir;
  const std::size_t n = 1001, rows = 900, kept = 517;  // 3.6 MB; 517 rows end inside a block
  std::vector<float> row(n);
  const auto fill = [&](std::size_t pass, std::size_t r) {
    for (std::size_t i = 0; i < n; ++i) row[i] = sample(pass, r, i);
  };
  std::size_t length = 0;
  {
    schedule::RowStore<float> store(policy, n, capacity, "kept");
    EXPECT_EQ(store.direct(), temp_takes_direct());
    for (std::size_t r = 0; r < rows; ++r) {
      fill(0, r);
      store.append(row);
      if (r + 1 == kept) length = store.make_durable();
    }
    store.rewind();
  }
  ASSERT_EQ(length, kept * n * sizeof(float));
  ASSERT_NE(length % 4096, 0u);
  schedule::RowStore<float> store(policy, n, capacity, "kept");
  store.restore(length);
  EXPECT_EQ(fs::file_size(dir / "kept.store"), length);
  for (std::size_t r = kept; r < rows; ++r) {
    fill(1, r);
    store.append(row);
  }
  EXPECT_EQ(store.make_durable(), rows * n * sizeof(float));
  store.rewind();
  for (std::size_t r = 0; r < rows; ++r) {
    store.read(row);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(row[i], sample(r < kept ? 0 : 1, r, i)) << "row " << r;
  }
  schedule::RowStore<float> shorter(policy, n, capacity, "kept");
  EXPECT_THROW(shorter.restore(fs::file_size(dir / "kept.store") + 1), OutputError);
  fs::remove_all(dir);
}

TEST(ScratchFiles, DirectCheckpointStoresRestoreToAnUnalignedLength) { restore_to_an_unaligned_length(900); }

// The same in a store made for 100 MB: its chunks at the cap, both buffers in one huge page.
TEST(ScratchFiles, BigDirectCheckpointStoresRestoreToAnUnalignedLength) { restore_to_an_unaligned_length(25000); }

// An O_DIRECT stream made for `expected` bytes of `record`-byte records: its chunk, and `rows`
// records written, then read back twice.
std::size_t direct_round_trip(std::size_t record, std::size_t expected, std::size_t rows) {
  const int fd = io::open_unlinked(fs::temp_directory_path(), "layout");
  EXPECT_TRUE(io::make_direct(fd));
  io::ScratchStream stream(fd, io::StreamKind::Direct, record, expected, 0, "layout", "");
  for (std::size_t r = 0; r < rows; ++r) {
    unsigned char* out = stream.append();
    for (std::size_t i = 0; i < record; ++i) out[i] = static_cast<unsigned char>((r * 31 + i) % 251);
  }
  for (int again = 0; again < 2; ++again) {
    stream.rewind();
    for (std::size_t r = 0; r < rows; ++r) {
      const unsigned char* in = stream.read();
      for (std::size_t i = 0; i < record; ++i)
        if (in[i] != static_cast<unsigned char>((r * 31 + i) % 251)) {
          ADD_FAILURE() << "record " << record << ": row " << r << " byte " << i;
          return stream.chunk();
        }
    }
  }
  EXPECT_EQ(stream.bytes(), rows * record);
  return stream.chunk();
}

// Chunks: whole records where records are whole blocks (or a few are), so none straddles two;
// at the cap (streams of 64 MiB and more) both buffers, each a chunk, a record and a block, fit
// one huge page. Records of other lengths straddle chunks and come back whole.
TEST(ScratchFiles, DirectChunksAreWholeRecordsAndBigStreamsFitAHugePage) {
  if (!temp_takes_direct()) GTEST_SKIP() << "the temp directory takes no O_DIRECT";
  const std::size_t big = std::size_t{512} << 20, mib = std::size_t{1} << 20;
  for (const std::size_t record : {std::size_t{32768}, std::size_t{12288}, std::size_t{98304}}) {
    const std::size_t chunk = direct_round_trip(record, big, 200);
    EXPECT_EQ(chunk % record, 0u) << record;
    EXPECT_LE(2 * io::align_up(chunk + record + io::kDirectAlign), io::kHugePage) << record;
    EXPECT_GE(chunk, mib / 2) << record;
  }
  const std::size_t odd = direct_round_trip(12004, big, 300);  // no whole number of blocks in a few
  EXPECT_EQ(odd % io::kDirectAlign, 0u);
  EXPECT_LE(2 * io::align_up(odd + 12004 + io::kDirectAlign), io::kHugePage);
  EXPECT_EQ(direct_round_trip(40960, 8 * mib, 100) % 40960, 0u);  // below the cap
  EXPECT_EQ(direct_round_trip(1 << 20, big, 12), std::size_t{1} << 20);  // records too long to share a page
}

// Huge buffers: whole huge pages at a huge page's alignment, all of them writable.
TEST(AlignedBytes, HugeBuffersAreWholeHugePagesOnTheirAlignment) {
  const io::AlignedBytes huge(3 * io::kHugePage / 2, true), small(5000);
  EXPECT_EQ(huge.size(), 2 * io::kHugePage);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(huge.data()) % io::kHugePage, 0u);
  std::memset(huge.data(), 7, huge.size());
  EXPECT_EQ(huge.data()[huge.size() - 1], 7);
  EXPECT_EQ(small.size(), 8192u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % io::kDirectAlign, 0u);
}

}  // namespace
}  // namespace gdp
