// Streaming image input: bands of rows from a codec (io/codecs.h), optionally decoded ahead on a thread.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <system_error>
#include <thread>
#include <type_traits>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "gdp/size_check.h"
#include "io/codec_util.h"
#include "io/codecs.h"
#include "util/bounded_queue.h"
#include "util/thread_name.h"
#include "util/recycle_pool.h"
#include "util/clones.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// Rows [y0, y1) of the window's columns, all channels, interleaved and of the sample type as in
// the file (8- and 16-bit samples become floats only in read_row(): a quarter or half of the
// memory, one pass).
struct Band {
  int y0 = 0, y1 = 0;
  std::vector<unsigned char> bytes;
  std::string error;  // non-empty: decoding failed here
};

// 8- and 16-bit samples as io/codec_util.h converts them, floats as they are.
template <class T>
inline float to_float(T v) {
  if constexpr (std::is_same_v<T, std::uint8_t>) return io::from_u8(v);
  else if constexpr (std::is_same_v<T, std::uint16_t>) return io::from_u16(v);
  else return v;
}

// One row of a band (w columns of `ch` interleaved channels) into a channel-major row of floats,
// channels `stride` apart. Ch == ch, a constant, lets the loop vectorise (Ch == 0: the count at run
// time); compiled for x86-64-v3 (AVX2) and the baseline, the loader picking one. The conversion is
// called directly, so that it is inlined: through a function pointer it was a call per sample
// (docs/scaling.md, "The input pass's arithmetic").
template <int Ch, class T>
GDP_CLONES void deinterleave_n(const T* src, int w, int ch,
                                std::size_t stride, float* out) {
  const int n = Ch > 0 ? Ch : ch;
  if constexpr (Ch > 0)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < Ch; ++c) out[c * stride + x] = to_float(src[static_cast<std::size_t>(x) * Ch + c]);
  else
    for (int c = 0; c < n; ++c)
      for (int x = 0; x < w; ++x) out[c * stride + x] = to_float(src[static_cast<std::size_t>(x) * n + c]);
}

template <class T>
void deinterleave(const unsigned char* band_row, int w, int ch, std::size_t stride, float* out) {
  const T* src = reinterpret_cast<const T*>(band_row);
  io::with_channel_count(ch, [&](auto n) { deinterleave_n<decltype(n)::value>(src, w, ch, stride, out); });
}

}  // namespace

struct ImageFileReader::Impl {
  fs::path path;
  std::string name;
  bool prefetch;
  ColumnRange columns;
  int page = 0;
  int x0 = 0, x1 = 0;  // the window
  bool decoder_used = false;  // the decoder has read rows (formats like PNG only go forwards)
  bool in_place = false;  // set_columns(): the window's samples go to their columns of a full row
  std::unique_ptr<io::Decoder> decoder;
  io::ImageLayout layout;
  int band_rows = 1;
  std::size_t row_bytes = 0;  // of the window
  Band band;                  // the band read_row serves from
  util::RecyclePool<std::vector<unsigned char>> spent;  // bands' bytes, allocated once
  int next_row = 0;
  std::size_t ahead_bytes = 0;  // read_ahead(): how far to decode ahead (else two bands)
  std::atomic<int> decoded{0};  // rows decoded in this pass
  std::string failed;  // non-empty: a band failed to decode; read_row() throws this
  std::unique_ptr<util::BoundedQueue<Band>> queue;
  std::thread decoder_thread;

  InputError fail(std::string_view problem) const { return InputError(fmt::format("{}: {}", name, problem)); }

  void open() {
    // Check the file ourselves first: codecs' messages do not carry the system's reason.
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw fail("cannot open: Is a directory");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw fail("cannot open: " + std::generic_category().message(errno));
    ::close(fd);
    try {
      decoder = io::open_decoder(name, page);
    } catch (const std::exception& e) {
      throw fail(e.what());
    }
    layout = decoder->layout();
    decoder_used = false;
    try {  // the codecs check before they allocate; OpenImageIO's are checked here
      check_image_size(layout.width, layout.height, layout.channels);
    } catch (const std::exception& e) {
      throw fail(e.what());
    }
    if (layout.channels > 4) throw fail(fmt::format("{} channels; gdp supports 1 to 4", layout.channels));
    set_window();
  }

  // The window from `columns`, and the band sizes that follow from it.
  void set_window() {
    x0 = columns.begin;
    x1 = columns.end < 0 ? layout.width : columns.end;
    if (x0 < 0 || x1 > layout.width || x0 >= x1)
      throw fail(fmt::format("column window [{}, {}) is not inside the image's {} columns", columns.begin,
                             columns.end, layout.width));
    band_rows = io::band_rows(x1 - x0, layout.height, layout.channels, std::max(layout.tile_height, 1));
    row_bytes = static_cast<std::size_t>(x1 - x0) * layout.channels * io::sample_bytes(layout.stored);
  }

  // Decodes rows [y0, y0 + band_rows).
  Band decode(int y0) noexcept {
    Band b;
    b.y0 = y0;
    b.y1 = std::min(layout.height, y0 + band_rows);
    try {
      b.bytes = spent.take();
      b.bytes.resize(static_cast<std::size_t>(b.y1 - y0) * row_bytes);
      decoder_used = true;
      decoder->read(y0, b.y1, x0, x1, b.bytes.data());
      decoded.store(b.y1, std::memory_order_relaxed);
    } catch (const std::bad_alloc&) {
      b.error = "out of memory for a band of rows";
    } catch (const std::exception& e) {
      b.error = e.what();
    }
    return b;
  }

