// Under mpirun: the ranks' columns of every result row put together on rank 0, which writes the file.
#include <algorithm>
#include <cstring>
#include <deque>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "bands/mpi_transport.h"
#include "schedule/bytes.h"
#include "gdp/image_stream.h"
#include "gdp/mpi_run.h"
#include "mpi/stored_samples.h"
#include "util/recycle_pool.h"

namespace gdp {
namespace {

// The messages' tags on the gather's own hub (bands::MpiHub, a communicator of its own): rows, and
// rank 0's file's stored_levels() (RowWriter) to the others, which then send 8- or 16-bit samples
// (a quarter or half of a float's bytes) that rank 0 turns into floats the file stores alike.
constexpr int kTag = 1, kLevelsTag = 2;
// Rows per message: about 1 MiB of floats, and at most 16 rows. No rank's writing ever waits for
// another rank (docs/how-bands-work.md, "Why a streamed solve cannot hang"): the other ranks send
// without waiting for rank 0 to receive, and rank 0 takes the messages that have arrived, keeps
// its own rows until the others' columns of them are in, and waits for the rest only in commit().
constexpr std::size_t kBatchSamples = std::size_t{1} << 18;
constexpr int kBatchRows = 16;

// A message: rows [first, first + rows) of columns [begin, end), channel-major per row, then this.
struct Header {
  int first = 0, rows = 0, begin = 0, end = 0;
};

class ColumnGather final : public RowWriter {
 public:
  ColumnGather(MpiRun::OpenFile open_file, int width, int height, int channels)
      : open_file_(std::move(open_file)), width_(width), height_(height), channels_(channels), rank_(MpiRun::rank()),
        from_(static_cast<std::size_t>(MpiRun::size())) {
    if (rank_ == 0 && !open_file_) throw std::logic_error("ColumnGather: rank 0 needs the output");
  }

  // Every rank agreed to solve and comes here: rank 0 opens the output now, every rank the hub.
  void set_columns(int begin, int end) override {
    file();
    begin_ = begin;
    end_ = end;
    hub_ = std::make_unique<bands::MpiHub>(1);
    schedule::ByteWriter mine;
    if (rank_ == 0) levels_ = file().stored_levels();
    mine.io(levels_);
    schedule::ByteReader(bands::broadcast(hub_->own(), kLevelsTag, std::move(mine.bytes))).io(levels_);
    sample_ = mpi::sent_bytes(levels_);
  }

  void write_row(int y, std::span<const float> row) override {
    if (!hub_) {  // every rank has the whole row
      if (rank_ == 0) file().write_row(y, row);
      return;
    }
    if (rank_ != 0) return send(y, row);
    std::vector<float>& mine = rows_.emplace_back(spare_rows_.take());  // only this rank's columns
    mine.resize(row.size());
    for (int c = 0; c < channels_; ++c) {
      const std::size_t at = static_cast<std::size_t>(c) * width_ + begin_;
      std::copy_n(row.begin() + at, end_ - begin_, mine.begin() + at);
    }
    for (int r = 1; r < static_cast<int>(from_.size()); ++r)
      while (auto m = hub_->poll(r, 0, kTag)) take(r, std::move(*m));
    write_complete(false);
  }

  void commit() override {
    if (rank_ != 0) return hub_.reset();  // waits for this rank's sends
    if (hub_) write_complete(true);
    file().commit();
  }

 private:
  struct Received {
    Header h;
    std::vector<unsigned char> bytes;  // the message: the samples, then the header
  };

  // The message is built in place, the header last: no copy but the row's columns, and no byte
  // written twice (a sent batch's buffer keeps its size: nothing is cleared or zero-filled).
  void send(int y, std::span<const float> row) {
    const std::size_t n = static_cast<std::size_t>(end_ - begin_);
    if (batch_rows_ == 0) {
      first_ = y;
      batch_ = hub_->spare();
      const std::size_t samples = std::max<std::size_t>(1, channels_ * n);
      batch_capacity_ = static_cast<int>(std::min<std::size_t>(kBatchRows, (kBatchSamples + samples - 1) / samples));
      const std::size_t bytes = batch_capacity_ * samples * sample_ + sizeof(Header);
      if (batch_.size() < bytes) batch_.resize(bytes);
    }
    unsigned char* at = batch_.data() + static_cast<std::size_t>(batch_rows_) * channels_ * n * sample_;
    for (int c = 0; c < channels_; ++c, at += n * sample_)
      mpi::pack(row.data() + static_cast<std::size_t>(c) * width_ + begin_, n, levels_, at);
    if (++batch_rows_ < batch_capacity_ && y + 1 < height_) return;
    const Header h{first_, batch_rows_, begin_, end_};
    const std::size_t size = static_cast<std::size_t>(batch_rows_) * channels_ * n * sample_;
    std::memcpy(batch_.data() + size, &h, sizeof(Header));
    batch_.resize(size + sizeof(Header));  // shrinking keeps the buffer (and writes nothing)
    hub_->endpoint(rank_).send(0, kTag, std::move(batch_));
    batch_ = {};
    batch_rows_ = 0;
  }

