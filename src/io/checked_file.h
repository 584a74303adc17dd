// The file an OpenImageIO writer writes through: buffered, and never reporting a failed write.
#pragma once

#include <OpenImageIO/filesystem.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace gdp::io {

// Some codecs ignore failed writes (OpenImageIO 2.4's PNG and BMP writers leave a truncated
// file and report success) and libjpeg's writer calls exit() on one. Given this proxy, every
// write "succeeds": the first failure (disk full, file too large, I/O error) is recorded here
// instead, later writes are dropped, and the owner turns problem() into an OutputError.
// (OpenImageIO 2.4's JPEG writer, given a proxy, compresses the whole file into memory and
// writes it at close(); the other writers write as they go.)
class CheckedFile final : public OIIO::Filesystem::IOProxy {
 public:
  explicit CheckedFile(const std::string& path);  // opens an existing file for writing, truncated
  ~CheckedFile() override;
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;

  const char* proxytype() const override { return "gdp-checked"; }
  void close() override;  // writes what is buffered and closes; a failure is recorded
  bool seek(int64_t offset) override;
  size_t read(void* buf, size_t size) override;
  size_t write(const void* buf, size_t size) override;
  size_t pread(void* buf, size_t size, int64_t offset) override;
  size_t pwrite(const void* buf, size_t size, int64_t offset) override;
  size_t size() const override;
  void flush() const override {}

  bool failed() const { return failed_.load(std::memory_order_acquire); }
  std::string problem() const;  // e.g. "No space left on device"; empty while none

 private:
  void record(int error);                   // keeps the first failure
  void put(const char* data, size_t size, int64_t offset);  // unbuffered, whole
  void drain();                             // writes the buffer out

  mutable std::mutex mutex_;
  int fd_ = -1;
  std::vector<char> buffer_;  // bytes for [buffer_at_, buffer_at_ + buffer_.size())
  int64_t buffer_at_ = 0;
  int64_t end_ = 0;           // size of the file as written so far
  std::string problem_;
  std::atomic<bool> failed_{false};
};

}  // namespace gdp::io
