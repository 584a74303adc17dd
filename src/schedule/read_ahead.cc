// A scratch file read ahead on a thread: pread into recycled chunks, handed over through queues.
#include "schedule/read_ahead.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <optional>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "util/exact_io.h"

namespace gdp::schedule {

ReadAhead::ReadAhead(int fd, std::size_t begin, std::size_t end, std::size_t chunk, io::DropBehind& drop, std::string where)
    : where_(std::move(where)) {
  for (int k = 0; k < 3; ++k) free_.push(Chunk{});
  thread_ = std::thread([this, fd, begin, end, chunk, &drop] { run(fd, begin, end, chunk, drop); });
}

ReadAhead::~ReadAhead() {
  free_.close();
  full_.close();
  thread_.join();
}

void ReadAhead::run(int fd, std::size_t begin, std::size_t end, std::size_t chunk, io::DropBehind& drop) {
  for (std::size_t at = begin; at < end;) {
    std::optional<Chunk> c = free_.pop();
    if (!c) return;
    c->size = std::min(chunk, end - at);
    c->bytes.resize(c->size);
    const util::Transfer t = util::pread_full(fd, c->bytes.data(), c->size, at);
    if (t.error != 0) c->error = std::generic_category().message(t.error);
    else if (t.done < c->size) c->error = "file is shorter than written";
    at += c->size;
    if (!c->error.empty()) at = end;  // the failed chunk is the last
    else drop.read(fd, at);
    if (!full_.push(std::move(*c))) return;
  }
  full_.finish();
}

std::span<const unsigned char> ReadAhead::next() {
  if (held_) free_.push(std::move(*held_));
  held_ = full_.pop();
  if (!held_) return {};
  if (!held_->error.empty()) throw OutputError(fmt::format("{}: cannot read back: {}", where_, held_->error));
  return {held_->bytes.data(), held_->size};
}

}  // namespace gdp::schedule
