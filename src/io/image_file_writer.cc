// Streaming image output: bands of rows encoded by OpenImageIO on a thread, into a temporary file renamed at the end.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <random>
#include <system_error>
#include <thread>

#include <fmt/format.h>

#include "gdp/cleanup.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "io/oiio_util.h"
#include "schedule/bounded_queue.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// Creates an empty ".NAME.tmp-PID-RANDOM.EXT" exclusively next to the output; on failure returns
// the empty path and sets `why`.
fs::path create_temp_file(const fs::path& path, std::string& why) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status)) why = fmt::format("no such directory '{}'", dir.string());
  else if (!fs::is_directory(status)) why = fmt::format("'{}' is not a directory", dir.string());
  if (!why.empty()) return {};
  std::random_device random;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const fs::path temp = dir / fmt::format(".{}.tmp-{}-{:08x}{}", path.stem().string(), static_cast<long>(::getpid()),
                                            static_cast<unsigned>(random()), path.extension().string());
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return temp;
    }
    if (errno != EEXIST) break;
  }
  why = errno == EEXIST ? "no unused temporary file name" : std::generic_category().message(errno);
  return {};
}

struct Band {
  int y0 = 0, y1 = 0;
  std::vector<float> samples;  // interleaved
};

}  // namespace

struct ImageFileWriter::Impl {
  fs::path path, temp;
  std::string name;
  int cleanup_handle = -1;
  std::unique_ptr<OIIO::ImageOutput> output;
  int width = 0, height = 0, channels = 0, band_rows = 1, next_row = 0;
  OIIO::ImageSpec spec;
  bool integer_file = false, tiled = false, committed = false, opened = false;
  Band band;
  schedule::BoundedQueue<Band> queue{2};
  std::thread encoder;
  std::string error;  // the encoder's, read after join or under the queue's ordering
  std::mutex error_mutex;

  OutputError fail(std::string_view problem) const { return OutputError(fmt::format("{}: {}", name, problem)); }
  void open();

  void encode(const Band& b) {
    const bool ok = tiled ? output->write_tiles(0, width, b.y0, b.y1, 0, 1, OIIO::TypeFloat, b.samples.data())
                          : output->write_scanlines(b.y0, b.y1, 0, OIIO::TypeFloat, b.samples.data());
    if (!ok) throw fail("cannot write: " + io::one_line(output->geterror()));
  }

  void run_encoder() {
    while (auto b = queue.pop()) {
      try {
        encode(*b);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(error_mutex);
        error = e.what();
        queue.close();
        return;
      }
    }
  }

  void check() {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (!error.empty()) throw OutputError(error);
  }

  void send() {
    if (band.y1 == band.y0) return;
    const int y1 = band.y1;
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
    if (!committed && !temp.empty()) {
      std::error_code ignored;
      fs::remove(temp, ignored);
    }
    cleanup::untrack(cleanup_handle);
  }
};

ImageFileWriter::ImageFileWriter(const fs::path& path, int width, int height, int channels, const WriteOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.name = path.string();
  m.width = width;
  m.height = height;
  m.channels = channels;
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
    spec.tile_width = spec.tile_height = std::max(16, options.tile_size);
    m.tiled = true;
  }
  std::string why;
  m.temp = create_temp_file(path, why);
  if (m.temp.empty()) throw m.fail("cannot write: " + why);
  m.cleanup_handle = cleanup::track(m.temp.string());  // also deleted if the process is interrupted
  m.spec = spec;
  m.band_rows = io::band_rows(width, height, channels, m.tiled ? spec.tile_height : 1);
}

// The file is opened with the first row, so that a run failing before it (bad input, say) does
// not make the codec complain about an empty image.
void ImageFileWriter::Impl::open() {
  if (!output->open(temp.string(), spec)) throw fail("cannot write: " + io::one_line(output->geterror()));
  // For integer files values are clamped to [0, 1] here (NaN -> 0), so the result never depends
  // on how the writer converts out-of-range values.
  integer_file = !output->spec().format.is_floating_point();
  encoder = std::thread([this] { run_encoder(); });
  opened = true;
}

ImageFileWriter::~ImageFileWriter() { impl_->abandon(); }

void ImageFileWriter::write_row(int y, std::span<const float> row) {
  Impl& m = *impl_;
  if (y != m.next_row || y >= m.height) throw std::logic_error(fmt::format("{}: row {} written out of order", m.name, y));
  if (!m.opened) m.open();
  const int w = m.width, ch = m.channels;
  const std::size_t at = m.band.samples.size();
  m.band.samples.resize(at + static_cast<std::size_t>(w) * ch);
  float* dst = m.band.samples.data() + at;
  for (int c = 0; c < ch; ++c) {
    const float* src = row.data() + static_cast<std::size_t>(c) * w;
    for (int x = 0; x < w; ++x) {
      const float v = src[x];
      dst[static_cast<std::size_t>(x) * ch + c] = m.integer_file ? (v > 0.0f ? std::min(v, 1.0f) : 0.0f) : v;
    }
  }
  m.band.y1 = ++m.next_row;
  if (m.band.y1 - m.band.y0 == m.band_rows || m.next_row == m.height) m.send();
}

void ImageFileWriter::commit() {
  Impl& m = *impl_;
  if (m.next_row != m.height) throw m.fail(fmt::format("only {} of {} rows were written", m.next_row, m.height));
  m.queue.finish();  // the encoder writes what is queued, then stops
  m.encoder.join();
  m.check();
  if (!m.output->close()) throw m.fail("cannot write: " + io::one_line(m.output->geterror()));
  m.output.reset();
  std::error_code ec;
  fs::rename(m.temp, m.path, ec);
  if (ec) throw m.fail("cannot move the finished file into place: " + ec.message());
  m.committed = true;
}

}  // namespace gdp
