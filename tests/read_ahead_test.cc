// io::ReadAhead: a file's bytes in order, chunk by chunk, errors named, no hang when dropped early.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "io/aligned_bytes.h"
#include "io/read_ahead.h"
#include "io/scratch_stream.h"

namespace gdp {
namespace {

// An unlinked scratch file holding `bytes` bytes, byte i = i * 7 mod 251.
int file_of(std::size_t bytes) {
  const int fd = io::open_unlinked(std::filesystem::temp_directory_path(), "read-ahead-test");
  std::vector<unsigned char> b(bytes);
  for (std::size_t i = 0; i < bytes; ++i) b[i] = static_cast<unsigned char>(i * 7 % 251);
  EXPECT_EQ(::pwrite(fd, b.data(), bytes, 0), static_cast<ssize_t>(bytes));
  return fd;
}

// Three aligned buffers of `bytes` each, lent to a ReadAhead.
struct Buffers {
  explicit Buffers(std::size_t bytes) {
    for (int k = 0; k < 3; ++k) own.emplace_back(bytes);
    for (const io::AlignedBytes& b : own) at.push_back(b.data());
  }
  std::vector<io::AlignedBytes> own;
  std::vector<unsigned char*> at;
};

TEST(ReadAhead, ChunksComeInOrderThenNothing) {
  const std::size_t bytes = 1000003, chunk = 65536, begin = 1000;
  const int fd = file_of(bytes);
  io::DropBehind drop(100000);
  Buffers buffers(chunk);
  io::ReadAhead ahead(fd, begin, bytes, chunk, buffers.at, drop, "test file");
  std::size_t at = begin;
  for (std::span<const unsigned char> c = ahead.next(); !c.empty(); c = ahead.next()) {
    EXPECT_EQ(c.size(), std::min(chunk, bytes - at));
    for (std::size_t i = 0; i < c.size(); ++i) ASSERT_EQ(c[i], static_cast<unsigned char>((at + i) * 7 % 251)) << at + i;
    at += c.size();
  }
  EXPECT_EQ(at, bytes);
  EXPECT_TRUE(ahead.next().empty());
  ::close(fd);
}

TEST(ReadAhead, AShortFileIsAnErrorNamingIt) {
  const std::size_t bytes = 300000, chunk = 65536;
  const int fd = file_of(bytes);
  io::DropBehind drop;
  Buffers buffers(chunk);
  io::ReadAhead ahead(fd, 0, bytes + 5 * chunk, chunk, buffers.at, drop, "scratch file in /x (u)");
  std::size_t got = 0;
  try {
    for (std::span<const unsigned char> c = ahead.next(); !c.empty(); c = ahead.next()) got += c.size();
    ADD_FAILURE() << "no error past the end of the file";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("scratch file in /x (u): cannot read back"), std::string::npos) << e.what();
  }
  EXPECT_EQ(got, bytes / chunk * chunk);  // the whole chunks before the short one
  ::close(fd);
}

TEST(ReadAhead, DroppedBeforeTheEndStopsItsThread) {
  const std::size_t bytes = 4 << 20, chunk = 4096;
  const int fd = file_of(bytes);
  io::DropBehind drop;
  Buffers buffers(chunk);
  for (int taken = 0; taken < 4; ++taken) {  // the reader stops after 0..3 chunks: the destructor must not hang
    io::ReadAhead ahead(fd, 0, bytes, chunk, buffers.at, drop, "test file");
    for (int k = 0; k < taken; ++k) EXPECT_EQ(ahead.next().size(), chunk);
  }
  ::close(fd);
}

// O_DIRECT: whole blocks, the file's last ending inside its block; where the temp directory
// refuses O_DIRECT (tmpfs) the same reads through the page cache.
TEST(ReadAhead, DirectReadsWholeBlocksUpToAnUnalignedEnd) {
  const std::size_t bytes = 3 * 65536 + 1234, chunk = 65536;
  const int fd = file_of(bytes);
  const bool direct = io::make_direct(fd);
  io::DropBehind drop;
  Buffers buffers(chunk);
  io::ReadAhead ahead(fd, 0, bytes, chunk, buffers.at, drop, "test file", direct);
  std::size_t at = 0;
  for (std::span<const unsigned char> c = ahead.next(); !c.empty(); c = ahead.next()) {
    ASSERT_EQ(c.size(), std::min(chunk, bytes - at));
    for (std::size_t i = 0; i < c.size(); ++i) ASSERT_EQ(c[i], static_cast<unsigned char>((at + i) * 7 % 251)) << at + i;
    at += c.size();
  }
  EXPECT_EQ(at, bytes);
  ::close(fd);
}

}  // namespace
}  // namespace gdp
