// Guidance rows decoded on one thread and made by columns on several: the input pass by band.
#pragma once

#include <climits>
#include <condition_variable>
#include <mutex>
#include <vector>

#include "gdp/guidance.h"

namespace gdp::schedule {

// A source's decoded rows (GuidanceSource::splits), shared by one decoding thread and `readers`
// readers on threads of their own, each computing its columns of every row (read): row y is
// decoded into slot y % slots once every reader is done with row y - slots. A source that does not
// split is read whole by its one reader (read_row), and decode_all only waits for it.
class InputRing {
 public:
  InputRing(GuidanceSource& source, int readers, int slots = 16);  // slots > 8
  // The decoding thread: every row, in order; then waits until every reader is finished.
  void decode_all();
  // Reader r: row j (rows in order), as GuidanceSource::read_row, columns [begin, end) filled.
  void read(int reader, int j, GuidanceRow& out, int begin, int end);
  // Reader r has every row it needs.
  void finished(int reader);
  // Wakes every thread waiting here; they throw Stopped.
  void stop();

 private:
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
