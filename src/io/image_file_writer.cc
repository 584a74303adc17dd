// Streaming image output: bands of rows converted and encoded by a codec (io/codecs.h) on a thread into a temporary file, renamed at the end.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string_view>
#include <system_error>
#include <thread>

#include <fmt/format.h>

#include "gdp/cleanup.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/temp_file.h"
#include "util/bounded_queue.h"
#include "util/clones.h"
#include "util/recycle_pool.h"
#include "util/thread_name.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

struct Band {
  int y0 = 0, y1 = 0;
  std::vector<float> rows;  // the rows as written (channel-major), converted by the encoder
};

// Channels [0, Ch) of a channel-major row into `ch` interleaved samples of type T (Ch == ch, a
// constant, lets the pixel loop vectorise: each pixel's samples are one store group); compiled
// for x86-64-v3 (AVX2) and the baseline, the loader picking one (this file is compiled with
// -ffp-contract=off: both round as the plain loop does).
template <int Ch, class T, class Convert>
GDP_CLONES void interleave_n(const float* row, int w, int ch, T* dst, Convert convert) {
  const int n = Ch > 0 ? Ch : ch;
  if constexpr (Ch > 0) {
    const float* src[Ch > 0 ? Ch : 1];
    for (int c = 0; c < Ch; ++c) src[c] = row + static_cast<std::size_t>(c) * w;
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < Ch; ++c) dst[static_cast<std::size_t>(x) * Ch + c] = convert(src[c][x]);
  } else {
    for (int c = 0; c < n; ++c) {
      const float* src = row + static_cast<std::size_t>(c) * w;
      for (int x = 0; x < w; ++x) dst[static_cast<std::size_t>(x) * n + c] = convert(src[x]);
    }
  }
}

// A channel-major row into interleaved samples of type T. `convert` is a lambda, so that it inlines
// (through a function pointer it was a call per sample).
template <class T, class Convert>
void interleave(const float* row, int w, int ch, unsigned char* out, Convert convert) {
  T* dst = reinterpret_cast<T*>(out);
  io::with_channel_count(ch, [&](auto n) { interleave_n<decltype(n)::value>(row, w, ch, dst, convert); });
}

}  // namespace

struct ImageFileWriter::Impl {
  fs::path path, temp;
  std::string name;
  int cleanup_handle = -1;
  std::unique_ptr<io::Encoder> output;
  int width = 0, height = 0, channels = 0, band_rows = 1, next_row = 0;
  io::EncodeSpec spec;
  SampleType band_type = SampleType::Float;  // UInt8 / UInt16 for 8- and 16-bit files, else Float
  std::size_t row_bytes = 0;
  bool integer_file = false, tiled = false, committed = false, opened = false, write_behind = true;
  Band band;
  // With the band encoded and the band filled: four. A writer ahead of the encoder sleeps until both
  // queued bands are taken (a futex wake-up every other band).
  util::BoundedQueue<Band> queue{2, 2};
  util::RecyclePool<std::vector<float>> spent;  // encoded bands' rows, allocated once
  std::vector<unsigned char> packed;  // the band being encoded, interleaved samples of band_type
  std::thread encoder;
  std::atomic<bool> encoder_failed{false};
  std::string error;  // the encoder's first error, written before encoder_failed is set

  OutputError fail(std::string_view problem) const { return OutputError(fmt::format("{}: {}", name, problem)); }
  void open();

  // A channel-major row into interleaved samples of the band type.
  void convert(const float* row, unsigned char* dst) const {
    if (band_type == SampleType::UInt8) {
      interleave<std::uint8_t>(row, width, channels, dst, [](float v) { return io::to_u8(v); });
    } else if (band_type == SampleType::UInt16) {
      interleave<std::uint16_t>(row, width, channels, dst, [](float v) { return io::to_u16(v); });
    } else if (integer_file) {
      interleave<float>(row, width, channels, dst, [](float v) { return io::clamp01(v); });
    } else {
      interleave<float>(row, width, channels, dst, [](float v) { return v; });
    }
  }

