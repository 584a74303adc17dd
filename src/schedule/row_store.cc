// Row stores in memfds or in unlinked scratch files, with optional half-float encoding.
#include "schedule/row_store.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "schedule/read_ahead.h"
#include "util/exact_io.h"

namespace gdp::schedule {
namespace {

constexpr std::size_t kFileBuffer = std::size_t{256} << 10;

std::string system_message() { return std::generic_category().message(errno); }

}  // namespace

int open_unlinked(const std::filesystem::path& dir, const std::string& name) {
  std::string pattern = (dir / fmt::format("gdp-scratch-{}-{}-XXXXXX", static_cast<long>(::getpid()), name)).string();
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0)
    throw OutputError(fmt::format("scratch directory {}: cannot create a file: {}", dir.string(), system_message()));
  ::unlink(pattern.c_str());
  return fd;
}

template <class T>
RowStore<T>::RowStore(const StorePolicy& policy, std::size_t row_length, std::size_t rows, std::string name)
    : name_(policy.name_prefix + name),
      row_length_(row_length),
      encoding_(policy.encoding_of(name)),
      buffer_(std::max(kFileBuffer, encoded_bytes())),
      budget_(policy.budget ? policy.budget : &ScratchBudget::process()),
      drop_behind_(policy.drop_behind) {
  const std::size_t total = encoded_bytes() * rows;
  if (!policy.keep_dir.empty()) {
    dir_ = policy.keep_dir;
    const std::filesystem::path path = dir_ / (name_ + ".store");
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw OutputError(fmt::format("checkpoint {}: cannot open: {}", path.string(), system_message()));
  } else if (budget_->reserve(total)) {
    // In memory: the same writes and reads as a file, into pages the kernel need not zero (a
    // fresh anonymous page must be; docs/how-streaming-works.md, "Scratch in a memfd").
    fd_ = ::memfd_create(("gdp-scratch-" + name_).c_str(), MFD_CLOEXEC);
    if (fd_ < 0) {
      budget_->release(total);
      throw OutputError(fmt::format("scratch memory ({}): cannot create: {}", name_, system_message()));
    }
    memory_ = total;
    drop_behind_ = io::DropBehind();
  } else {
    budget_->count_spill();
    dir_ = policy.dir.empty() ? std::filesystem::temp_directory_path() : policy.dir;
    fd_ = open_unlinked(dir_, name_);
  }
  if (on_disk()) ::posix_fadvise(fd_, 0, 0, POSIX_FADV_SEQUENTIAL);  // read back front to back: a larger readahead
}

// The file now holds at least `bytes` (what the budget's on-disk count says).
template <class T>
void RowStore<T>::count_disk(std::size_t bytes) {
  if (bytes <= disk_bytes_ || !on_disk()) return;
  budget_->add_disk(static_cast<std::ptrdiff_t>(bytes - disk_bytes_));
  disk_bytes_ = bytes;
}

template <class T>
std::string RowStore<T>::where() const {
  if (!on_disk()) return fmt::format("scratch memory ({})", name_);
  return fmt::format("scratch file in {} ({})", dir_.string(), name_);
}

template <class T>
RowStore<T>::~RowStore() {
  ahead_.reset();  // its thread reads fd_
  ::close(fd_);
  budget_->add_disk(-static_cast<std::ptrdiff_t>(disk_bytes_));
  budget_->release(memory_);
}

template <class T>
std::size_t RowStore<T>::encoded_bytes() const {
  return row_length_ * (encoding_ == StoreEncoding::Half ? sizeof(_Float16) : sizeof(T));
}

template <class T>
void RowStore<T>::append(std::span<const T> row) {
  const std::size_t n = encoded_bytes();
  if (reading_) throw std::logic_error("RowStore::append while reading");
  if (buffered_ + n > buffer_.size()) flush();
  unsigned char* out = buffer_.data() + buffered_;
  if (encoding_ == StoreEncoding::Half) {
    multigrid::to_half(row.data(), reinterpret_cast<_Float16*>(out), row_length_);
  } else {
    std::memcpy(out, row.data(), n);
  }
  buffered_ += n;
  written_ += n;
}

