// Row stores: where each goes (memfd, O_DIRECT or page-cache file), and half-float encoding of its rows.
#include "schedule/row_store.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "util/exact_io.h"

namespace gdp::schedule {

// Where a store of `total` bytes goes (docs/how-streaming-works.md, "Scratch in O_DIRECT files"): a
// checkpoint's named file, O_DIRECT however small (the resume tests cover it); else an O_DIRECT file
// from the budget's direct_from() on, where the directory takes one; else memory while the budget
// has room; else a file, O_DIRECT from 1 MiB on where it can be.
template <class T>
RowStore<T>::RowStore(const StorePolicy& policy, std::size_t row_length, std::size_t rows, std::string name)
    : row_length_(row_length), half_(policy.half.rounds(name)), kept_(!policy.keep_dir.empty()),
      budget_(policy.budget ? policy.budget : &ScratchBudget::process()) {
  name = policy.name_prefix + name;
  const std::size_t total = encoded_bytes() * rows;
  const bool direct = budget_->direct_files();
  const std::filesystem::path dir = kept_ ? policy.keep_dir : policy.dir.empty() ? std::filesystem::temp_directory_path() : policy.dir;
  int fd = -1;
  if (kept_) {
    const std::filesystem::path path = dir / (name + ".store");
    fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw OutputError(fmt::format("checkpoint {}: cannot open: {}", path.string(), util::errno_message()));
  } else if (direct && total >= budget_->direct_from()) {
    fd = io::open_unlinked(dir, name);
  }
  io::StreamKind kind = io::StreamKind::File;
  if (fd >= 0 && direct && io::make_direct(fd)) kind = io::StreamKind::Direct;
  else if (fd >= 0 && !kept_) fd = (::close(fd), -1);  // the directory takes no O_DIRECT: memory if the budget has room
  if (fd < 0 && budget_->reserve(total)) {
    // In memory: the same writes and reads as a file, into pages the kernel need not zero (a
    // fresh anonymous page must be; docs/how-streaming-works.md, "Scratch in a memfd").
    fd = ::memfd_create(("gdp-scratch-" + name).c_str(), MFD_CLOEXEC);
    if (fd < 0) {
      budget_->release(total);
      throw OutputError(fmt::format("scratch memory ({}): cannot create: {}", name, util::errno_message()));
    }
    memory_ = total;
    kind = io::StreamKind::Memory;
  } else if (fd < 0) {
    budget_->count_spill();
    constexpr std::size_t kDirectMin = std::size_t{1} << 20;  // a smaller file's blocks are not worth a thread
    fd = io::open_unlinked(dir, name);
    if (direct && total >= kDirectMin && io::make_direct(fd)) kind = io::StreamKind::Direct;
  }
  const bool memory = kind == io::StreamKind::Memory;
  // "scratch file in DIR (NAME)": messages name the directory (the disk that filled up).
  std::string where = memory ? fmt::format("scratch memory ({})", name) : fmt::format("scratch file in {} ({})", dir.string(), name);
  const char* hint = memory ? " (--memory SIZE keeps less in memory; a file size limit, ulimit -f, bounds it too)"
                            : " (--temp DIR puts scratch files elsewhere)";
  stream_ = std::make_unique<io::ScratchStream>(fd, kind, encoded_bytes(), total, policy.drop_behind, std::move(where), hint);
}

// The file holds bytes() (what the budget's on-disk count says).
template <class T>
void RowStore<T>::count_disk() {
  if (bytes() <= disk_bytes_ || !on_disk()) return;
  budget_->add_disk(static_cast<std::ptrdiff_t>(bytes() - disk_bytes_));
  disk_bytes_ = bytes();
}

template <class T>
RowStore<T>::~RowStore() {
  stream_.reset();
  budget_->add_disk(-static_cast<std::ptrdiff_t>(disk_bytes_));
  budget_->release(memory_);
}

template <class T>
std::size_t RowStore<T>::encoded_bytes() const {
  return row_length_ * (half_ ? sizeof(_Float16) : sizeof(T));
}

template <class T>
void RowStore<T>::append(std::span<const T> row) {
  unsigned char* out = stream_->append();
  if (half_) multigrid::to_half(row.data(), reinterpret_cast<_Float16*>(out), row_length_);
  else std::memcpy(out, row.data(), encoded_bytes());
}

template <class T>
void RowStore<T>::rewind(bool last) {
  stream_->rewind(last && !kept_);  // a checkpoint's file keeps its rows: a resume reads them again
  count_disk();
}

template <class T>
void RowStore<T>::read(std::span<T> row) {
  const unsigned char* in = stream_->read();
  if (half_) multigrid::from_half(reinterpret_cast<const _Float16*>(in), row.data(), row_length_);
  else std::memcpy(row.data(), in, encoded_bytes());
}

template <class T>
std::size_t RowStore<T>::make_durable() {
  const std::size_t n = stream_->make_durable();
  count_disk();
  return n;
}

template <class T>
void RowStore<T>::restore(std::size_t bytes) {
  stream_->restore(bytes);
  count_disk();
}

template class RowStore<float>;
template class RowStore<double>;
template class RowStore<unsigned char>;

}  // namespace gdp::schedule