  // Rank 0's output, opened at the first need.
  RowWriter& file() {
    if (!file_ && rank_ == 0) file_ = open_file_();
    return *file_;
  }

  // Rank r's next message (rows in order).
  void take(int r, std::vector<unsigned char> bytes) {
    std::deque<Received>& q = from_[r];
    const int next = q.empty() ? written_ : q.back().h.first + q.back().h.rows;
    Received& m = q.emplace_back(Received{{}, std::move(bytes)});
    if (m.bytes.size() < sizeof(Header)) throw std::logic_error("ColumnGather: short message");
    std::memcpy(&m.h, m.bytes.data() + m.bytes.size() - sizeof(Header), sizeof(Header));
    const std::size_t count = (m.bytes.size() - sizeof(Header)) / sample_;
    if (m.h.first != next || m.h.rows < 1 || m.h.begin < 0 || m.h.end > width_ || m.h.begin > m.h.end ||
        count != static_cast<std::size_t>(m.h.rows) * channels_ * (m.h.end - m.h.begin))
      throw std::logic_error(fmt::format("ColumnGather: rank {} sent rows {}.. columns {}..{}, row {} expected", r,
                                         m.h.first, m.h.begin, m.h.end, next));
  }

  // Writes rank 0's rows, in order, while every rank's columns of the next one are in; `wait`: all
  // of them, receiving what has not arrived.
  void write_complete(bool wait) {
    for (; !rows_.empty(); rows_.pop_front(), ++written_) {
      for (int r = 1; r < static_cast<int>(from_.size()); ++r) {
        std::deque<Received>& q = from_[r];
        if (!q.empty() && written_ >= q.front().h.first + q.front().h.rows) {
          hub_->recycle(std::move(q.front().bytes));
          q.pop_front();
        }
        if (q.empty() && !wait) return;
        if (q.empty()) take(r, hub_->endpoint(0).receive(r, kTag));
        const Received& m = q.front();
        const std::size_t n = static_cast<std::size_t>(m.h.end - m.h.begin);
        const unsigned char* src = m.bytes.data() + static_cast<std::size_t>(written_ - m.h.first) * channels_ * n * sample_;
        for (int c = 0; c < channels_; ++c)
          mpi::unpack(src + c * n * sample_, n, levels_, rows_.front().data() + static_cast<std::size_t>(c) * width_ + m.h.begin);
      }
      file().write_row(written_, rows_.front());
      spare_rows_.give(std::move(rows_.front()));
    }
  }

  MpiRun::OpenFile open_file_;
  std::unique_ptr<RowWriter> file_;
  int width_, height_, channels_, rank_;
  int begin_ = 0, end_ = 0, first_ = 0;
  int levels_ = 0;                    // rank 0's file's RowWriter::stored_levels()
  std::size_t sample_ = sizeof(float);  // bytes a sample takes in a message
  std::unique_ptr<bands::MpiHub> hub_;  // once the columns are set: the messages to rank 0
  schedule::Bytes batch_;                // the message being filled: batch_rows_ of batch_capacity_ rows
  int batch_rows_ = 0, batch_capacity_ = 0;
  std::deque<std::vector<float>> rows_;  // rank 0: its rows from `written_` on, not yet written
  util::RecyclePool<std::vector<float>> spare_rows_;  // rank 0: written rows' buffers, reused
  int written_ = 0;
  std::vector<std::deque<Received>> from_;  // rank 0: each rank's messages not yet used up
};

}  // namespace

std::unique_ptr<RowWriter> MpiRun::gather_writer(OpenFile open_file, int width, int height, int channels) {
  if (size() <= 1) return open_file();
  return std::make_unique<ColumnGather>(rank() == 0 ? std::move(open_file) : OpenFile{}, width, height, channels);
}

std::unique_ptr<RowWriter> MpiRun::gather_file(const std::filesystem::path& path, int width, int height, int channels,
                                               const WriteOptions& options) {
  return gather_writer([=] { return std::make_unique<ImageFileWriter>(path, width, height, channels, options); },
                       width, height, channels);
}

}  // namespace gdp
