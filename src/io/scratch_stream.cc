// Scratch streams: one buffer filled by the caller, passed on to a memfd, a dropped-behind file or an O_DIRECT writer.
#include "io/scratch_stream.h"

#include <fcntl.h>
#include <linux/magic.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "util/exact_io.h"

namespace gdp::io {
namespace {

constexpr std::size_t kFileChunk = std::size_t{256} << 10;  // Memory and File: a write's, a read's size

// Direct: a 64th of the stream, from 64 KB to 1 MiB (a V-cycle fills all its stores at once, each
// with two buffers: the one filled, the one the disk takes; 2 MiB took 24 MB more at 16384²). At
// 8192² 256 KB chunks cost more system time than 1 and 4 MiB ones (docs/how-streaming-works.md,
// "Scratch in O_DIRECT files"). A chunk at the cap shrinks a little so that both buffers, each with
// room for a record and a block past the chunk, share one huge page (AlignedBytes: cheaper to pin;
// "Cheaper O_DIRECT stores"). A chunk is whole records where a record is whole blocks (or a few
// records are), so that no record straddles two chunks and no block is written twice.
struct DirectLayout {
  std::size_t chunk;
  bool huge;
};

DirectLayout direct_layout(std::size_t expected, std::size_t record) {
  constexpr std::size_t kCap = std::size_t{1} << 20;
  std::size_t chunk = std::clamp(align_up(expected / 64), std::size_t{64} << 10, kCap);
  const std::size_t slack = align_up(record) + kDirectAlign;
  const bool huge = chunk == kCap && 4 * slack <= kHugePage / 2;
  if (huge) chunk = kHugePage / 2 - slack;
  const std::size_t unit = std::lcm(std::max<std::size_t>(record, 1), kDirectAlign);
  return {unit <= chunk ? chunk / unit * unit : align_down(chunk), huge};
}

}  // namespace

int open_unlinked(const std::filesystem::path& dir, const std::string& name) {
  std::string pattern = (dir / fmt::format("gdp-scratch-{}-{}-XXXXXX", static_cast<long>(::getpid()), name)).string();
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0)
    throw OutputError(fmt::format("scratch directory {}: cannot create a file: {}", dir.string(), util::errno_message()));
  ::unlink(pattern.c_str());
  return fd;
}

bool make_direct(int fd) {
  struct statfs info{};
  if (::fstatfs(fd, &info) != 0 || info.f_type == TMPFS_MAGIC) return false;
  const int flags = ::fcntl(fd, F_GETFL);
  return flags >= 0 && ::fcntl(fd, F_SETFL, flags | O_DIRECT) == 0;
}

ScratchStream::ScratchStream(int fd, StreamKind kind, std::size_t record, std::size_t expected,
                             std::size_t drop_behind, std::string where, std::string hint)
    : fd_(fd),
      kind_(kind),
      record_(record),
      where_(std::move(where)),
      hint_(std::move(hint)),
      drop_behind_(kind == StreamKind::File ? drop_behind : 0) {
  // Filled to at least chunk_ before it is passed on, by records of record_ bytes.
  const DirectLayout direct = direct_layout(expected, record_);
  chunk_ = kind == StreamKind::Direct ? direct.chunk : std::max(align_up(std::min(expected, kFileChunk)), kDirectAlign);
  const std::size_t n = kind == StreamKind::Memory ? 1 : kind == StreamKind::Direct ? 2 : 3;
  const std::size_t each = align_up(chunk_ + record_ + kDirectAlign);
  if (kind == StreamKind::Direct && direct.huge) {
    buffers_.emplace_back(n * each, true);
    for (std::size_t k = 0; k < n; ++k) lent_.push_back(buffers_[0].data() + k * each);
  } else {
    for (std::size_t k = 0; k < n; ++k) buffers_.emplace_back(each);
    for (const AlignedBytes& b : buffers_) lent_.push_back(b.data());
  }
  cur_ = lent_[0];
  if (kind == StreamKind::Direct) {
    writer_ = std::make_unique<DirectWriter>(fd_, std::span(lent_).subspan(1), where_, hint_);
    straddle_.resize(record_);
  }
  if (kind != StreamKind::Memory) ::posix_fadvise(fd_, 0, 0, POSIX_FADV_SEQUENTIAL);  // a larger readahead
}

ScratchStream::~ScratchStream() {
  ahead_.reset();  // their threads use fd_ and the buffers
  writer_.reset();
  ::close(fd_);
}

unsigned char* ScratchStream::append() {
  if (reading_) throw std::logic_error("ScratchStream::append while reading");
  if (fill_ >= chunk_) pass_on(false);
  unsigned char* at = cur_ + fill_;
  fill_ += record_;
  return at;
}

