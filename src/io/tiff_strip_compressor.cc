// Worker threads that predict and deflate TIFF strips with libdeflate, and their in-order hand-back.
#include "io/tiff_strip_compressor.h"

#include <libdeflate.h>

#include <memory>

#include "io/codec.h"
#include "io/tiff_predictor.h"
#include "util/thread_name.h"

namespace gdp::io {

StripCompressor::StripCompressor(const StripFormat& format, int threads) : format_(format), limit_(threads + 2) {
  for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

StripCompressor::~StripCompressor() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    bells_.ring_all(idle_);
  }
  for (std::thread& t : workers_) t.join();
}

void StripCompressor::work() {
  struct Free {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  util::name_thread("gdp-deflate");
  const std::unique_ptr<libdeflate_compressor, Free> compressor(libdeflate_alloc_compressor(format_.level));
  std::vector<unsigned char> predicted;
  std::unique_lock lock(mutex_);
  for (;;) {
    bells_.wait(lock, idle_, [&] { return stopping_ || !jobs_.empty(); });
    if (stopping_) return;
    Job job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    Zipped out{zipped_.take()};
    std::string failure;
    try {
      if (!compressor) throw CodecError("out of memory for a deflate compressor");
      const std::size_t row = static_cast<std::size_t>(format_.width) * format_.channels * format_.sample_bytes;
      unsigned char* data = job.rows.data();
      if (format_.floating) {
        if (predicted.size() < job.size) predicted.resize(job.size);
        for (std::size_t at = 0; at < job.size; at += row)
          float_difference(job.rows.data() + at, predicted.data() + at, format_.width, format_.channels,
                           format_.sample_bytes);
        data = predicted.data();
      } else {
        for (std::size_t at = 0; at < job.size; at += row)
          horizontal_difference(job.rows.data() + at, format_.width, format_.channels, format_.sample_bytes);
      }
      const std::size_t bound = libdeflate_zlib_compress_bound(compressor.get(), job.size);
      if (out.bytes.size() < bound) out.bytes.resize(bound);
      out.size = libdeflate_zlib_compress(compressor.get(), data, job.size, out.bytes.data(), bound);
      if (out.size == 0) throw CodecError("deflate failed");
    } catch (const std::exception& e) {
      failure = e.what();
    }
    spent_.give(std::move(job.rows));
    lock.lock();
    if (!failure.empty() && error_.empty()) error_ = failure;
    done_[job.strip] = std::move(out);
    if (util::Bell* wake = job.strip == next_ || !error_.empty() ? bells_.call(submitter_) : nullptr) {
      lock.unlock();
      bells_.ring(wake);
      lock.lock();
    }
  }
}

void StripCompressor::sink_ready(std::unique_lock<std::mutex>& lock, const Sink& sink) {
  for (auto it = done_.find(next_); it != done_.end(); it = done_.find(next_)) {
    Zipped data = std::move(it->second);
    done_.erase(it);
    if (!error_.empty()) throw CodecError("cannot write: " + error_);
    const int strip = next_++;
    lock.unlock();
    sink(strip, {data.bytes.data(), data.size});  // libtiff, on the submitting thread, without the lock
    zipped_.give(std::move(data.bytes));
    lock.lock();
    --outstanding_;
  }
  if (!error_.empty()) throw CodecError("cannot write: " + error_);
}

void StripCompressor::submit(int strip, std::vector<unsigned char> rows, std::size_t size, const Sink& sink) {
  std::unique_lock lock(mutex_);
  for (;;) {
    sink_ready(lock, sink);
    if (outstanding_ < limit_) break;
    wait_for_next(lock);
  }
  jobs_.push_back(Job{strip, std::move(rows), size});
  ++outstanding_;
  util::Bell* wake = bells_.call(idle_);
  lock.unlock();
  bells_.ring(wake);
}

void StripCompressor::wait_for_next(std::unique_lock<std::mutex>& lock) {
  bells_.wait(lock, submitter_, [&] { return done_.contains(next_) || !error_.empty(); });
}

void StripCompressor::finish(const Sink& sink) {
  std::unique_lock lock(mutex_);
  for (;;) {
    sink_ready(lock, sink);
    if (outstanding_ == 0) return;
    wait_for_next(lock);
  }
}

}  // namespace gdp::io
