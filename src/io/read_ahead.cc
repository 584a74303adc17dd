// A scratch file read ahead on a thread: pread (or O_DIRECT block reads) into lent buffers, handed over through queues.
#include "io/read_ahead.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "io/aligned_bytes.h"
#include "util/exact_io.h"

namespace gdp::io {

util::Transfer read_chunk(int fd, unsigned char* p, std::size_t n, std::size_t at, bool direct) {
  if (!direct) return util::pread_full(fd, p, n, at);
  util::Transfer t;
  const std::size_t want = align_up(n);
  while (t.done < want) {
    const ssize_t k = ::pread(fd, p + t.done, want - t.done, static_cast<off_t>(at + t.done));
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) t.error = errno;
    if (k <= 0) break;
    t.done += static_cast<std::size_t>(k);
    if (t.done % kDirectAlign != 0) break;  // the end of the file
  }
  t.done = std::min(t.done, n);
  return t;
}

ReadAhead::ReadAhead(int fd, std::size_t begin, std::size_t end, std::size_t chunk,
                     std::span<unsigned char* const> buffers, DropBehind& drop, std::string where, bool direct,
                     std::size_t give_back)
    : where_(std::move(where)), free_(buffers.size()), full_(buffers.size()) {
  for (unsigned char* b : buffers) free_.push(Chunk{b});
  thread_ = std::thread(
      [this, fd, begin, end, chunk, &drop, direct, give_back] { run(fd, begin, end, chunk, drop, direct, give_back); });
}

ReadAhead::~ReadAhead() {
  free_.close();
  full_.close();
  thread_.join();
}

void ReadAhead::run(int fd, std::size_t begin, std::size_t end, std::size_t chunk, DropBehind& drop, bool direct,
                    std::size_t give_back) {
  std::size_t returned = begin;  // blocks before it were punched out
  for (std::size_t at = begin; at < end;) {
    std::optional<Chunk> c = free_.pop();
    if (!c) return;
    c->size = std::min(chunk, end - at);
    const util::Transfer t = read_chunk(fd, c->bytes, c->size, at, direct);
    c->error = t.error != 0 ? t.error : t.done < c->size ? -1 : 0;
    at += c->size;
    if (c->error != 0) at = end;  // the failed chunk is the last
    else drop.read(fd, at);
    if (!full_.push(*c)) return;
    // Read into the buffers: the file's blocks there are needed no more. A file system without
    // holes keeps them until the close.
    if (give_back > 0 && c->error == 0) returned = util::punch_behind(fd, returned, at, give_back, at == end);
  }
  full_.finish();
}

std::span<const unsigned char> ReadAhead::next() {
  if (held_) free_.push(*held_);
  held_ = full_.pop();
  if (!held_) return {};
  if (held_->error != 0)
    throw OutputError(fmt::format("{}: cannot read back: {}", where_,
                                  held_->error < 0 ? "file is shorter than written"
                                                   : std::generic_category().message(held_->error)));
  return {held_->bytes, held_->size};
}

}  // namespace gdp::io