  // A band's rows into interleaved samples of the band type, then to the codec (on the encoder's
  // thread with write-behind: the conversion is off the writing thread too): row by row straight
  // into the codec's own buffer where it has one (io::Encoder::row_space), else through `packed`.
  void encode(const Band& b) {
    const std::size_t samples = static_cast<std::size_t>(width) * channels;
    try {
      if (output->row_space(b.y0)) {
        for (int y = b.y0; y < b.y1; ++y) {
          unsigned char* place = output->row_space(y);
          convert(b.rows.data() + (y - b.y0) * samples, place);
          output->write(y, y + 1, place);
        }
        return;
      }
      packed.resize(static_cast<std::size_t>(b.y1 - b.y0) * row_bytes);
      for (int r = 0; r < b.y1 - b.y0; ++r) convert(b.rows.data() + r * samples, packed.data() + r * row_bytes);
      output->write(b.y0, b.y1, packed.data());
    } catch (const std::exception& e) {
      throw fail(e.what());
    }
  }

  void run_encoder() {
    while (auto b = queue.pop()) {
      try {
        encode(*b);
        b->rows.clear();  // keeps its capacity for a later band
        spent.give(std::move(b->rows));
      } catch (const std::exception& e) {
        error = e.what();
        encoder_failed.store(true, std::memory_order_release);
        queue.close();
        return;
      }
    }
  }

  void check() const {
    if (encoder_failed.load(std::memory_order_acquire)) throw OutputError(error);
  }

  void send() {
    const int y1 = band.y1;
    if (!write_behind) {
      try {
        encode(band);
      } catch (const std::exception& e) {
        error = e.what();
        encoder_failed.store(true, std::memory_order_release);
        throw;
      }
      band.y0 = y1;
      band.rows.clear();
      return;
    }
    if (!queue.push(std::move(band))) {
      check();
      throw fail("writing stopped");
    }
    band = Band{y1, y1, spent.take()};
  }

  // Stops the encoder, closes the writer and removes the temporary file (no-op after commit).
  void abandon() noexcept {
    queue.close();
    if (encoder.joinable()) encoder.join();
    output.reset();
    if (!committed && !temp.empty()) {
      std::error_code ignored;
      fs::remove(temp, ignored);
    }
    cleanup::untrack(cleanup_handle);
  }
};

void check_compression(const std::filesystem::path& path, const std::string& compression) {
  if (compression.empty()) return;
  std::string known;
  try {
    known = io::create_encoder(path.string())->compression_refusal(compression);
  } catch (const std::exception&) {
    return;  // no codec for the name: ImageFileWriter says so, naming the file
  }
  if (known.empty()) return;  // (other formats' names are OpenImageIO's)
  throw UsageError(fmt::format("--compression {} does not apply to {}: {}", compression, path.string(), known));
}

ImageFileWriter::ImageFileWriter(const fs::path& path, int width, int height, int channels, const WriteOptions& options,
                                 bool write_behind)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.name = path.string();
  m.width = width;
  m.height = height;
  m.channels = channels;
  m.write_behind = write_behind;
  if (width <= 0 || height <= 0 || channels <= 0) throw m.fail("cannot write an empty image");
  // The codec is chosen by the final name; the temporary name keeps the same extension.
  try {
    m.output = io::create_encoder(m.name);
  } catch (const std::exception& e) {
    throw m.fail(e.what());
  }
  check_compression(path, options.compression);  // (every writer: gdp convert too)
  const std::string format = m.output->format_name();
  io::EncodeSpec& spec = m.spec;
  spec.width = width;
  spec.height = height;
  spec.channels = channels;
  spec.sample_type = io::choose_sample_type(format, options.sample_type);
  spec.jpeg_quality = options.jpeg_quality;
  spec.compression = options.compression;
  spec.fits_header = options.fits_header;
  spec.geo = options.geo;
  spec.frame = options.frame;
  const double bytes = static_cast<double>(width) * height * channels * io::sample_bytes(spec.sample_type);
  spec.bigtiff = format == "tiff" && bytes > io::kBigTiffBytes;
  if (options.tiled) {
    if (format != "tiff" && format != "openexr")
      throw m.fail(fmt::format("tiled output needs a .tif or .exr file, not {}", format));
    if (options.tile_size <= 0 || options.tile_size % 16 != 0)
      throw m.fail(fmt::format("tile size {} is not a positive multiple of 16", options.tile_size));
    spec.tile_size = options.tile_size;
    m.tiled = true;
  }
  std::string why;
  m.temp = io::create_temp_file(path, why);
  if (m.temp.empty()) throw m.fail("cannot write: " + why);
  m.cleanup_handle = cleanup::track(m.temp.string());  // also deleted if the process is interrupted
  m.band_rows = io::band_rows(width, height, channels, m.tiled ? spec.tile_size : 1);
}

