// A scratch byte stream on a memfd, a file through the page cache, or an O_DIRECT file; unlinked scratch files.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/aligned_bytes.h"
#include "io/direct_writer.h"
#include "io/drop_behind.h"
#include "io/read_ahead.h"

namespace gdp::io {

// How a scratch stream reaches its bytes. Memory: a memfd, written and read back by its caller.
// File: a file through the page cache, dropped behind (io/drop_behind.h), read back by a
// ReadAhead thread. Direct: an O_DIRECT file (no page cache: docs/how-streaming-works.md, "Scratch
// in O_DIRECT files"), written in aligned blocks by a DirectWriter thread and read back by a ReadAhead.
enum class StreamKind { Memory, File, Direct };

// An exclusive file in `dir`, unlinked at once: only the returned descriptor keeps it alive
// (OutputError naming the directory when it cannot be created).
int open_unlinked(const std::filesystem::path& dir, const std::string& name);

// Makes `fd` O_DIRECT where its file system takes that (not tmpfs, whose pages are the file);
// false, and `fd` unchanged, where it does not.
bool make_direct(int fd);

// A sequential stream of records of `record` bytes on `fd` (owned: closed by the destructor):
// append them, rewind(), read them back in the same order (as often as needed); clear() starts
// writing anew; rewind(true) says the coming read is the stream's last: a memfd then gives its
// pages back behind the read position as it goes (every kReturnBytes), a file its blocks behind
// its ReadAhead thread's reads, so that nothing is left to free when the stream closes
// (docs/how-streaming-works.md, "The e2e stitch, third round" and "Scratch files given back on
// their last read"); rewinding again before a clear() is a logic error. Its buffers are made once (one for Memory,
// three for File, of 256 KB or the `expected` length if shorter; two for Direct, of 64 KB to
// 1 MiB, whole records where records are whole blocks, in one huge page at the cap) and reused
// for every pass. A Direct stream writes whole blocks, its last padded; bytes() is the length written, and
// make_durable()/restore() keep it (a checkpoint's file may be longer; restore truncates it).
// Errors are OutputError naming `where`, with `hint` after a failed write's reason.
class ScratchStream {
 public:
  ScratchStream(int fd, StreamKind kind, std::size_t record, std::size_t expected, std::size_t drop_behind,
                std::string where, std::string hint);
  ~ScratchStream();
  ScratchStream(const ScratchStream&) = delete;
  ScratchStream& operator=(const ScratchStream&) = delete;

  // Room for the next record, to be filled before the next call.
  unsigned char* append();
  void rewind(bool last = false);
  // The next record, valid until the next call.
  const unsigned char* read();
  void clear();
  // Checkpoints: writes what is buffered, syncs the file and returns the stream's length;
  // restore() makes the stream that long again (truncating what came after), ready to append
  // or to rewind. OutputError when the file is shorter than that.
  std::size_t make_durable();
  void restore(std::size_t bytes);

  std::size_t bytes() const { return base_ + fill_; }
  // Bytes the file holds (its allocated blocks: a memfd's pages), for the tests.
  std::size_t allocated() const;
  // A memfd on its last read gives back its pages in runs of this many bytes (aligned: whole
  // 2 MiB blocks of the page allocator, the unit the VM's free page reporting takes).
  static constexpr std::size_t kReturnBytes = std::size_t{4} << 20;
  StreamKind kind() const { return kind_; }
  std::size_t chunk() const { return chunk_; }  // bytes passed on (and read back) at once

 private:
  void pass_on(bool all);
  void next_chunk();
  std::size_t read_chunk_bytes() const;

  int fd_;
  StreamKind kind_;
  std::size_t record_, chunk_;
  std::string where_, hint_;
  std::vector<AlignedBytes> buffers_;
  std::vector<unsigned char*> lent_;         // buffers_' addresses, lent to the threads
  unsigned char* cur_;                       // the buffer being filled
  std::size_t base_ = 0, fill_ = 0;          // its offset in the file, and the bytes in it
  const unsigned char* chunk_at_ = nullptr;  // the chunk being read: size_ bytes, cursor_ read
  std::size_t size_ = 0, cursor_ = 0, read_at_ = 0;
  bool last_ = false, spent_ = false;        // this read is the last (Memory: pages given back); one was
  std::size_t returned_ = 0;                 // bytes given back so far
  std::vector<unsigned char> straddle_;      // a record across two chunks (Direct)
  DropBehind drop_behind_;
  std::unique_ptr<DirectWriter> writer_;
  std::unique_ptr<ReadAhead> ahead_;
  bool reading_ = false;
};

}  // namespace gdp::io
