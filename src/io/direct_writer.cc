// O_DIRECT writes on a thread: jobs in, buffers back, the first error kept for the writer.
#include "io/direct_writer.h"

#include <fcntl.h>

#include <cerrno>
#include <string>
#include <system_error>

#include "gdp/errors.h"
#include "util/exact_io.h"

namespace gdp::io {

DirectWriter::DirectWriter(int fd, std::span<unsigned char* const> buffers, std::string where, std::string hint)
    : where_(std::move(where)),
      hint_(std::move(hint)),
      idle_(buffers.begin(), buffers.end()),
      jobs_(buffers.size()),
      done_(buffers.size()) {
  thread_ = std::thread([this, fd] { run(fd); });
}

DirectWriter::~DirectWriter() {
  jobs_.finish();
  thread_.join();
}

void DirectWriter::run(int fd) {
  while (std::optional<Job> job = jobs_.pop()) {
    if (error_.load() == 0) {
      util::Transfer t = util::pwrite_full(fd, job->data, job->size, job->at);
      const int flags = ::fcntl(fd, F_GETFL);
      if (t.error == EINVAL && flags >= 0 && (flags & O_DIRECT) && ::fcntl(fd, F_SETFL, flags & ~O_DIRECT) == 0)
        t = util::pwrite_full(fd, job->data + t.done, job->size - t.done, job->at + t.done);
      if (t.error != 0) error_.store(t.error);
    }
    done_.push(job->data);
  }
}

void DirectWriter::check() const {
  if (const int e = error_.load())
    throw OutputError(where_ + ": cannot write: " + std::generic_category().message(e) + hint_);
}

unsigned char* DirectWriter::take() {
  if (idle_.empty()) {
    idle_.push_back(*done_.pop());
    --out_;
  }
  check();
  unsigned char* b = idle_.back();
  idle_.pop_back();
  return b;
}

void DirectWriter::put(unsigned char* data, std::size_t size, std::size_t at) {
  ++out_;
  jobs_.push(Job{data, size, at});
}

void DirectWriter::drain() {
  for (; out_ > 0; --out_) idle_.push_back(*done_.pop());
  check();
}

}  // namespace gdp::io
