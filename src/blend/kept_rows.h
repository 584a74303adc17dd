// Layers' rows as the seam pass decoded them, kept for the sweep: each compressed layer is decoded once, not twice.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "gdp/blend.h"
#include "io/drop_behind.h"

namespace gdp::blending {

// The seam pass reads every layer whole, top to bottom; the sweep reads them again. Where a
// layer's samples are 8- or 16-bit (they came from such integers: checked per sample), the seam
// pass keeps its rows as those integers (channel-major, a quarter or half of the floats) in an
// unlinked scratch file, pushed to the disk and dropped from the page cache a window behind
// (io::DropBehind), and the sweep reads them back in chunks instead of decoding the file again.
// The floats read back are the decoded ones exactly. A layer is kept only if all the rows the
// sweep will ask for were written, and while the file holds at most 4 GiB (beyond, layers are
// decoded twice). Once a reader is done with a layer (the sweep closed it), its room in the file is
// given back to the disk and the layer is no longer kept: a sweep started again decodes it.
class KeptRows {
 public:
  KeptRows(const BlendPlan& plan, const std::filesystem::path& dir);
  ~KeptRows();
  KeptRows(const KeptRows&) = delete;
  KeptRows& operator=(const KeptRows&) = delete;

  // Layer k's rows [0, rows) in order, `channels` channel-major rows of `width` samples each.
  class Writer {
   public:
    Writer(KeptRows& kept, int k, int channels, int width, int rows, int bytes);
    ~Writer();  // the rows written so far: the layer is kept if they are all of them
    void write(std::span<const float> row);
   private:
    void flush();
    KeptRows& kept_;
    int k_, samples_, rows_, bytes_, done_ = 0, chunk_rows_;
    std::size_t at_;  // the next chunk's place in the file
    std::vector<unsigned char> chunk_;
    int in_chunk_ = 0;
    bool exact_ = true;
    io::DropBehind drop_;
  };
  class Reader {
   public:
    Reader(const KeptRows& kept, int k);
    ~Reader();
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;
    void read(std::span<float> row);  // the next row
   private:
    const KeptRows& kept_;
    int k_, samples_, rows_, bytes_, next_ = 0, chunk_rows_, chunk_first_ = 0;
    std::size_t base_;
    std::vector<unsigned char> chunk_;
    io::DropBehind drop_;
  };
  // A writer for layer k of `channels` x `width` samples a row (the file's sample type `type`), for
  // its rows [0, rows); null where its rows are not kept (not 8- or 16-bit).
  std::unique_ptr<Writer> writer(int k, SampleType type, int channels, int width, int rows);
  // Whether all of layer k's rows [0, rows) are kept.
  bool has(int k, int rows) const { return rows > 0 && layers_[k].rows.load(std::memory_order_acquire) >= rows; }
  // A reader of layer k's rows from the first, where has(k, rows).
  std::unique_ptr<Reader> reader(int k, int rows) const;
  // The file's size: the rows kept (given back to the disk as they are read).
  std::size_t bytes() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return end_;
  }

 private:
  struct Layer {
    int channels = 0, width = 0, bytes = 0;  // bytes a sample: 1 or 2
    std::size_t base = 0;
    mutable std::atomic<int> rows{0};  // rows kept (set once the writer is done; 0 again once read)
  };
  std::filesystem::path dir_;
  std::vector<Layer> layers_;
  std::mutex mutex_;  // the file's creation and size
  int fd_ = -1;
  std::size_t end_ = 0;
};

}  // namespace gdp::blending