template <class T>
void RowStore<T>::flush() {
  const char* hint = on_disk() ? " (--temp DIR puts scratch files elsewhere)"
                               : " (--memory SIZE keeps less in memory; a file size limit, ulimit -f, bounds it too)";
  util::write_exactly(fd_, buffer_.data(), buffered_, {where(), {}, hint});
  buffered_ = 0;
  count_disk(written_);
  if (!drop_behind_.wrote(fd_, written_))
    throw OutputError(fmt::format("{}: cannot write: {}", where(), system_message()));
}

template <class T>
void RowStore<T>::rewind() {
  if (!reading_) flush();
  ahead_.reset();
  buffered_ = 0;
  drop_behind_.restart(0);
  // A file is read ahead on a thread of its own (the wait for its disk is that thread's); memory
  // is read by the reader itself, a chunk at a time into the file buffer (fill()).
  if (on_disk()) ahead_ = std::make_unique<ReadAhead>(fd_, 0, written_, chunk_bytes(), drop_behind_, where());
  cursor_ = read_at_ = 0;
  reading_ = true;
}

// Chunks of whole rows (a row never straddles two), about a file buffer each.
template <class T>
std::size_t RowStore<T>::chunk_bytes() const {
  const std::size_t row = encoded_bytes();
  return std::max<std::size_t>(1, kFileBuffer / row) * row;
}

// The next chunk: from the ReadAhead's thread (a file), or read here (memory).
template <class T>
void RowStore<T>::fill() {
  if (cursor_ != buffered_) throw std::logic_error("RowStore: a row straddles two chunks");
  if (ahead_) {
    const std::span<const unsigned char> c = ahead_->next();
    chunk_ = c.data();
    buffered_ = c.size();
  } else {
    const std::size_t n = std::min(chunk_bytes(), written_ - read_at_);
    util::read_exactly_at(fd_, buffer_.data(), n, read_at_, {where()});
    chunk_ = buffer_.data();
    buffered_ = n;
    read_at_ += n;
  }
  cursor_ = 0;
}

template <class T>
void RowStore<T>::read(std::span<T> row) {
  const std::size_t n = encoded_bytes();
  if (!reading_) throw std::logic_error("RowStore::read before rewind");
  if (cursor_ + n > buffered_) fill();
  if (cursor_ + n > buffered_) throw std::logic_error("RowStore: read past the end");
  const unsigned char* in = chunk_ + cursor_;
  if (encoding_ == StoreEncoding::Half) {
    multigrid::from_half(reinterpret_cast<const _Float16*>(in), row.data(), row_length_);
  } else {
    std::memcpy(row.data(), in, n);
  }
  cursor_ += n;
}

template <class T>
void RowStore<T>::clear() {
  ahead_.reset();
  ::lseek(fd_, 0, SEEK_SET);  // later reads never pass written_
  buffered_ = cursor_ = written_ = 0;
  drop_behind_.restart(0);
  reading_ = false;
}

template <class T>
std::size_t RowStore<T>::make_durable() {
  if (!on_disk()) throw std::logic_error("RowStore::make_durable in memory");
  if (!reading_) flush();
  if (::fdatasync(fd_) != 0) throw OutputError(fmt::format("{}: cannot sync: {}", where(), system_message()));
  return written_;
}

template <class T>
void RowStore<T>::restore(std::size_t bytes) {
  if (!on_disk()) throw std::logic_error("RowStore::restore in memory");
  ahead_.reset();
  const off_t end = ::lseek(fd_, 0, SEEK_END);
  if (end < 0 || static_cast<std::size_t>(end) < bytes)
    throw OutputError(fmt::format("{}: shorter than the checkpoint says ({} of {} bytes)", where(),
                                  static_cast<long long>(end), bytes));
  if (::ftruncate(fd_, static_cast<off_t>(bytes)) != 0 || ::lseek(fd_, static_cast<off_t>(bytes), SEEK_SET) < 0)
    throw OutputError(fmt::format("{}: {}", where(), system_message()));
  buffered_ = cursor_ = 0;
  written_ = bytes;
  drop_behind_.restart(bytes);
  count_disk(bytes);
  reading_ = false;
}

template class RowStore<float>;
template class RowStore<double>;
template class RowStore<unsigned char>;

}  // namespace gdp::schedule
