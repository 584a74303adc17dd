// Streaming image output: bands of rows encoded by OpenImageIO on a thread into a temporary file, renamed at the end.
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
#include "io/checked_file.h"
#include "io/oiio_util.h"
#include "io/temp_file.h"
#include "schedule/bounded_queue.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

struct Band {
  int y0 = 0, y1 = 0;
  std::vector<unsigned char> bytes;  // interleaved samples of the writer's band type
};

float clamp01(float v) { return v > 0.0f ? std::min(v, 1.0f) : 0.0f; }  // NaN -> 0

// A channel-major row into interleaved samples of type T.
template <class T, class Convert>
void interleave(const float* row, int w, int ch, unsigned char* out, Convert convert) {
  T* dst = reinterpret_cast<T*>(out);
  for (int c = 0; c < ch; ++c) {
    const float* src = row + static_cast<std::size_t>(c) * w;
    for (int x = 0; x < w; ++x) dst[static_cast<std::size_t>(x) * ch + c] = convert(src[x]);
  }
}

}  // namespace

struct ImageFileWriter::Impl {
  fs::path path, temp;
  std::string name;
  int cleanup_handle = -1;
  // Declared before `output`, which writes through it, so it is destroyed after it.
  std::unique_ptr<io::CheckedFile> file;
  std::unique_ptr<OIIO::ImageOutput> output;
  int width = 0, height = 0, channels = 0, band_rows = 1, next_row = 0;
  OIIO::ImageSpec spec;
  OIIO::TypeDesc band_type = OIIO::TypeFloat;  // as stored for 8- and 16-bit files (io::native_integer_type)
  std::size_t row_bytes = 0;
  bool integer_file = false, tiled = false, committed = false, opened = false, write_behind = true;
  Band band;
  schedule::BoundedQueue<Band> queue{1};  // with the band encoded and the band filled: three
  std::thread encoder;
  std::atomic<bool> encoder_failed{false};
  std::string error;  // the encoder's first error, written before encoder_failed is set

  OutputError fail(std::string_view problem) const { return OutputError(fmt::format("{}: {}", name, problem)); }
  void open();

  void encode(const Band& b) {
    const bool ok = tiled ? output->write_tiles(0, width, b.y0, b.y1, 0, 1, band_type, b.bytes.data())
                          : output->write_scanlines(b.y0, b.y1, 0, band_type, b.bytes.data());
    // A failed write to the file itself explains more than the codec's message, if it has one.
    if (file && file->failed()) throw fail("cannot write: " + file->problem());
    if (!ok) throw fail("cannot write: " + io::one_line(output->geterror()));
  }

  void run_encoder() {
    while (auto b = queue.pop()) {
      try {
        encode(*b);
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
      band.bytes.clear();
      return;
    }
    if (!queue.push(std::move(band))) {
      check();
      throw fail("writing stopped");
    }
    band = Band{y1, y1, {}};
  }

  // Stops the encoder, closes the writer and removes the temporary file (no-op after commit).
  void abandon() noexcept {
    queue.close();
    if (encoder.joinable()) encoder.join();
    output.reset();
    file.reset();
    if (!committed && !temp.empty()) {
      std::error_code ignored;
      fs::remove(temp, ignored);
    }
    cleanup::untrack(cleanup_handle);
  }
};

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
  // The plugin is chosen by the final name; the temporary name keeps the same extension.
  m.output = OIIO::ImageOutput::create(m.name);
  if (!m.output) {
    OIIO::geterror();  // clear OpenImageIO's pending message; ours names the cause
    if (!path.has_extension()) throw m.fail("cannot write: no file extension to choose an image format by");
    throw m.fail(fmt::format("cannot write: no image format for extension '{}'", path.extension().string()));
  }
  const std::string format = m.output->format_name();
  OIIO::ImageSpec spec(width, height, channels, io::type_desc_of(io::choose_sample_type(format, options.sample_type)));
  spec.attribute("oiio:UnassociatedAlpha", 1);  // write alpha as given, never un-premultiply it
  // OpenImageIO 2.4 takes the quality as "Compression" = "CODEC:Q" (jpeg and webp also accept
  // "CompressionQuality"; heif does not); without it JPEG is written at quality 98.
  if (format == "jpeg" || format == "webp" || format == "heif") {
    const std::string codec = format == "heif" ? "heic" : format;
    spec.attribute("Compression", fmt::format("{}:{}", codec, std::clamp(options.jpeg_quality, 1, 100)));
  }
  if (!options.compression.empty()) spec.attribute("Compression", options.compression);
  const double bytes = static_cast<double>(width) * height * channels * spec.format.size();
  if (format == "tiff" && bytes > io::kBigTiffBytes) spec.attribute("tiff:bigtiff", 1);
  if (options.tiled) {
    if (format != "tiff" && format != "openexr")
      throw m.fail(fmt::format("tiled output needs a .tif or .exr file, not {}", format));
    if (options.tile_size <= 0 || options.tile_size % 16 != 0)
      throw m.fail(fmt::format("tile size {} is not a positive multiple of 16", options.tile_size));
    spec.tile_width = spec.tile_height = options.tile_size;
    m.tiled = true;
  }
  std::string why;
  m.temp = io::create_temp_file(path, why);
  if (m.temp.empty()) throw m.fail("cannot write: " + why);
  m.cleanup_handle = cleanup::track(m.temp.string());  // also deleted if the process is interrupted
  m.spec = spec;
  m.band_rows = io::band_rows(width, height, channels, m.tiled ? spec.tile_height : 1);
}

