// Buffered POSIX output file that records write failures instead of reporting them.
#include "io/output_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

#include "util/exact_io.h"

namespace gdp::io {

namespace {
constexpr std::size_t kBufferBytes = std::size_t{1} << 18;  // codecs write in pieces of a few bytes
}

OutputFile::OutputFile(const std::string& path) {
  fd_ = ::open(path.c_str(), O_RDWR | O_TRUNC | O_CLOEXEC);
  if (fd_ < 0) record(errno);
  buffer_.reserve(kBufferBytes);
}

OutputFile::~OutputFile() { close(); }

void OutputFile::record(int error) {
  if (failed()) return;
  problem_ = std::generic_category().message(error);
  failed_.store(true, std::memory_order_release);
}

std::string OutputFile::problem() const {
  std::lock_guard lock(mutex_);
  return problem_;
}

void OutputFile::put(const char* data, std::size_t size, std::int64_t offset) {
  if (failed()) return;
  const util::Transfer t = util::pwrite_full(fd_, data, size, static_cast<std::size_t>(offset));
  if (t.error != 0) {
    record(t.error);
    return;
  }
  put_end_ = std::max(put_end_, static_cast<std::size_t>(offset) + size);
  if (!failed() && !drop_behind_.wrote(fd_, put_end_)) record(errno);
}

void OutputFile::drain() {
  put(buffer_.data(), buffer_.size(), buffer_at_);
  buffer_at_ += static_cast<std::int64_t>(buffer_.size());
  buffer_.clear();
}

void OutputFile::write_at(std::int64_t offset, const void* data, std::size_t size) {
  std::lock_guard lock(mutex_);
  if (fd_ < 0) return;
  if (offset != buffer_at_ + static_cast<std::int64_t>(buffer_.size())) {
    drain();
    buffer_at_ = offset;
  }
  const char* bytes = static_cast<const char*>(data);
  if (buffer_.size() + size > kBufferBytes) drain();
  if (size >= kBufferBytes) {
    put(bytes, size, offset);
    buffer_at_ = offset + static_cast<std::int64_t>(size);
  } else {
    buffer_.insert(buffer_.end(), bytes, bytes + size);
  }
  end_ = std::max(end_, offset + static_cast<std::int64_t>(size));
}

std::size_t OutputFile::read_at(std::int64_t offset, void* data, std::size_t size) {
  std::lock_guard lock(mutex_);
  if (fd_ < 0) return 0;
  drain();
  return util::pread_full(fd_, data, size, static_cast<std::size_t>(offset)).done;
}

std::int64_t OutputFile::size() const {
  std::lock_guard lock(mutex_);
  return end_;
}

void OutputFile::close() {
  std::lock_guard lock(mutex_);
  if (fd_ < 0) return;
  drain();
  if (::close(fd_) != 0) record(errno);
  fd_ = -1;
}

}  // namespace gdp::io
