// Keeps a file that is written or read front to back out of the page cache, a window behind.
#pragma once

#include <cstddef>

namespace gdp::io {

// For one file descriptor streamed sequentially: once a window of bytes has been written since
// the last push, starts their writeback, waits for the window before to reach the disk and drops
// it from the page cache; when reading, drops what has been read a window at a time. So the
// stream holds about two windows of the cache whatever its length, and the pages it frees are the
// ones it takes next. On this VM a buffered write into fresh page-cache pages costs about 3.2 s
// of system time per GB, one that recycles them 0.4 s (bench/scratch_io_bench.cc,
// docs/how-streaming-works.md "Scratch in files"). Window 0: does nothing.
// The window the scratch stores, large inputs and outputs use: 32 MB (docs/how-streaming-works.md).
inline constexpr std::size_t kDropBehindWindow = std::size_t{32} << 20;

class DropBehind {
 public:
  explicit DropBehind(std::size_t window = 0) : window_(window) {}

  // A new pass (writing or reading) starts at byte `at`.
  void restart(std::size_t at) { pushed_ = dropped_ = at; }
  // The file holds what was written up to `end`. False when the disk reported an error (errno).
  bool wrote(int fd, std::size_t end);
  // Bytes up to `end` have been read and are not needed again in this pass.
  void read(int fd, std::size_t end);

 private:
  std::size_t window_;
  std::size_t pushed_ = 0, dropped_ = 0;  // writeback started / dropped up to here
};

}  // namespace gdp::schedule
