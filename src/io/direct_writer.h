// Writes a stream's aligned blocks to an O_DIRECT file on a thread of its own, from a few reused buffers.
#pragma once

#include <atomic>
#include <cstddef>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "util/bounded_queue.h"

namespace gdp::io {

// The writer fills a buffer (take()), hands it over with its file offset (put()) and fills the
// next while the thread writes it: the wait for the disk is the thread's, and memory stays
// bounded by the buffers lent (two or more; aligned, io/aligned_bytes.h). A file system that
// refuses O_DIRECT for a write (EINVAL) gets that write, and the file's later ones, through the
// page cache instead (the descriptor's O_DIRECT flag cleared). Errors are OutputError
// "<where>: cannot write: <reason><hint>", thrown by the next take() or drain().
class DirectWriter {
 public:
  DirectWriter(int fd, std::span<unsigned char* const> buffers, std::string where, std::string hint);
  ~DirectWriter();  // waits for the writes handed over, then stops the thread
  DirectWriter(const DirectWriter&) = delete;
  DirectWriter& operator=(const DirectWriter&) = delete;

  // A buffer free to fill (waits while every other one is being written).
  unsigned char* take();
  // Writes `size` bytes of `data` (a buffer from take()) at `at`: both multiples of kDirectAlign.
  void put(unsigned char* data, std::size_t size, std::size_t at);
  // Waits until every write handed over is done; the buffers are all free again.
  void drain();

 private:
  struct Job {
    unsigned char* data = nullptr;
    std::size_t size = 0, at = 0;
  };
  void run(int fd);
  void check() const;

  std::string where_, hint_;
  std::vector<unsigned char*> idle_;  // the caller's free buffers
  std::size_t out_ = 0;               // buffers with the thread
  std::atomic<int> error_{0};         // errno of the first failed write
  util::BoundedQueue<Job> jobs_;
  util::BoundedQueue<unsigned char*> done_;
  std::thread thread_;
};

}  // namespace gdp::io
