// The file an encoder writes through: buffered, and recording (never reporting) a failed write.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "io/drop_behind.h"

namespace gdp::io {

// Some codecs ignore failed writes (OpenImageIO 2.4's PNG and BMP writers leave a truncated file
// and report success) and libjpeg's stdio destination calls exit() on one. Written through this,
// every write "succeeds": the first failure (disk full, file too large, I/O error) is recorded
// instead, later writes are dropped, and the encoder turns problem() into an error. Writes at
// the end of what was written so far collect in a buffer; others write it out first.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path);  // opens an existing file for writing, truncated
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write_at(std::int64_t offset, const void* data, std::size_t size);
  std::size_t read_at(std::int64_t offset, void* data, std::size_t size);  // 0 past the end or closed
  std::int64_t size() const;  // of the file as written so far
  void close();               // writes what is buffered and closes; a failure is recorded

  bool failed() const { return failed_.load(std::memory_order_acquire); }
  std::string problem() const;  // e.g. "No space left on device"; empty while none

 private:
  void record(int error);                                         // keeps the first failure
  void put(const char* data, std::size_t size, std::int64_t offset);  // unbuffered, whole
  void drain();                                                   // writes the buffer out

  mutable std::mutex mutex_;
  int fd_ = -1;
  std::vector<char> buffer_;  // bytes for [buffer_at_, buffer_at_ + buffer_.size())
  std::int64_t buffer_at_ = 0;
  std::int64_t end_ = 0;
  std::size_t put_end_ = 0;  // the furthest byte put() has written
  // What was written goes to the disk and out of the page cache 32 MB behind (a gigapixel output
  // would otherwise take GBs of fresh cache pages: io/drop_behind.h).
  DropBehind drop_behind_{kDropBehindWindow};
  std::string problem_;
  std::atomic<bool> failed_{false};
};

}  // namespace gdp::io
