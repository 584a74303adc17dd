// Under mpirun: the ranks' columns of every result row put together on rank 0, which writes the file.
#include <mpi.h>

#include <cstring>
#include <deque>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "bands/mpi_wait.h"
#include "gdp/mpi_run.h"

namespace gdp {
namespace {

// Messages go through MPI_COMM_WORLD with their own tag (the band transport has a communicator
// of its own, the collective check uses no tags).
constexpr int kTag = 7001;
// Rows per message: about 1 MiB of floats, and at most 16 rows. Rank 0 waits for a message only
// when it needs its first row, so a message must never hold rows that the sender can only solve
// once rank 0's workers, blocked behind rank 0's writing, have gone further.
constexpr std::size_t kBatchSamples = std::size_t{1} << 18;
constexpr int kBatchRows = 16;
constexpr std::size_t kInFlight = 4;                         // sends not yet completed, per rank

// A message: rows [first, first + rows) of columns [begin, end), channel-major per row.
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
  ~ColumnGather() override {
    for (auto& s : sending_) MPI_Request_free(&s.request);  // a failed run: MPI_Abort ends it anyway
  }

  void set_columns(int begin, int end) override {
    file();  // every rank agreed to solve: rank 0 opens the output now
    begin_ = begin;
    end_ = end;
    split_ = true;
  }

  void write_row(int y, std::span<const float> row) override {
    if (!split_) {  // every rank has the whole row
      if (rank_ == 0) file().write_row(y, row);
      return;
    }
    if (rank_ != 0) return send(y, row);
    row_.assign(row.begin(), row.end());
    for (int r = 1; r < static_cast<int>(from_.size()); ++r) fill(r, y);
    file().write_row(y, row_);
  }

  void commit() override {
    if (rank_ == 0) return file().commit();
    while (!sending_.empty()) wait_oldest();
  }

 private:
  struct Sending {
    std::vector<unsigned char> bytes;
    MPI_Request request = MPI_REQUEST_NULL;
  };
  struct Received {
    Header h;
    std::vector<float> samples;
  };

  void send(int y, std::span<const float> row) {
    const int n = end_ - begin_;
    if (batch_.empty()) first_ = y;
    for (int c = 0; c < channels_; ++c) {
      const float* p = row.data() + static_cast<std::size_t>(c) * width_ + begin_;
      batch_.insert(batch_.end(), p, p + n);
    }
    if (batch_.size() < kBatchSamples && y + 1 - first_ < kBatchRows && y + 1 < height_) return;
    const Header h{first_, y + 1 - first_, begin_, end_};
    Sending s;
    s.bytes.resize(sizeof h + batch_.size() * sizeof(float));
    std::memcpy(s.bytes.data(), &h, sizeof h);
    std::memcpy(s.bytes.data() + sizeof h, batch_.data(), batch_.size() * sizeof(float));
    batch_.clear();
    sending_.push_back(std::move(s));
    MPI_Isend(sending_.back().bytes.data(), static_cast<int>(sending_.back().bytes.size()), MPI_BYTE, 0, kTag,
              MPI_COMM_WORLD, &sending_.back().request);
    if (sending_.size() > kInFlight) wait_oldest();
  }

  // Rank 0's output, opened at the first need.
  RowWriter& file() {
    if (!file_ && rank_ == 0) file_ = open_file_();
    return *file_;
  }

  void wait_oldest() {
    MPI_Request& request = sending_.front().request;
    bands::wait_until([&] {
      int done = 0;
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      return done != 0;
    });
    sending_.pop_front();
  }

  // Rank r's columns of row y into row_, receiving its next message when needed.
  void fill(int r, int y) {
    Received& m = from_[r];
    if (m.h.rows == 0 || y >= m.h.first + m.h.rows) {
      MPI_Message message;
      MPI_Status status;
      bands::wait_until([&] {
        int found = 0;
        MPI_Improbe(r, kTag, MPI_COMM_WORLD, &found, &message, &status);
        return found != 0;
      });
      int bytes = 0;
      MPI_Get_count(&status, MPI_BYTE, &bytes);
      std::vector<unsigned char> buffer(static_cast<std::size_t>(bytes));
      MPI_Mrecv(buffer.data(), bytes, MPI_BYTE, &message, MPI_STATUS_IGNORE);
      if (buffer.size() < sizeof(Header)) throw std::logic_error("ColumnGather: short message");
      std::memcpy(&m.h, buffer.data(), sizeof(Header));
      const std::size_t count = (buffer.size() - sizeof(Header)) / sizeof(float);
      if (m.h.first != y || m.h.begin < 0 || m.h.end > width_ || m.h.begin > m.h.end ||
          count != static_cast<std::size_t>(m.h.rows) * channels_ * (m.h.end - m.h.begin))
        throw std::logic_error(fmt::format("ColumnGather: rank {} sent rows {}.. columns {}..{}, row {} expected", r,
                                           m.h.first, m.h.begin, m.h.end, y));
      m.samples.resize(count);
      std::memcpy(m.samples.data(), buffer.data() + sizeof(Header), count * sizeof(float));
    }
    const int n = m.h.end - m.h.begin;
    const float* src = m.samples.data() + static_cast<std::size_t>(y - m.h.first) * channels_ * n;
    for (int c = 0; c < channels_; ++c)
      std::memcpy(row_.data() + static_cast<std::size_t>(c) * width_ + m.h.begin, src + static_cast<std::size_t>(c) * n,
                  n * sizeof(float));
  }

  MpiRun::OpenFile open_file_;
  std::unique_ptr<RowWriter> file_;
  int width_, height_, channels_, rank_;
  bool split_ = false;
  int begin_ = 0, end_ = 0, first_ = 0;
  std::vector<float> batch_, row_;
  std::deque<Sending> sending_;
  std::vector<Received> from_;
};

}  // namespace

std::unique_ptr<RowWriter> MpiRun::gather_writer(OpenFile open_file, int width, int height, int channels) {
  if (size() <= 1) return open_file();
  return std::make_unique<ColumnGather>(rank() == 0 ? std::move(open_file) : OpenFile{}, width, height, channels);
}

}  // namespace gdp