// The buffer to the file: all of it (padded to a block for Direct, and waited for), or with
// `all` false the whole blocks of a Direct buffer, handed to the writer thread while the next
// fills. Direct's last partial block moves to the front of the next buffer, to be written again
// with what follows it.
void ScratchStream::pass_on(bool all) {
  if (!writer_) {
    util::write_exactly_at(fd_, cur_, fill_, base_, {where_, {}, hint_});
    base_ += fill_;
    fill_ = 0;
    if (!drop_behind_.wrote(fd_, base_)) throw OutputError(where_ + ": cannot write: " + util::errno_message());
    return;
  }
  if (all && fill_ == 0) return writer_->drain();
  const std::size_t whole = align_down(fill_);
  const unsigned char* const full = cur_;
  if (all) std::memset(cur_ + fill_, 0, align_up(fill_) - fill_);
  writer_->put(cur_, all ? align_up(fill_) : whole, base_);
  if (all) writer_->drain();
  cur_ = writer_->take();  // (the thread only reads `full`'s whole blocks meanwhile)
  std::memmove(cur_, full + whole, fill_ - whole);
  base_ += whole;
  fill_ -= whole;
}

void ScratchStream::rewind(bool last) {
  if (spent_) throw std::logic_error("ScratchStream::rewind after the last read");
  if (!reading_) pass_on(true);
  last_ = spent_ = last;
  returned_ = 0;
  ahead_.reset();
  drop_behind_.restart(0);
  // A file is read ahead on a thread of its own (the wait for its disk is that thread's); memory
  // is read by the reader itself, a chunk at a time (next_chunk()).
  if (kind_ != StreamKind::Memory)
    ahead_ = std::make_unique<ReadAhead>(fd_, 0, bytes(), read_chunk_bytes(), lent_, drop_behind_, where_,
                                         kind_ == StreamKind::Direct, last ? kReturnBytes : 0);
  chunk_at_ = nullptr;
  size_ = cursor_ = read_at_ = 0;
  reading_ = true;
}

// Chunks of whole records where the file takes any length, so that none straddles two; whole
// blocks for Direct (a record across two is copied: read()).
std::size_t ScratchStream::read_chunk_bytes() const {
  return kind_ == StreamKind::Direct ? chunk_ : std::max<std::size_t>(1, chunk_ / record_) * record_;
}

// The next chunk: from the ReadAhead's thread (a file), or read here (memory).
void ScratchStream::next_chunk() {
  if (ahead_) {
    const std::span<const unsigned char> c = ahead_->next();
    chunk_at_ = c.data();
    size_ = c.size();
  } else {
    size_ = std::min(read_chunk_bytes(), bytes() - read_at_);
    util::read_exactly_at(fd_, cur_, size_, read_at_, {where_});
    chunk_at_ = cur_;
    read_at_ += size_;
    // A memfd on its last read: the pages read go back to the system as they are copied out.
    if (last_) returned_ = util::punch_behind(fd_, returned_, read_at_, kReturnBytes, read_at_ == bytes());
  }
  cursor_ = 0;
  if (size_ == 0) throw std::logic_error("ScratchStream: read past the end");
}

std::size_t ScratchStream::allocated() const {
  struct stat st{};
  if (::fstat(fd_, &st) != 0) throw OutputError(where_ + ": " + util::errno_message());
  return static_cast<std::size_t>(st.st_blocks) * 512;
}

const unsigned char* ScratchStream::read() {
  if (!reading_) throw std::logic_error("ScratchStream::read before rewind");
  if (cursor_ == size_) next_chunk();
  if (cursor_ + record_ <= size_) {
    cursor_ += record_;
    return chunk_at_ + cursor_ - record_;
  }
  for (std::size_t got = 0; got < record_;) {  // across chunks (Direct only)
    if (cursor_ == size_) next_chunk();
    const std::size_t k = std::min(record_ - got, size_ - cursor_);
    std::memcpy(straddle_.data() + got, chunk_at_ + cursor_, k);
    got += k;
    cursor_ += k;
  }
  return straddle_.data();
}

void ScratchStream::clear() {
  ahead_.reset();
  if (writer_ && !reading_) writer_->drain();  // its buffers are ours again
  base_ = fill_ = 0;
  drop_behind_.restart(0);
  reading_ = last_ = spent_ = false;
}

std::size_t ScratchStream::make_durable() {
  if (!reading_) pass_on(true);
  if (::fdatasync(fd_) != 0) throw OutputError(where_ + ": cannot sync: " + util::errno_message());
  return bytes();
}

void ScratchStream::restore(std::size_t bytes) {
  ahead_.reset();
  if (writer_ && !reading_) writer_->drain();
  const off_t end = ::lseek(fd_, 0, SEEK_END);
  if (end < 0 || static_cast<std::size_t>(end) < bytes)
    throw OutputError(where_ + ": shorter than the checkpoint says (" + std::to_string(end) + " of " +
                      std::to_string(bytes) + " bytes)");
  if (::ftruncate(fd_, static_cast<off_t>(bytes)) != 0) throw OutputError(where_ + ": " + util::errno_message());
  base_ = kind_ == StreamKind::Direct ? align_down(bytes) : bytes;
  fill_ = bytes - base_;  // Direct: the last partial block, read back to be written again
  if (fill_ > 0 && read_chunk(fd_, cur_, fill_, base_, true).done < fill_)
    throw OutputError(where_ + ": cannot read back: " + util::errno_message());
  drop_behind_.restart(bytes);
  reading_ = last_ = spent_ = false;
}

}  // namespace gdp::io
