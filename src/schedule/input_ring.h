// Guidance rows decoded on one thread and made by columns on several: the input pass by band.
#pragma once

#include <climits>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "gdp/guidance.h"

namespace gdp::schedule {

// A source's decoded rows (GuidanceSource::splits), shared by one decoding thread and `readers`
// threads, each computing its own columns of every row through its view(): row y is decoded into
// slot y % slots once every reader is done with row y - slots. A source that does not split is
// read whole by its one reader (read_row), and decode_all does nothing.
class InputRing {
 public:
  using Range = std::pair<int, int>;  // columns [first, second)

  InputRing(GuidanceSource& source, int readers, int slots = 16);  // slots > 8
  // The decoding thread: every row, in order; then waits until every reader is finished.
  void decode_all();
  // Reader r's source: the rows it asks for in order, with the columns in `windows` (of a source
  // that splits) filled.
  std::unique_ptr<GuidanceSource> view(int reader, std::vector<Range> windows);
  // Reader r has every row it needs.
  void finished(int reader);
  // Wakes every thread waiting here; they throw Stopped.
  void stop();

 private:
  class View;
  void wait_decoded(int y);  // until row y is decoded
  void release(int reader, int rows);  // the reader is done with rows < `rows`

  GuidanceSource& source_;
  const bool split_;
  const int slots_, height_;
  static constexpr int kBatch = 4;  // slots_ > 2 * kBatch
  std::mutex mutex_;
  std::condition_variable readers_, decoder_;
  int decoded_ = 0;                                 // rows decoded
  std::vector<int> released_;                       // per reader: rows it is done with
  int reader_wants_ = INT_MAX, decoder_wants_ = INT_MAX;  // what a waiting thread waits to exceed
  bool stopped_ = false;
};

}  // namespace gdp::schedule