// The file is opened with the first row, so that a run failing before it (bad input, say) does
// not make the codec complain about an empty image.
void ImageFileWriter::Impl::open() {
  // OpenImageIO 2.4's JPEG writer keeps the whole compressed file in memory when it writes
  // through a proxy: accept that up to kJpegBufferBytes of 8-bit pixels (some 10-100 MB of JPEG);
  // larger JPEGs stream to the file, where a failed write makes libjpeg exit() the process (the
  // temporary file is still removed, by gdp::cleanup's exit handler).
  const double pixel_bytes = static_cast<double>(width) * height * channels;
  const bool buffers_whole_file = output->format_name() == std::string_view("jpeg");
  if (output->supports("ioproxy") && (!buffers_whole_file || pixel_bytes <= io::kJpegBufferBytes)) {
    file = std::make_unique<io::CheckedFile>(temp.string());
    if (!output->set_ioproxy(file.get())) file.reset();
  }
  if (!output->open(temp.string(), spec)) {
    const std::string problem = io::one_line(output->geterror());
    throw fail("cannot write: " + (file && file->failed() ? file->problem() : problem));
  }
  // For integer files values are clamped to [0, 1] here (NaN -> 0), so the result never depends
  // on how the writer converts out-of-range values; 8- and 16-bit samples are also quantised here.
  integer_file = !output->spec().format.is_floating_point();
  const OIIO::TypeDesc native = io::native_integer_type(output->spec());
  if (native != OIIO::TypeDesc::UNKNOWN) band_type = native;
  row_bytes = static_cast<std::size_t>(width) * channels * band_type.size();
  if (write_behind) encoder = std::thread([this] { run_encoder(); });
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
  if (m.band.bytes.empty()) m.band.bytes.reserve(m.band_rows * m.row_bytes);
  const std::size_t at = m.band.bytes.size();
  m.band.bytes.resize(at + m.row_bytes);
  unsigned char* dst = m.band.bytes.data() + at;
  if (m.band_type == OIIO::TypeDesc::UINT8) {
    interleave<std::uint8_t>(row.data(), w, ch, dst,
                             [](float v) { return static_cast<std::uint8_t>(clamp01(v) * 255.0f + 0.5f); });
  } else if (m.band_type == OIIO::TypeDesc::UINT16) {
    interleave<std::uint16_t>(row.data(), w, ch, dst,
                              [](float v) { return static_cast<std::uint16_t>(clamp01(v) * 65535.0f + 0.5f); });
  } else if (m.integer_file) {
    interleave<float>(row.data(), w, ch, dst, clamp01);
  } else {
    interleave<float>(row.data(), w, ch, dst, [](float v) { return v; });
  }
  m.band.y1 = ++m.next_row;
  if (m.band.y1 - m.band.y0 == m.band_rows || m.next_row == m.height) m.send();
}

void ImageFileWriter::commit() {
  Impl& m = *impl_;
  if (m.committed) throw std::logic_error(fmt::format("{}: commit() called twice", m.name));
  if (m.next_row != m.height) throw m.fail(fmt::format("only {} of {} rows were written", m.next_row, m.height));
  m.queue.finish();  // the encoder writes what is queued, then stops
  if (m.encoder.joinable()) m.encoder.join();
  m.check();
  const bool closed = m.output->close();
  if (m.file) {
    m.file->close();
    if (m.file->failed()) throw m.fail("cannot write: " + m.file->problem());
  }
  if (!closed) throw m.fail("cannot write: " + io::one_line(m.output->geterror()));
  m.output.reset();
  m.file.reset();
  std::error_code ec;
  fs::rename(m.temp, m.path, ec);
  if (ec) throw m.fail("cannot move the finished file into place: " + ec.message());
  m.committed = true;
}

}  // namespace gdp
