// Under mpirun: the ranks' columns of every result row put together on rank 0, which writes the file.
#include <cstring>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "bands/mpi_transport.h"
#include "schedule/bytes.h"
#include "gdp/image_stream.h"
#include "gdp/mpi_run.h"

namespace gdp {
namespace {

// The messages' tag on the gather's own hub (bands::MpiHub, a communicator of its own).
constexpr int kTag = 1;
// Rows per message: about 1 MiB of floats, and at most 16 rows. Rank 0 waits for a message only
// when it needs its first row, so a message must never hold rows that the sender can only solve
// once rank 0's workers, blocked behind rank 0's writing, have gone further.
constexpr std::size_t kBatchSamples = std::size_t{1} << 18;
constexpr int kBatchRows = 16;
constexpr std::size_t kInFlight = 4;  // sends not yet completed, per rank

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
    hub_ = std::make_unique<bands::MpiHub>(1, kInFlight);
  }

  void write_row(int y, std::span<const float> row) override {
    if (!hub_) {  // every rank has the whole row
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
    hub_.reset();  // waits for this rank's sends
  }

 private:
  struct Received {
    Header h;
    std::vector<unsigned char> bytes;  // the message: the samples, then the header
  };

  // The message is built in place, the header last: no copy but the row's columns.
  void send(int y, std::span<const float> row) {
    if (batch_.bytes.empty()) first_ = y;
    for (int c = 0; c < channels_; ++c) batch_.put(row.data() + static_cast<std::size_t>(c) * width_ + begin_, end_ - begin_);
    const std::size_t samples = batch_.bytes.size() / sizeof(float);
    if (samples < kBatchSamples && y + 1 - first_ < kBatchRows && y + 1 < height_) return;
    batch_.io(Header{first_, y + 1 - first_, begin_, end_});
    hub_->endpoint(rank_).send(0, kTag, std::move(batch_.bytes));
    batch_.bytes = {};
  }

  // Rank 0's output, opened at the first need.
  RowWriter& file() {
    if (!file_ && rank_ == 0) file_ = open_file_();
    return *file_;
  }

  // Rank r's columns of row y into row_, receiving its next message when needed.
  void fill(int r, int y) {
    Received& m = from_[r];
    if (m.h.rows == 0 || y >= m.h.first + m.h.rows) {
      m.bytes = hub_->endpoint(0).receive(r, kTag);
      if (m.bytes.size() < sizeof(Header)) throw std::logic_error("ColumnGather: short message");
      std::memcpy(&m.h, m.bytes.data() + m.bytes.size() - sizeof(Header), sizeof(Header));
      const std::size_t count = (m.bytes.size() - sizeof(Header)) / sizeof(float);
      if (m.h.first != y || m.h.begin < 0 || m.h.end > width_ || m.h.begin > m.h.end ||
          count != static_cast<std::size_t>(m.h.rows) * channels_ * (m.h.end - m.h.begin))
        throw std::logic_error(fmt::format("ColumnGather: rank {} sent rows {}.. columns {}..{}, row {} expected", r,
                                           m.h.first, m.h.begin, m.h.end, y));
    }
    const int n = m.h.end - m.h.begin;
    const std::size_t row_bytes = static_cast<std::size_t>(n) * sizeof(float);
    const unsigned char* src = m.bytes.data() + static_cast<std::size_t>(y - m.h.first) * channels_ * row_bytes;
    for (int c = 0; c < channels_; ++c)
      std::memcpy(row_.data() + static_cast<std::size_t>(c) * width_ + m.h.begin, src + c * row_bytes, row_bytes);
  }

  MpiRun::OpenFile open_file_;
  std::unique_ptr<RowWriter> file_;
  int width_, height_, channels_, rank_;
  int begin_ = 0, end_ = 0, first_ = 0;
  std::unique_ptr<bands::MpiHub> hub_;  // once the columns are set: the messages to rank 0
  schedule::ByteWriter batch_;          // the message being filled
  std::vector<float> row_;
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
