// Exact reads and writes on a file descriptor: every byte, through EINTR and short counts.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace gdp::util {

// How far a transfer got: `done` bytes, and the errno that stopped it (0: none). A read that
// meets the end of the file stops early with error 0; a write that makes no progress is ENOSPC.
struct Transfer {
  std::size_t done = 0;
  int error = 0;
};

// All n bytes (or up to the end of the file, for a read), retried on EINTR and short counts; never throw.
Transfer pread_full(int fd, void* data, std::size_t n, std::size_t at) noexcept;
Transfer pwrite_full(int fd, const void* data, std::size_t n, std::size_t at) noexcept;
Transfer write_full(int fd, const void* data, std::size_t n) noexcept;  // at the file's position

// Gives bytes [from, to) of fd back to the system (fallocate PUNCH_HOLE, the length kept); false
// where the kernel or file system takes no holes (the blocks then stay until the file closes).
bool punch_hole(int fd, std::size_t from, std::size_t to) noexcept;
// A stream's last read gives back what it has read: bytes [returned, at) of fd in whole runs of
// `step` bytes, or all of them at the `end` (the last run rounded up: past the length there is
// nothing). Returns how far the bytes are given back now (`returned` where nothing was).
std::size_t punch_behind(int fd, std::size_t returned, std::size_t at, std::size_t step, bool end) noexcept;

// errno's text now (after a failed system call), for messages.
std::string errno_message();

// The file an error message names, "<prefix><file>", with `hint` after a failed write's reason.
// Views only: nothing is formatted unless a transfer fails.
struct FileName {
  std::string_view file;
  std::string_view prefix = {};
  std::string_view hint = {};
};

// Exactly n bytes, or gdp::OutputError (these are a run's own files: scratch, checkpoints, outputs):
// "<name>: cannot write: <reason><hint>", "<name>: cannot read: <reason>" ("the file ends early"
// for a read past the end).
void write_exactly_at(int fd, const void* data, std::size_t n, std::size_t at, const FileName& name);
void write_exactly(int fd, const void* data, std::size_t n, const FileName& name);
void read_exactly_at(int fd, void* data, std::size_t n, std::size_t at, const FileName& name);
// Up to n bytes, fewer only at the end of the file; OutputError as above on an error.
std::size_t read_up_to_at(int fd, void* data, std::size_t n, std::size_t at, const FileName& name);

}  // namespace gdp::util
