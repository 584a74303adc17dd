// Kept rows: the seam pass's decoded 8/16-bit rows to an unlinked file with drop-behind, read back in chunks by the sweep.
#include "blend/kept_rows.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <system_error>

#include "blend/scratch.h"
#include "gdp/errors.h"
#include "io/codec_util.h"
#include "io/scratch_stream.h"
#include "util/exact_io.h"

namespace gdp::blending {
namespace {

constexpr std::size_t kChunkBytes = std::size_t{1} << 20;  // written and read a chunk of rows at a time
constexpr std::size_t kWindow = std::size_t{8} << 20;      // drop-behind's window per layer
constexpr std::size_t kMostBytes = std::size_t{4} << 30;   // the file's size at most

int chunk_rows(std::size_t row_bytes) { return static_cast<int>(std::max<std::size_t>(1, kChunkBytes / row_bytes)); }

// The integers the samples came from (false where one did not: not kept). Bits compared, not
// floats: a floating-point test would keep the loop from vectorising.
template <class T, class To, class From>
bool quantise(std::span<const float> row, T* out, To to, From from) {
  std::uint32_t differ = 0;
  const float* in = row.data();
  for (std::size_t i = 0, n = row.size(); i < n; ++i) {
    const T q = to(in[i]);
    out[i] = q;
    differ |= std::bit_cast<std::uint32_t>(from(q)) ^ std::bit_cast<std::uint32_t>(in[i]);
  }
  return differ == 0;
}

}  // namespace

KeptRows::KeptRows(const BlendPlan& plan, const std::filesystem::path& dir)
    : dir_(dir.empty() ? std::filesystem::temp_directory_path() : dir), layers_(plan.layers.size()) {}

KeptRows::~KeptRows() {
  if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<KeptRows::Writer> KeptRows::writer(int k, SampleType type, int channels, int width, int rows) {
  const int bytes = type == SampleType::UInt8 ? 1 : type == SampleType::UInt16 ? 2 : 0;
  if (bytes == 0 || rows <= 0 || layers_[k].rows.load() > 0) return nullptr;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (end_ + static_cast<std::size_t>(channels) * width * bytes * rows > kMostBytes) return nullptr;
  }
  return std::make_unique<Writer>(*this, k, channels, width, rows, bytes);
}

std::unique_ptr<KeptRows::Reader> KeptRows::reader(int k, int rows) const {
  if (!has(k, rows)) return nullptr;
  return std::make_unique<Reader>(*this, k);
}

KeptRows::Writer::Writer(KeptRows& kept, int k, int channels, int width, int rows, int bytes)
    : kept_(kept), k_(k), samples_(channels * width), rows_(rows), bytes_(bytes),
      chunk_rows_(chunk_rows(static_cast<std::size_t>(channels) * width * bytes)), drop_(kWindow) {
  const std::size_t row_bytes = static_cast<std::size_t>(samples_) * bytes_;
  {
    const std::lock_guard<std::mutex> lock(kept.mutex_);
    if (kept.fd_ < 0) kept.fd_ = io::open_unlinked(kept.dir_, "decoded layers");
    at_ = kept.end_;
    kept.end_ += row_bytes * static_cast<std::size_t>(rows);
  }
  Layer& l = kept.layers_[k];
  l.channels = channels;
  l.width = width;
  l.bytes = bytes;
  l.base = at_;
  drop_.restart(at_);
  chunk_.resize(row_bytes * static_cast<std::size_t>(chunk_rows_));
}

KeptRows::Writer::~Writer() {
  try {
    if (exact_ && done_ == rows_) flush();
    if (exact_ && done_ == rows_) kept_.layers_[k_].rows.store(rows_, std::memory_order_release);
  } catch (const std::exception&) {  // not kept: the sweep decodes the layer's file again
  }
}

void KeptRows::Writer::write(std::span<const float> row) {
  if (!exact_ || done_ >= rows_) return;
  unsigned char* to = chunk_.data() + static_cast<std::size_t>(in_chunk_) * samples_ * bytes_;
  const std::span<const float> s = row.first(samples_);
  exact_ = bytes_ == 1 ? quantise(s, to, [](float v) { return io::to_u8(v); }, [](std::uint8_t v) { return io::from_u8(v); })
                       : quantise(s, reinterpret_cast<std::uint16_t*>(to), [](float v) { return io::to_u16(v); },
                                  [](std::uint16_t v) { return io::from_u16(v); });
  ++done_;
  if (++in_chunk_ == chunk_rows_) flush();
}

void KeptRows::Writer::flush() {
  const std::size_t n = static_cast<std::size_t>(in_chunk_) * samples_ * bytes_;
  write_at(kept_.fd_, chunk_.data(), n, at_, kept_.dir_);
  at_ += n;
  in_chunk_ = 0;
  if (!drop_.wrote(kept_.fd_, at_)) throw OutputError("scratch file: cannot write: " + util::errno_message());
}

KeptRows::Reader::Reader(const KeptRows& kept, int k)
    : kept_(kept), k_(k), samples_(kept.layers_[k].channels * kept.layers_[k].width), rows_(kept.layers_[k].rows.load()),
      bytes_(kept.layers_[k].bytes), chunk_rows_(chunk_rows(static_cast<std::size_t>(samples_) * bytes_)),
      base_(kept.layers_[k].base), drop_(kWindow) {
  drop_.restart(base_);
}

KeptRows::Reader::~Reader() {
  const std::size_t bytes = static_cast<std::size_t>(samples_) * bytes_ * rows_;
  kept_.layers_[k_].rows.store(0);  // read once: a sweep started again decodes the layer
  util::punch_hole(kept_.fd_, base_, base_ + bytes);
}

void KeptRows::Reader::read(std::span<float> row) {
  const std::size_t row_bytes = static_cast<std::size_t>(samples_) * bytes_;
  if (next_ >= rows_) throw std::logic_error("KeptRows::Reader: past the last row");
  if (next_ == 0 || next_ - chunk_first_ >= chunk_rows_) {  // the next chunk, and the one after it asked for
    chunk_first_ = next_;
    const int n_rows = std::min(chunk_rows_, rows_ - next_);
    chunk_.resize(row_bytes * n_rows);
    const std::size_t at = base_ + row_bytes * next_;
    read_at(kept_.fd_, chunk_.data(), chunk_.size(), at, kept_.dir_);
    drop_.read(kept_.fd_, at + chunk_.size());
    const std::size_t ahead = base_ + row_bytes * std::min(rows_, next_ + n_rows);
    ::posix_fadvise(kept_.fd_, static_cast<off_t>(ahead), static_cast<off_t>(row_bytes * chunk_rows_), POSIX_FADV_WILLNEED);
  }
  const unsigned char* from = chunk_.data() + static_cast<std::size_t>(next_ - chunk_first_) * row_bytes;
  if (bytes_ == 1) {
    for (int i = 0; i < samples_; ++i) row[i] = io::from_u8(from[i]);
  } else {
    const auto* u = reinterpret_cast<const std::uint16_t*>(from);
    for (int i = 0; i < samples_; ++i) row[i] = io::from_u16(u[i]);
  }
  ++next_;
}

}  // namespace gdp::blending
