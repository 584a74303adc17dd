// Scratch files keep only a window of their stream in the page cache (RowStore's drop-behind).
#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/magic.h>
#include <sys/mman.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

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
  schedule::ScratchBudget none(0);  // no memory: a file
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

}  // namespace
}  // namespace gdp
