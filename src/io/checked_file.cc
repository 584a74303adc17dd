// Buffered POSIX file behind OpenImageIO writers that records write failures instead of reporting them.
#include "io/checked_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

namespace gdp::io {

namespace {
constexpr std::size_t kBufferBytes = std::size_t{1} << 18;  // codecs write in pieces of a few bytes to a strip
}

CheckedFile::CheckedFile(const std::string& path) : IOProxy(path, Write) {
  fd_ = ::open(path.c_str(), O_RDWR | O_TRUNC | O_CLOEXEC);
  if (fd_ < 0) {
    record(errno);
    m_mode = Closed;
  }
  buffer_.reserve(kBufferBytes);
}

CheckedFile::~CheckedFile() { CheckedFile::close(); }

void CheckedFile::record(int error) {
  if (failed()) return;
  problem_ = std::generic_category().message(error);
  failed_.store(true, std::memory_order_release);
}

std::string CheckedFile::problem() const {
  std::lock_guard lock(mutex_);
  return problem_;
}

void CheckedFile::put(const char* data, size_t size, int64_t offset) {
  while (size > 0 && !failed()) {
    const ssize_t n = ::pwrite(fd_, data, size, offset);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      record(n < 0 ? errno : EIO);
      return;
    }
    data += n;
    size -= static_cast<size_t>(n);
    offset += n;
  }
}

void CheckedFile::drain() {
  put(buffer_.data(), buffer_.size(), buffer_at_);
  buffer_at_ += static_cast<int64_t>(buffer_.size());
  buffer_.clear();
}

void CheckedFile::close() {
  std::lock_guard lock(mutex_);
  if (fd_ < 0) return;
  drain();
  if (::close(fd_) != 0) record(errno);
  fd_ = -1;
  m_mode = Closed;
}

bool CheckedFile::seek(int64_t offset) {
  std::lock_guard lock(mutex_);
  m_pos = offset;
  return offset >= 0;
}

size_t CheckedFile::read(void* buf, size_t size) {
  const size_t n = pread(buf, size, m_pos);
  std::lock_guard lock(mutex_);
  m_pos += static_cast<int64_t>(n);
  return n;
}

size_t CheckedFile::write(const void* buf, size_t size) {
  std::lock_guard lock(mutex_);
  if (fd_ < 0) return 0;
  // Sequential writes collect in the buffer; anything else writes it out first.
  if (m_pos != buffer_at_ + static_cast<int64_t>(buffer_.size())) {
    drain();
    buffer_at_ = m_pos;
  }
  const char* data = static_cast<const char*>(buf);
  if (buffer_.size() + size > kBufferBytes) drain();
  if (size >= kBufferBytes) {
    put(data, size, m_pos);
    buffer_at_ = m_pos + static_cast<int64_t>(size);
  } else {
    buffer_.insert(buffer_.end(), data, data + size);
  }
  m_pos += static_cast<int64_t>(size);
  end_ = std::max(end_, m_pos);
  return size;
}

size_t CheckedFile::pread(void* buf, size_t size, int64_t offset) {
  std::lock_guard lock(mutex_);
  if (fd_ < 0) return 0;
  drain();
  const ssize_t n = ::pread(fd_, buf, size, offset);
  return n > 0 ? static_cast<size_t>(n) : 0;
}

size_t CheckedFile::pwrite(const void* buf, size_t size, int64_t offset) {
  std::lock_guard lock(mutex_);
  if (fd_ < 0) return 0;
  drain();
  put(static_cast<const char*>(buf), size, offset);
  end_ = std::max(end_, offset + static_cast<int64_t>(size));
  return size;
}

size_t CheckedFile::size() const {
  std::lock_guard lock(mutex_);
  return static_cast<size_t>(end_);
}

}  // namespace gdp::io
