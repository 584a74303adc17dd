// Bytes kept between the passes of a blend: in memory when small, else in an unlinked scratch file.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace gdp::blending {

// Exactly n bytes to / from a scratch file in `dir` at byte `at` (OutputError naming `dir` otherwise:
// a failed write, a full disk, a read past the end).
void write_at(int fd, const void* data, std::size_t n, std::size_t at, const std::filesystem::path& dir);
void read_at(int fd, void* data, std::size_t n, std::size_t at, const std::filesystem::path& dir);

// A fixed-size block of bytes read and written at any offset (rows of a plane, in any order).
class Scratch {
 public:
  // Up to `memory_limit` bytes stay in memory; more go to a file in `dir` (empty: the system's
  // temporary directory) that nothing else can see and that vanishes with the process.
  Scratch(const std::filesystem::path& dir, std::size_t bytes, const std::string& name,
          std::size_t memory_limit = std::size_t{8} << 20);
  ~Scratch();
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  void write(std::size_t offset, const void* data, std::size_t n);
  void read(std::size_t offset, void* data, std::size_t n) const;
  std::size_t bytes() const { return bytes_; }

 private:
  std::size_t bytes_;
  std::filesystem::path dir_;
  int fd_ = -1;
  std::vector<unsigned char> memory_;
};

}  // namespace gdp::blending
