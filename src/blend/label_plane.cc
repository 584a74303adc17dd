// The label plane: rows as runs of one label, appended to memory and past 8 MiB to an unlinked file; an index per row.
#include "blend/label_plane.h"

#include <unistd.h>

#include <algorithm>

#include "io/scratch_stream.h"

namespace gdp::blending {
namespace {

constexpr std::size_t kMemoryUnits = (std::size_t{8} << 20) / sizeof(Label);
constexpr std::uint32_t kLongestRun = 65536;  // a run's length - 1 is a Label

// Row as (label, length - 1) pairs, into `out`; false (out unspecified) once they are longer than the row.
bool runs_of(std::span<const Label> row, std::vector<Label>& out) {
  out.clear();
  const std::size_t w = row.size();
  for (std::size_t x = 0; x < w;) {
    const Label l = row[x];
    std::size_t run = x + 1;
    while (run < w && row[run] == l && run - x < kLongestRun) ++run;
    if (out.size() + 2 > w) return false;
    out.push_back(l);
    out.push_back(static_cast<Label>(run - x - 1));
    x = run;
  }
  return true;
}

}  // namespace

LabelPlane::LabelPlane(const std::filesystem::path& dir, int width, int height)
    : width_(width), height_(height), dir_(dir.empty() ? std::filesystem::temp_directory_path() : dir),
      index_(dir, static_cast<std::size_t>(height) * sizeof(Kept), "label index") {}

LabelPlane::~LabelPlane() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t LabelPlane::bytes() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return index_.bytes() + end_ * sizeof(Label);
}

void LabelPlane::write_row(int y, std::span<const Label> row) {
  thread_local std::vector<Label> runs;
  row = row.first(width_);
  const bool as_runs = runs_of(row, runs);
  const std::span<const Label> units = as_runs ? std::span<const Label>(runs) : row;
  Kept k;
  k.units = static_cast<std::uint32_t>(units.size());
  k.runs = as_runs ? 1 : 0;
  int fd = -1;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    k.at = end_;
    end_ += units.size();
    if (fd_ < 0 && end_ > kMemoryUnits) {  // too many for memory: to a file from here on
      fd_ = io::open_unlinked(dir_, "labels");
      write_at(fd_, memory_.data(), memory_.size() * sizeof(Label), 0, dir_);
      std::vector<Label>().swap(memory_);
    }
    if (fd_ < 0) memory_.insert(memory_.end(), units.begin(), units.end());
    fd = fd_;
  }
  if (fd >= 0)  // room taken above
    write_at(fd, units.data(), units.size() * sizeof(Label), k.at * sizeof(Label), dir_);
  index_.write(static_cast<std::size_t>(y) * sizeof(Kept), &k, sizeof(Kept));
}

// Row k's units into `out`.
void LabelPlane::units(const Kept& k, std::vector<Label>& out) const {
  out.resize(k.units);
  int fd = -1;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (fd_ < 0) {
      std::copy_n(memory_.begin() + static_cast<std::ptrdiff_t>(k.at), k.units, out.begin());
      return;
    }
    fd = fd_;
  }
  read_at(fd, out.data(), out.size() * sizeof(Label), k.at * sizeof(Label), dir_);
}

void LabelPlane::read_row(int y, std::span<Label> row, int begin, int end) const {
  fill();
  if (end < 0) end = width_;
  Kept k;
  index_.read(static_cast<std::size_t>(y) * sizeof(Kept), &k, sizeof(Kept));
  if (k.units == 0) {
    std::fill(row.begin() + begin, row.begin() + end, Label{0});
    return;
  }
  thread_local std::vector<Label> kept;
  units(k, kept);
  if (!k.runs) {
    std::copy(kept.begin() + begin, kept.begin() + end, row.begin() + begin);
    return;
  }
  for (std::size_t r = 0, x = 0; r < kept.size() && static_cast<int>(x) < end; r += 2) {
    const std::size_t next = x + kept[r + 1] + 1;
    const std::size_t a = std::max<std::size_t>(x, begin), b = std::min<std::size_t>(next, end);
    if (a < b) std::fill(row.begin() + static_cast<std::ptrdiff_t>(a), row.begin() + static_cast<std::ptrdiff_t>(b), kept[r]);
    x = next;
  }
}

void LabelPlane::want_columns(int begin, int end) const {
  if (end < 0) end = width_;
  if (want_end_ == 0) {
    want_begin_ = begin;
    want_end_ = end;
  }
  want_begin_ = std::min(want_begin_, begin);
  want_end_ = std::max(want_end_, end);
}

void LabelPlane::fill() const {
  if (filled_.load(std::memory_order_acquire)) return;
  const std::lock_guard<std::mutex> lock(fill_mutex_);
  if (filled_.load(std::memory_order_relaxed) || !fill_) return;
  const Fill f = std::move(fill_);
  fill_ = nullptr;
  f(const_cast<LabelPlane&>(*this), want_end_ > 0 ? want_begin_ : 0, want_end_ > 0 ? want_end_ : width_);
  filled_.store(true, std::memory_order_release);
}

}  // namespace gdp::blending