// The file is opened with the first row, so that a run failing before it (bad input, say) does
// not make the codec complain about an empty image.
void ImageFileWriter::Impl::open() {
  try {
    output->open(temp.string(), spec);
  } catch (const std::exception& e) {
    throw fail(e.what());
  }
  // For integer files values are clamped to [0, 1] here (NaN -> 0), so the result never depends
  // on how the codec converts out-of-range values; 8- and 16-bit samples are also quantised here.
  integer_file = output->integer_file();
  band_type = output->stored();
  row_bytes = static_cast<std::size_t>(width) * channels * io::sample_bytes(band_type);
  if (write_behind) encoder = std::thread([this] {
    util::name_thread("gdp-encode");
    run_encoder();
  });
  opened = true;
}

ImageFileWriter::~ImageFileWriter() { impl_->abandon(); }

void ImageFileWriter::write_row(int y, std::span<const float> row) {
  Impl& m = *impl_;
  const int w = m.width, ch = m.channels;
  if (m.committed) throw std::logic_error(fmt::format("{}: row {} written after commit()", m.name, y));
  if (y != m.next_row || y >= m.height)
    throw std::logic_error(fmt::format("{}: row {} written out of order (next is {})", m.name, y, m.next_row));
  if (row.size() < static_cast<std::size_t>(w) * ch)
    throw std::logic_error(fmt::format("{}: row of {} samples, {} needed", m.name, row.size(), w * ch));
  m.check();
  if (!m.opened) m.open();
  const std::size_t samples = static_cast<std::size_t>(w) * ch;
  if (m.band.rows.empty()) m.band.rows.reserve(m.band_rows * samples);
  m.band.rows.insert(m.band.rows.end(), row.begin(), row.begin() + static_cast<std::ptrdiff_t>(samples));
  m.band.y1 = ++m.next_row;
  if (m.band.y1 - m.band.y0 == m.band_rows || m.next_row == m.height) m.send();
}

int ImageFileWriter::stored_levels() {
  Impl& m = *impl_;
  if (!m.opened) m.open();
  return m.band_type == SampleType::UInt8 ? 255 : m.band_type == SampleType::UInt16 ? 65535 : 0;
}

void ImageFileWriter::commit() {
  Impl& m = *impl_;
  if (m.committed) throw std::logic_error(fmt::format("{}: commit() called twice", m.name));
  if (m.next_row != m.height) throw m.fail(fmt::format("only {} of {} rows were written", m.next_row, m.height));
  m.queue.finish();  // the encoder writes what is queued, then stops
  if (m.encoder.joinable()) m.encoder.join();
  m.check();
  try {
    m.output->close();
  } catch (const std::exception& e) {
    throw m.fail(e.what());
  }
  m.output.reset();
  std::error_code ec;
  fs::rename(m.temp, m.path, ec);
  if (ec) throw m.fail("cannot move the finished file into place: " + ec.message());
  m.committed = true;
}

}  // namespace gdp
