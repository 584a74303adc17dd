// Exact reads and writes on a file descriptor: the one retry loop, and the errors naming the file.
#include "util/exact_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>

#include "gdp/errors.h"

namespace gdp::util {
namespace {

// One pass of pread / pwrite / write over n bytes: `step(p, left, at)` moves some of them.
template <class Byte, class Step>
Transfer loop(Byte* p, std::size_t n, std::size_t at, bool is_read, Step step) noexcept {
  Transfer t;
  while (t.done < n) {
    const ssize_t k = step(p + t.done, n - t.done, at + t.done);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) {
      t.error = errno;
      break;
    }
    if (k == 0) {  // a read at the end of the file; a write that cannot go on
      if (!is_read) t.error = ENOSPC;
      break;
    }
    t.done += static_cast<std::size_t>(k);
  }
  return t;
}

[[noreturn]] void fail(const FileName& name, std::string_view verb, const std::string& reason, std::string_view hint) {
  std::string message;
  message.append(name.prefix).append(name.file).append(": cannot ").append(verb).append(": ");
  message.append(reason).append(hint);
  throw OutputError(message);
}

std::string reason_of(int error) { return std::generic_category().message(error); }

}  // namespace

bool punch_hole(int fd, std::size_t from, std::size_t to) noexcept {
  return ::fallocate(fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, static_cast<off_t>(from),
                     static_cast<off_t>(to - from)) == 0;
}

std::size_t punch_behind(int fd, std::size_t returned, std::size_t at, std::size_t step, bool end) noexcept {
  const std::size_t to = (end ? at + step - 1 : at) / step * step;
  return to > returned && punch_hole(fd, returned, to) ? to : returned;
}

std::string errno_message() { return reason_of(errno); }

Transfer pread_full(int fd, void* data, std::size_t n, std::size_t at) noexcept {
  return loop(static_cast<unsigned char*>(data), n, at, true, [fd](unsigned char* p, std::size_t left, std::size_t off) {
    return ::pread(fd, p, left, static_cast<off_t>(off));
  });
}

Transfer pwrite_full(int fd, const void* data, std::size_t n, std::size_t at) noexcept {
  return loop(static_cast<const unsigned char*>(data), n, at, false,
              [fd](const unsigned char* p, std::size_t left, std::size_t off) {
                return ::pwrite(fd, p, left, static_cast<off_t>(off));
              });
}

Transfer write_full(int fd, const void* data, std::size_t n) noexcept {
  return loop(static_cast<const unsigned char*>(data), n, 0, false,
              [fd](const unsigned char* p, std::size_t left, std::size_t) { return ::write(fd, p, left); });
}

void write_exactly_at(int fd, const void* data, std::size_t n, std::size_t at, const FileName& name) {
  const Transfer t = pwrite_full(fd, data, n, at);
  if (t.error != 0) fail(name, "write", reason_of(t.error), name.hint);
}

void write_exactly(int fd, const void* data, std::size_t n, const FileName& name) {
  const Transfer t = write_full(fd, data, n);
  if (t.error != 0) fail(name, "write", reason_of(t.error), name.hint);
}

std::size_t read_up_to_at(int fd, void* data, std::size_t n, std::size_t at, const FileName& name) {
  const Transfer t = pread_full(fd, data, n, at);
  if (t.error != 0) fail(name, "read", reason_of(t.error), {});
  return t.done;
}

void read_exactly_at(int fd, void* data, std::size_t n, std::size_t at, const FileName& name) {
  if (read_up_to_at(fd, data, n, at, name) < n) fail(name, "read", "the file ends early", {});
}

}  // namespace gdp::util
