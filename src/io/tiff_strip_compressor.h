// Deflate-compressed TIFF strips or tiles made on worker threads (predictor + libdeflate), handed back in order.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "util/bells.h"
#include "util/recycle_pool.h"

namespace gdp::io {

// How a strip's (or tile's) rows are laid out and predicted.
struct StripFormat {
  int width = 0, channels = 0;  // of a row: the image's width for strips, the tile width for tiles
  std::size_t sample_bytes = 1;  // 1, 2 (unsigned: horizontal predictor) or 4, 8 (float: floating-point predictor)
  bool floating = false;
  int level = 6;  // deflate level, 1..12
};

// libtiff deflates a strip on the thread that writes it; this compresses several at once. The
// strips (uncompressed rows, as they go into TIFFWriteEncodedStrip; or tiles, as into
// TIFFWriteEncodedTile) are submitted in order (0, 1, 2, ...) from one thread; `sink` receives
// each compressed one, in that order, on that same thread (it calls TIFFWriteRawStrip or
// TIFFWriteRawTile). At most threads + 2 are held at a time. Buffers keep their size between
// uses (no clearing, so no zero-filling when they are sized again): a strip is `size` bytes of its
// buffer, a compressed one the span the sink is given.
class StripCompressor {
 public:
  using Sink = std::function<void(int strip, std::span<const unsigned char> zlib_stream)>;
  StripCompressor(const StripFormat& format, int threads);
  ~StripCompressor();
  StripCompressor(const StripCompressor&) = delete;
  StripCompressor& operator=(const StripCompressor&) = delete;

  // Strips 0, 1, 2, ...: bytes [0, size) of `rows`.
  void submit(int strip, std::vector<unsigned char> rows, std::size_t size, const Sink& sink);
  // The buffer of an earlier strip (as large as it was; empty at first) to fill and submit.
  std::vector<unsigned char> buffer() { return spent_.take(); }
  void finish(const Sink& sink);  // waits for every strip and sinks it; throws CodecError on a failure

 private:
  struct Job {
    int strip;
    std::vector<unsigned char> rows;
    std::size_t size;  // bytes of rows
  };
  struct Zipped {
    std::vector<unsigned char> bytes;  // room for the bound; the stream is its first `size`
    std::size_t size = 0;
  };
  void work();
  void sink_ready(std::unique_lock<std::mutex>& lock, const Sink& sink);  // in-order finished strips
  void wait_for_next(std::unique_lock<std::mutex>& lock);  // until strip next_ is done, or one failed

  StripFormat format_;
  // Workers wait in `idle_` for a job, each woken by the submit that brings one; the submitting
  // thread in `submitter_` for the next strip to sink, woken only by the worker that finishes it
  // (or fails). Rung after unlocking (util/bells.h).
  std::mutex mutex_;
  util::Bells bells_;
  util::Bells::Line idle_, submitter_;
  std::deque<Job> jobs_;
  std::map<int, Zipped> done_;
  util::RecyclePool<std::vector<unsigned char>> spent_;   // strips' buffers, allocated once
  util::RecyclePool<std::vector<unsigned char>> zipped_;  // compressed strips' buffers, the same
  int next_ = 0;         // next strip to sink
  int outstanding_ = 0;  // submitted, not yet sunk
  int limit_ = 4;
  bool stopping_ = false;
  std::string error_;
  std::vector<std::thread> workers_;
};

}  // namespace gdp::io
