// Scratch storage for a level's rows between the two passes of a streaming V-cycle.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <type_traits>

#include "multigrid/half_policy.h"
#include "io/drop_behind.h"
#include "io/scratch_stream.h"
#include "schedule/bytes.h"
#include "schedule/scratch_budget.h"

namespace gdp::schedule {

// Where rows are kept: in memory while `budget` has room for the whole stream (an anonymous
// memfd: page-cache pages that no disk backs, written and read like a file, never mapped), else
// in an unlinked file in `dir` (the space returns to the system when the store is destroyed or
// the process dies, however it dies).
struct StorePolicy {
  std::filesystem::path dir;
  ScratchBudget* budget = nullptr;  // shared by many stores (null: ScratchBudget::process())
  // Which stores keep 16-bit half floats, by name (multigrid::HalfPolicy: "u" every level's u,
  // "level0-u" the finest only); the rest keep the kernel's precision.
  multigrid::HalfPolicy half;
  // Non-empty (a checkpoint's directory): every store is a named file `keep_dir/NAME.store`,
  // kept after the process ends, whatever its size (docs/resume.md).
  std::filesystem::path keep_dir;
  std::string name_prefix;  // put before every store's name (a lane's, "lane0-")
  // How far behind the write (and read) position a file store's bytes are pushed to the disk and
  // dropped from the page cache (io/drop_behind.h; 0: never). A memory store keeps every page.
  std::size_t drop_behind = io::kDropBehindWindow;
};

// A sequential stream of equal-length rows of T: append them, rewind(), read them back in the
// same order (as often as needed); clear() starts writing anew. The bytes go through an
// io::ScratchStream: a memfd, a file through the page cache, or an O_DIRECT file (a store of at
// least ScratchBudget::direct_from() bytes whatever the budget, or one past the budget: "Scratch in
// O_DIRECT files", docs/how-streaming-works.md).
template <class T>
class RowStore {
 public:
  // A store for up to `rows` rows of `row_length` samples.
  RowStore(const StorePolicy& policy, std::size_t row_length, std::size_t rows, std::string name);
  ~RowStore();
  RowStore(const RowStore&) = delete;
  RowStore& operator=(const RowStore&) = delete;

  void append(std::span<const T> row);
  // `last`: the coming read is the store's last (its pages or blocks go back as it is read;
  // io::ScratchStream::rewind), but for a checkpoint's file, which keeps them.
  void rewind(bool last = false);
  void read(std::span<T> row);
  void clear() { stream_->clear(); }
  // Bytes of the stream so far (what it occupies on disk or in memory).
  std::size_t bytes() const { return stream_->bytes(); }
  // Bytes it holds now (less than bytes() once a last read has given pages back).
  std::size_t allocated() const { return stream_->allocated(); }
  bool on_disk() const { return stream_->kind() != io::StreamKind::Memory; }
  bool direct() const { return stream_->kind() == io::StreamKind::Direct; }
  bool half() const { return half_; }  // rows kept as half floats

  // Checkpoints (kept files only): writes what is buffered, syncs the file and returns the
  // stream's length; restore() makes the stream that long again (truncating what came after),
  // ready to append or to rewind. OutputError when the file is shorter than that.
  std::size_t make_durable();
  void restore(std::size_t bytes);

 private:
  void count_disk();
  std::size_t encoded_bytes() const;

  std::size_t row_length_;
  bool half_;
  bool kept_;  // a checkpoint's named file (StorePolicy::keep_dir)
  ScratchBudget* budget_ = nullptr;  // holds memory_, counts a disk file's bytes
  std::size_t memory_ = 0;           // bytes taken from the budget (a store in memory)
  std::size_t disk_bytes_ = 0;       // counted so far
  std::unique_ptr<io::ScratchStream> stream_;
};

// A row store's length in a checkpoint state (Archive: ByteWriter or ByteReader): saving makes
// the store durable and writes its length, loading truncates the store to it.
template <class Archive, class T>
void store_state(Archive& a, RowStore<T>* store) {
  std::size_t bytes = 0;
  if constexpr (std::is_same_v<Archive, ByteWriter>) bytes = store ? store->make_durable() : 0;
  a.io(bytes);
  if constexpr (std::is_same_v<Archive, ByteReader>) {
    if (store) store->restore(bytes);
    else if (bytes) throw CorruptState("a store this state does not have");
  }
}

}  // namespace gdp::schedule
