// Scratch blocks: a vector, or pread/pwrite on an unlinked file.
#include "blend/scratch.h"

#include <unistd.h>

#include <cstring>
#include <stdexcept>

#include "io/scratch_stream.h"
#include "util/exact_io.h"

namespace gdp::blending {

Scratch::Scratch(const std::filesystem::path& dir, std::size_t bytes, const std::string& name, std::size_t memory_limit)
    : bytes_(bytes), dir_(dir.empty() ? std::filesystem::temp_directory_path() : dir) {
  if (bytes <= memory_limit) {
    memory_.assign(bytes, 0);
  } else {
    fd_ = io::open_unlinked(dir_, name);
  }
}

Scratch::~Scratch() {
  if (fd_ >= 0) ::close(fd_);
}

namespace {
// What a scratch file's errors name: its directory, and where else it could go.
util::FileName scratch_name(const std::filesystem::path& dir) {
  return {dir.native(), "scratch file in ", " (--temp DIR puts scratch files elsewhere)"};
}
}  // namespace

void write_at(int fd, const void* data, std::size_t n, std::size_t at, const std::filesystem::path& dir) {
  util::write_exactly_at(fd, data, n, at, scratch_name(dir));
}

void read_at(int fd, void* data, std::size_t n, std::size_t at, const std::filesystem::path& dir) {
  util::read_exactly_at(fd, data, n, at, scratch_name(dir));
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
  // Past what was ever written (a sparse hole at the end): zeros.
  const std::size_t got = util::read_up_to_at(fd_, data, n, offset, scratch_name(dir_));
  std::memset(static_cast<unsigned char*>(data) + got, 0, n - got);
}

}  // namespace gdp::blending
