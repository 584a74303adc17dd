// Reads a scratch file front to back on a thread of its own, a chunk or two ahead of its reader.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <thread>

#include "io/drop_behind.h"
#include "util/bounded_queue.h"
#include "util/exact_io.h"

namespace gdp::io {

// `n` bytes of `fd` at `at`; `direct` (O_DIRECT): whole blocks into `p` (aligned, room for
// align_up(n) bytes), up to the end of the file where it ends inside the last.
util::Transfer read_chunk(int fd, unsigned char* p, std::size_t n, std::size_t at, bool direct);

// Bytes [begin, end) of `fd` in chunks of `chunk` bytes (the last may be shorter), read by a
// thread of its own into the caller's `buffers` (two or more, each at least `chunk` bytes, kept
// by the caller across passes): the reader holds one, the thread fills the others ahead of it. So
// the kernel's copies (and any wait for the disk) leave the reading thread, which keeps only its
// own work. `drop` hears of what has been read (drop-behind, on the thread). `direct`: `fd` is
// O_DIRECT, so `begin` and `chunk` are multiples of kDirectAlign, the buffers aligned and a
// whole block each (io/aligned_bytes.h), and the last chunk's block is read whole (the file may
// end inside it). `give_back` > 0: the read is the file's last, so the thread punches out its
// blocks behind what it has read (the buffers hold those bytes), in runs of `give_back` bytes and
// the rest at the end: the blocks' release (synchronous discards on a file system mounted with
// `discard`) is this thread's wait, spread over the read, not the closing thread's at the end
// (docs/how-streaming-works.md, "Scratch files given back on their last read"). Errors are
// OutputError naming `where` ("scratch file in DIR (NAME)"), thrown by next().
class ReadAhead {
 public:
  ReadAhead(int fd, std::size_t begin, std::size_t end, std::size_t chunk, std::span<unsigned char* const> buffers,
            DropBehind& drop, std::string where, bool direct = false, std::size_t give_back = 0);
  ~ReadAhead();  // stops the thread (what it read ahead is dropped)
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;
  // The next chunk, valid until the next call; empty past `end`.
  std::span<const unsigned char> next();

 private:
  struct Chunk {
    unsigned char* bytes = nullptr;
    std::size_t size = 0;
    int error = 0;  // errno where reading failed here (-1: the file is shorter than written)
  };
  void run(int fd, std::size_t begin, std::size_t end, std::size_t chunk, DropBehind& drop, bool direct,
           std::size_t give_back);

  std::string where_;
  util::BoundedQueue<Chunk> free_, full_;
  std::optional<Chunk> held_;  // the chunk next() handed out last
  std::thread thread_;
};

}  // namespace gdp::io
