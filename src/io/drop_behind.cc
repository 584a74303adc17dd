// Drop-behind for sequentially streamed files: sync_file_range and posix_fadvise(DONTNEED).
#include "io/drop_behind.h"

#include <fcntl.h>

#include <cerrno>

namespace gdp::io {
namespace {

// False only when the disk reported an error: a file system that cannot do it is not one.
bool sync_range(int fd, std::size_t from, std::size_t to, unsigned flags) {
  return ::sync_file_range(fd, static_cast<off_t>(from), static_cast<off_t>(to - from), flags) == 0 || errno != EIO;
}

}  // namespace

bool DropBehind::wrote(int fd, std::size_t end) {
  if (window_ == 0 || end < pushed_ + window_) return true;
  if (!sync_range(fd, pushed_, end, SYNC_FILE_RANGE_WRITE)) return false;
  if (pushed_ > dropped_) {
    if (!sync_range(fd, dropped_, pushed_,
                    SYNC_FILE_RANGE_WAIT_BEFORE | SYNC_FILE_RANGE_WRITE | SYNC_FILE_RANGE_WAIT_AFTER))
      return false;
    ::posix_fadvise(fd, static_cast<off_t>(dropped_), static_cast<off_t>(pushed_ - dropped_), POSIX_FADV_DONTNEED);
    dropped_ = pushed_;
  }
  pushed_ = end;
  return true;
}

void DropBehind::read(int fd, std::size_t end) {
  if (window_ == 0 || end < dropped_ + window_) return;
  ::posix_fadvise(fd, static_cast<off_t>(dropped_), static_cast<off_t>(end - dropped_), POSIX_FADV_DONTNEED);
  dropped_ = end;
}

}  // namespace gdp::schedule
