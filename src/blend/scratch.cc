// Scratch blocks: a vector, or pread/pwrite on an unlinked file.
#include "blend/scratch.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "schedule/row_store.h"

namespace gdp::blending {

Scratch::Scratch(const std::filesystem::path& dir, std::size_t bytes, const std::string& name, std::size_t memory_limit)
    : bytes_(bytes), dir_(dir.empty() ? std::filesystem::temp_directory_path() : dir) {
  if (bytes <= memory_limit) {
    memory_.assign(bytes, 0);
  } else {
    fd_ = schedule::open_unlinked(dir_, name);
  }
}

Scratch::~Scratch() {
  if (fd_ >= 0) ::close(fd_);
}

void write_at(int fd, const void* data, std::size_t n, std::size_t at, const std::filesystem::path& dir) {
  const auto* p = static_cast<const unsigned char*>(data);
  while (n > 0) {
    const ssize_t k = ::pwrite(fd, p, n, static_cast<off_t>(at));
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0)
      throw OutputError(fmt::format("scratch file in {}: cannot write: {} (--temp DIR puts scratch files elsewhere)",
                                    dir.string(), k < 0 ? std::generic_category().message(errno) : "no space"));
    p += k;
    at += static_cast<std::size_t>(k);
    n -= static_cast<std::size_t>(k);
  }
}

void read_at(int fd, void* data, std::size_t n, std::size_t at, const std::filesystem::path& dir) {
  auto* p = static_cast<unsigned char*>(data);
  while (n > 0) {
    const ssize_t k = ::pread(fd, p, n, static_cast<off_t>(at));
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0)
      throw OutputError(fmt::format("scratch file in {}: cannot read: {}", dir.string(),
                                    k < 0 ? std::generic_category().message(errno) : "past its end"));
    p += k;
    at += static_cast<std::size_t>(k);
    n -= static_cast<std::size_t>(k);
  }
}

void Scratch::write(std::size_t offset, const void* data, std::size_t n) {
  if (offset + n > bytes_) throw std::logic_error("Scratch::write past the end");
  if (fd_ < 0) {
    std::memcpy(memory_.data() + offset, data, n);
    return;
  }
  write_at(fd_, data, n, offset, dir_);
}

void Scratch::read(std::size_t offset, void* data, std::size_t n) const {
  if (offset + n > bytes_) throw std::logic_error("Scratch::read past the end");
  if (fd_ < 0) {
    std::memcpy(data, memory_.data() + offset, n);
    return;
  }
  auto* p = static_cast<unsigned char*>(data);
  while (n > 0) {
    const ssize_t k = ::pread(fd_, p, n, static_cast<off_t>(offset));
    if (k < 0 && errno == EINTR) continue;
    if (k < 0)
      throw OutputError(fmt::format("scratch file in {}: cannot read: {}", dir_.string(),
                                    std::generic_category().message(errno)));
    if (k == 0) {  // never written (a sparse hole past the end): zeros
      std::memset(p, 0, n);
      return;
    }
    p += k;
    offset += static_cast<std::size_t>(k);
    n -= static_cast<std::size_t>(k);
  }
}

}  // namespace gdp::blending