  // A new pass from row 0; with prefetch, decoding starts at the first read_row() (so that a
  // set_columns() hint before it wastes nothing), or at read_ahead().
  void start() {
    next_row = 0;
    decoded.store(0, std::memory_order_relaxed);
    band = Band{};
    failed.clear();
  }

  void start_decoding() {
    // Bands queued: two, or after read_ahead() as many as fit its bytes (2 to 64); one more being
    // decoded, one being read. A decoder ahead of its reader sleeps until half the queue is taken
    // (a futex wake-up per half).
    const std::size_t band_bytes = std::max<std::size_t>(row_bytes * static_cast<std::size_t>(band_rows), 1);
    const std::size_t ahead = std::clamp<std::size_t>(ahead_bytes / band_bytes, 2, 64);
    queue = std::make_unique<util::BoundedQueue<Band>>(ahead, std::max<std::size_t>(2, ahead / 2));
    decoder_thread = std::thread([this] {
      util::name_thread("gdp-decode");
      for (int y0 = 0; y0 < layout.height; y0 += band_rows) {
        Band b = decode(y0);
        const bool failed = !b.error.empty();
        if (!queue->push(std::move(b)) || failed) return;
      }
    });
  }

  void stop() {
    if (queue) queue->close();
    if (decoder_thread.joinable()) decoder_thread.join();
    queue.reset();
  }

  void next_band() {
    if (prefetch && !queue) start_decoding();
    spent.give(std::move(band.bytes));
    if (!prefetch) {
      band = decode(band.y1);
    } else {
      auto b = queue->pop();
      if (!b) throw fail("reading stopped");
      band = std::move(*b);
    }
    if (!band.error.empty()) {
      failed = band.error;  // every later read_row() fails too, until rewind()
      band = Band{};
      throw fail(failed);
    }
  }
};

ImageFileReader::ImageFileReader(const fs::path& path, bool prefetch) : ImageFileReader(path, prefetch, ColumnRange{}) {}

ImageFileReader::ImageFileReader(const fs::path& path, bool prefetch, ColumnRange columns, int page)
    : impl_(std::make_unique<Impl>()) {
  impl_->page = page;
  impl_->path = path;
  impl_->name = path.string();
  impl_->prefetch = prefetch;
  impl_->columns = columns;
  impl_->open();
  impl_->start();
}

ImageFileReader::~ImageFileReader() { impl_->stop(); }

const ImageFileInfo& ImageFileReader::info() const { return impl_->layout.info; }
int ImageFileReader::window_begin() const { return impl_->x0; }
int ImageFileReader::window_width() const { return impl_->x1 - impl_->x0; }
int ImageFileReader::width() const { return impl_->layout.width; }
int ImageFileReader::height() const { return impl_->layout.height; }
int ImageFileReader::channels() const { return impl_->layout.channels; }

void ImageFileReader::read_row(int y, std::span<float> out) {
  Impl& m = *impl_;
  const int w = m.x1 - m.x0, ch = m.layout.channels;
  const std::size_t stride = m.in_place ? m.layout.width : w;
  float* dst = out.data() + (m.in_place ? m.x0 : 0);
  if (y != m.next_row)
    throw std::logic_error(fmt::format("{}: row {} read out of order (next is {})", m.name, y, m.next_row));
  if (y >= m.layout.height) throw std::logic_error(fmt::format("{}: row {} past the end", m.name, y));
  if (out.size() < stride * ch)
    throw std::logic_error(fmt::format("{}: row buffer of {} samples, {} needed", m.name, out.size(), stride * ch));
  if (!m.failed.empty()) throw m.fail(m.failed);
  if (y >= m.band.y1) m.next_band();
  const unsigned char* src = m.band.bytes.data() + static_cast<std::size_t>(y - m.band.y0) * m.row_bytes;
  if (m.layout.stored == SampleType::UInt8) {
    deinterleave<std::uint8_t>(src, w, ch, stride, dst);
  } else if (m.layout.stored == SampleType::UInt16) {
    deinterleave<std::uint16_t>(src, w, ch, stride, dst);
  } else {
    deinterleave<float>(src, w, ch, stride, dst);
  }
  ++m.next_row;
}

void ImageFileReader::read_ahead(std::size_t bytes) {
  Impl& m = *impl_;
  m.ahead_bytes = bytes;
  if (m.prefetch && !m.queue && m.next_row == 0) m.start_decoding();
}

int ImageFileReader::decoded_rows() const { return impl_->decoded.load(std::memory_order_relaxed); }

void ImageFileReader::set_columns(int begin, int end) {
  Impl& m = *impl_;
  if (m.next_row != 0) throw std::logic_error(m.name + ": set_columns after rows were read");
  if (m.in_place && begin == m.x0 && end == m.x1) return;
  m.stop();
  m.columns = {begin, end};
  m.in_place = true;
  if (m.decoder_used) {  // rows decoded already: decode afresh from the top
    m.decoder.reset();
    m.open();
  } else {  // nothing decoded yet: the decoder reads any window
    m.set_window();
  }
  m.start();
}

void ImageFileReader::rewind() {
  Impl& m = *impl_;
  if (m.band.y0 == 0 && m.band.y1 == m.layout.height) {  // one band holds the whole image: keep it
    m.next_row = 0;
    return;
  }
  m.stop();
  m.decoder.reset();  // formats such as PNG and JPEG only decode forwards: open again
  m.open();
  m.start();
}

}  // namespace gdp
