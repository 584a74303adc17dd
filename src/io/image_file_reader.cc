// Streaming image input: bands of rows decoded by OpenImageIO, optionally ahead on a thread.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <exception>
#include <system_error>
#include <thread>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "io/oiio_util.h"
#include "schedule/bounded_queue.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// Rows [y0, y1) of all channels, interleaved and of the sample type as in the file (8- and
// 16-bit samples become floats only in read_row(): a quarter or half of the memory, one pass).
struct Band {
  int y0 = 0, y1 = 0;
  std::vector<unsigned char> bytes;
  std::string error;  // non-empty: decoding failed here
};

// One row of a band into a channel-major row of floats.
template <class T, class Convert>
void deinterleave(const unsigned char* band_row, int w, int ch, float* out, Convert convert) {
  const T* src = reinterpret_cast<const T*>(band_row);
  for (int c = 0; c < ch; ++c) {
    float* dst = out + static_cast<std::size_t>(c) * w;
    for (int x = 0; x < w; ++x) dst[x] = convert(src[static_cast<std::size_t>(x) * ch + c]);
  }
}

}  // namespace

struct ImageFileReader::Impl {
  fs::path path;
  std::string name;
  bool prefetch;
  std::unique_ptr<OIIO::ImageInput> input;
  int subimage = 0;
  OIIO::ImageSpec spec;
  ImageFileInfo info;
  int band_rows = 1;
  OIIO::TypeDesc stored = OIIO::TypeFloat;  // the band's sample type (see io::native_integer_type)
  std::size_t row_bytes = 0;
  Band band;  // the band read_row serves from
  int next_row = 0;
  std::string failed;  // non-empty: a band failed to decode; read_row() throws this
  std::unique_ptr<schedule::BoundedQueue<Band>> queue;
  std::thread decoder;

  InputError fail(std::string_view problem) const { return InputError(fmt::format("{}: {}", name, problem)); }

  void open() {
    // Check the file ourselves first: OpenImageIO's messages do not carry the system's reason.
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw fail("cannot open: Is a directory");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw fail("cannot open: " + std::generic_category().message(errno));
    ::close(fd);
    // Keep alpha as stored (no premultiplication): gdp treats every channel as plain data.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    input = OIIO::ImageInput::open(name, &config);
    if (!input) throw fail(fmt::format("not an image file OpenImageIO can read ({})", io::one_line(OIIO::geterror())));
    // FITS files often keep only a header in the primary HDU: use the first subimage with pixels.
    subimage = 0;
    while (input->spec().width <= 0 || input->spec().height <= 0) {
      if (!input->seek_subimage(subimage + 1, 0)) break;
      ++subimage;
    }
    spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw fail("image has zero size");
    if (spec.depth > 1) throw fail("volume images (depth > 1) are not supported");
    if (spec.nchannels > 4) throw fail(fmt::format("{} channels; gdp supports 1 to 4", spec.nchannels));
    info.sample_type = io::sample_type_of(spec.format);
    info.format_name = input->format_name();
    info.lossy = io::is_lossy_format(info.format_name);
    band_rows = io::band_rows(spec.width, spec.height, spec.nchannels, spec.tile_height > 0 ? spec.tile_height : 1);
    const OIIO::TypeDesc native = io::native_integer_type(spec);
    stored = native != OIIO::TypeDesc::UNKNOWN ? native : OIIO::TypeFloat;
    row_bytes = static_cast<std::size_t>(spec.width) * spec.nchannels * stored.size();
  }

  // Decodes rows [y0, y1). Tiled files are read by whole tile rows (read_scanlines() on a tiled
  // TIFF crashes OpenImageIO 2.4 with SIGFPE).
  Band decode(int y0) noexcept {
    Band b;
    b.y0 = y0;
    b.y1 = std::min(spec.height, y0 + band_rows);
    try {
      b.bytes.resize(static_cast<std::size_t>(b.y1 - y0) * row_bytes);
    } catch (const std::bad_alloc&) {
      b.error = "out of memory for a band of rows";
      return b;
    }
    const bool ok = spec.tile_width > 0
                        ? input->read_tiles(subimage, 0, spec.x, spec.x + spec.width, spec.y + y0, spec.y + b.y1,
                                            spec.z, spec.z + 1, 0, spec.nchannels, stored, b.bytes.data())
                        : input->read_scanlines(subimage, 0, spec.y + y0, spec.y + b.y1, spec.z, 0, spec.nchannels,
                                                stored, b.bytes.data());
    if (!ok) b.error = "cannot read pixels: " + io::one_line(input->geterror());
    return b;
  }

  void start() {
    next_row = 0;
    band = Band{};
    failed.clear();
    if (!prefetch) return;
    // One band queued, one being decoded, one being read: three at most.
    queue = std::make_unique<schedule::BoundedQueue<Band>>(1);
    decoder = std::thread([this] {
      for (int y0 = 0; y0 < spec.height; y0 += band_rows) {
        Band b = decode(y0);
        const bool failed = !b.error.empty();
        if (!queue->push(std::move(b)) || failed) return;
      }
    });
  }

  void stop() {
    if (queue) queue->close();
    if (decoder.joinable()) decoder.join();
    queue.reset();
  }

  void next_band() {
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

ImageFileReader::ImageFileReader(const fs::path& path, bool prefetch) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->name = path.string();
  impl_->prefetch = prefetch;
  impl_->open();
  impl_->start();
}

ImageFileReader::~ImageFileReader() { impl_->stop(); }

const ImageFileInfo& ImageFileReader::info() const { return impl_->info; }
int ImageFileReader::width() const { return impl_->spec.width; }
int ImageFileReader::height() const { return impl_->spec.height; }
int ImageFileReader::channels() const { return impl_->spec.nchannels; }

void ImageFileReader::read_row(int y, std::span<float> out) {
  Impl& m = *impl_;
  if (y != m.next_row)
    throw std::logic_error(fmt::format("{}: row {} read out of order (next is {})", m.name, y, m.next_row));
  if (y >= m.spec.height) throw std::logic_error(fmt::format("{}: row {} past the end", m.name, y));
  if (out.size() < static_cast<std::size_t>(m.spec.width) * m.spec.nchannels)
    throw std::logic_error(fmt::format("{}: row buffer of {} samples, {} needed", m.name, out.size(),
                                       m.spec.width * m.spec.nchannels));
  if (!m.failed.empty()) throw m.fail(m.failed);
  if (y >= m.band.y1) m.next_band();
  const int w = m.spec.width, ch = m.spec.nchannels;
  const unsigned char* src = m.band.bytes.data() + static_cast<std::size_t>(y - m.band.y0) * m.row_bytes;
  if (m.stored == OIIO::TypeDesc::UINT8) {
    deinterleave<std::uint8_t>(src, w, ch, out.data(),
                               [](std::uint8_t v) { return static_cast<float>(v) * (1.0f / 255.0f); });
  } else if (m.stored == OIIO::TypeDesc::UINT16) {
    deinterleave<std::uint16_t>(src, w, ch, out.data(),
                                [](std::uint16_t v) { return static_cast<float>(v) * (1.0f / 65535.0f); });
  } else {
    deinterleave<float>(src, w, ch, out.data(), [](float v) { return v; });
  }
  ++m.next_row;
}

void ImageFileReader::rewind() {
  Impl& m = *impl_;
  if (m.band.y0 == 0 && m.band.y1 == m.spec.height) {  // one band holds the whole image: keep it
    m.next_row = 0;
    return;
  }
  m.stop();
  m.input.reset();  // formats such as PNG and JPEG only decode forwards: open again
  m.open();
  m.start();
}

}  // namespace gdp
