// Reads a scratch file front to back on a thread of its own, a chunk or two ahead of its reader.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "util/bounded_queue.h"
#include "io/drop_behind.h"

namespace gdp::schedule {

// Bytes [begin, end) of `fd` in chunks of `chunk` bytes (the last may be shorter), read by a
// thread of its own into three buffers: the reader holds one, the thread fills the others ahead of
// it. So the kernel's copies (and any wait for the disk) leave the reading thread, which keeps
// only its own work. `drop` hears of what has been read (drop-behind, on the thread). Errors are
// OutputError naming `where` ("scratch file in DIR (NAME)"), thrown by next().
class ReadAhead {
 public:
  ReadAhead(int fd, std::size_t begin, std::size_t end, std::size_t chunk, io::DropBehind& drop, std::string where);
  ~ReadAhead();  // stops the thread (what it read ahead is dropped)
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;
  // The next chunk, valid until the next call; empty past `end`.
  std::span<const unsigned char> next();

 private:
  struct Chunk {
    std::vector<unsigned char> bytes;
    std::size_t size = 0;
    std::string error;  // non-empty: reading failed here
  };
  void run(int fd, std::size_t begin, std::size_t end, std::size_t chunk, io::DropBehind& drop);

  std::string where_;
  util::BoundedQueue<Chunk> free_{3}, full_{3};
  std::optional<Chunk> held_;  // the chunk next() handed out last
  std::thread thread_;
};

}  // namespace gdp::schedule
