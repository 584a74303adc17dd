// Under mpirun: the ranks' columns of every result row put together on rank 0, which writes the file.
#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "bands/mpi_transport.h"
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
    std::vector<unsigned char> bytes;  // the message: the header, then the samples
  };

  void send(int y, std::span<const float> row) {
    // The message is built in place (the header written last): no copy but the row's columns.
    const std::size_t row_bytes = static_cast<std::size_t>(end_ - begin_) * sizeof(float);
    if (batch_.empty()) {
      first_ = y;
      batch_ = hub_->spare();  // a completed message's buffer
      batch_.reserve(sizeof(Header) + std::min(kBatchSamples * sizeof(float) + channels_ * row_bytes,
                                               kBatchRows * channels_ * row_bytes));
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
    hub_->endpoint(rank_).send(0, kTag, std::move(batch_));
    batch_ = {};
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
      hub_->recycle(std::move(m.bytes));  // the next message lands in this one's buffer
      m.bytes = hub_->endpoint(0).receive(r, kTag);
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
  int begin_ = 0, end_ = 0, first_ = 0;
  std::unique_ptr<bands::MpiHub> hub_;  // once the columns are set: the messages to rank 0
  std::vector<unsigned char> batch_;    // the message being filled
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
