// Under mpirun: the ranks' columns of every result row put together on rank 0, which writes the file.
#include <mpi.h>

#include <cstring>
#include <deque>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "mpi/wait.h"
#include "gdp/image_stream.h"
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
    std::vector<unsigned char> bytes;  // the message: the header, then the samples
  };

  void send(int y, std::span<const float> row) {
    // The message is built in place (the header written last): no copy but the row's columns.
    const std::size_t row_bytes = static_cast<std::size_t>(end_ - begin_) * sizeof(float);
    if (batch_.empty()) {
      first_ = y;
      batch_.swap(spare_);  // the bytes of the last completed send: no allocation per message
      batch_.resize(sizeof(Header));
    }
    for (int c = 0; c < channels_; ++c) {
      const auto* p = reinterpret_cast<const unsigned char*>(row.data() + static_cast<std::size_t>(c) * width_ + begin_);
      batch_.insert(batch_.end(), p, p + row_bytes);
    }
    const std::size_t samples = (batch_.size() - sizeof(Header)) / sizeof(float);
    if (samples < kBatchSamples && y + 1 - first_ < kBatchRows && y + 1 < height_) return;
    const Header h{first_, y + 1 - first_, begin_, end_};
    std::memcpy(batch_.data(), &h, sizeof h);
    Sending s;
    s.bytes.swap(batch_);
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
    mpi::wait_request(sending_.front().request);
    spare_.swap(sending_.front().bytes);
    spare_.clear();
    sending_.pop_front();
  }

  // Rank r's columns of row y into row_, receiving its next message when needed.
  void fill(int r, int y) {
    Received& m = from_[r];
    if (m.h.rows == 0 || y >= m.h.first + m.h.rows) {
      mpi::receive_message(r, kTag, MPI_COMM_WORLD, m.bytes);  // into the last message's bytes
      const std::vector<unsigned char>& buffer = m.bytes;
      if (buffer.size() < sizeof(Header)) throw std::logic_error("ColumnGather: short message");
      std::memcpy(&m.h, buffer.data(), sizeof(Header));
      const std::size_t count = (buffer.size() - sizeof(Header)) / sizeof(float);
      if (m.h.first != y || m.h.begin < 0 || m.h.end > width_ || m.h.begin > m.h.end ||
          count != static_cast<std::size_t>(m.h.rows) * channels_ * (m.h.end - m.h.begin))
        throw std::logic_error(fmt::format("ColumnGather: rank {} sent rows {}.. columns {}..{}, row {} expected", r,
                                           m.h.first, m.h.begin, m.h.end, y));
    }
    const int n = m.h.end - m.h.begin;
    const std::size_t row_bytes = static_cast<std::size_t>(n) * sizeof(float);
    const unsigned char* src = m.bytes.data() + sizeof(Header) + static_cast<std::size_t>(y - m.h.first) * channels_ * row_bytes;
    for (int c = 0; c < channels_; ++c)
      std::memcpy(row_.data() + static_cast<std::size_t>(c) * width_ + m.h.begin, src + c * row_bytes, row_bytes);
  }

  MpiRun::OpenFile open_file_;
  std::unique_ptr<RowWriter> file_;
  int width_, height_, channels_, rank_;
  bool split_ = false;
  int begin_ = 0, end_ = 0, first_ = 0;
  std::vector<unsigned char> batch_, spare_;  // the message being filled, the bytes of a sent one
  std::vector<float> row_;
  std::deque<Sending> sending_;
  std::vector<Received> from_;
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
