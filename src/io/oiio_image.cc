// Image file reading and atomic writing (temporary file + rename) for gdp::Image, over OpenImageIO.
#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstddef>
#include <random>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/cleanup.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// Samples moved between OpenImageIO's interleaved layout and gdp's planar one per call (4 MiB):
// small enough to stay in cache and to never need a second whole-image buffer, large enough that
// OpenImageIO still decodes in big blocks. Measured on an 8000x4500 RGB image: as fast as a single
// read_image() call, while a whole-image interleaved buffer plus deinterleave was 40-60% slower.
constexpr std::size_t kBandSamples = std::size_t{1} << 20;

// Above this many bytes of pixel data a TIFF must be BigTIFF (classic TIFF offsets are 32-bit).
constexpr double kBigTiffBytes = 3.5 * 1024.0 * 1024.0 * 1024.0;

// OpenImageIO messages may span several lines; join the non-empty ones with "; ".
std::string one_line(std::string_view message) {
  std::string result;
  while (!message.empty()) {
    const std::size_t end = std::min(message.find('\n'), message.size());
    std::string_view line = message.substr(0, end);
    message.remove_prefix(std::min(end + 1, message.size()));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front()))) line.remove_prefix(1);
    if (line.empty()) continue;
    if (!result.empty()) result += "; ";
    result += line;
  }
  return result.empty() ? "unknown error" : result;
}

SampleType sample_type_of(OIIO::TypeDesc type) {
  switch (type.basetype) {
    case OIIO::TypeDesc::UINT8: return SampleType::UInt8;
    case OIIO::TypeDesc::UINT16: return SampleType::UInt16;
    case OIIO::TypeDesc::HALF: return SampleType::Half;
    case OIIO::TypeDesc::FLOAT: return SampleType::Float;
    case OIIO::TypeDesc::DOUBLE: return SampleType::Double;
    default: return type.is_floating_point() ? SampleType::Float : SampleType::UInt16;
  }
}

OIIO::TypeDesc type_desc_of(SampleType type) {
  switch (type) {
    case SampleType::UInt8: return OIIO::TypeDesc::UINT8;
    case SampleType::UInt16: return OIIO::TypeDesc::UINT16;
    case SampleType::Half: return OIIO::TypeDesc::HALF;
    case SampleType::Float: return OIIO::TypeDesc::FLOAT;
    case SampleType::Double: return OIIO::TypeDesc::DOUBLE;
  }
  return OIIO::TypeDesc::FLOAT;
}

// Sample type to ask the writer for. Writers that store floating point (TIFF, OpenEXR, Radiance
// HDR, FITS) default to Float, all others to UInt8. A floating-point type asked of a writer that
// cannot store it becomes UInt16 for PNG (OpenImageIO itself would pick UInt8) and UInt8 otherwise.
// OpenImageIO's open() may still adjust the type to what the plugin stores (seen in 2.4: TIFF
// Half -> Float, OpenEXR Double -> Float and integers -> Half, HDR anything -> Float, JPEG/WebP/
// BMP/PPM UInt16 -> UInt8, FITS UInt16 -> Int16); the samples written follow that adjusted spec.
SampleType choose_sample_type(const std::string& format_name, const std::optional<SampleType>& requested) {
  const bool holds_float =
      format_name == "tiff" || format_name == "openexr" || format_name == "hdr" || format_name == "fits";
  if (!requested) return holds_float ? SampleType::Float : SampleType::UInt8;
  const bool float_requested = *requested == SampleType::Half || *requested == SampleType::Float ||
                               *requested == SampleType::Double;
  if (float_requested && !holds_float) return format_name == "png" ? SampleType::UInt16 : SampleType::UInt8;
  return *requested;
}

// Rows [y0, y1) of all channels, interleaved, into band. Tiled files are read by whole tile rows
// (read_scanlines() on a tiled TIFF crashes OpenImageIO 2.4 with SIGFPE).
bool read_band(OIIO::ImageInput& input, int subimage, const OIIO::ImageSpec& spec, int y0, int y1, float* band) {
  if (spec.tile_width > 0) {
    return input.read_tiles(subimage, 0, spec.x, spec.x + spec.width, spec.y + y0, spec.y + y1, spec.z, spec.z + 1, 0,
                            spec.nchannels, OIIO::TypeFloat, band);
  }
  return input.read_scanlines(subimage, 0, spec.y + y0, spec.y + y1, spec.z, 0, spec.nchannels, OIIO::TypeFloat, band);
}

// Removes the temporary file on destruction unless keep() was called.
class TempFile {
 public:
  explicit TempFile(fs::path path) : path_(std::move(path)), handle_(cleanup::track(path_.string())) {}
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    std::error_code ignored;
    if (!path_.empty()) fs::remove(path_, ignored);
    cleanup::untrack(handle_);
  }
  const fs::path& path() const { return path_; }
  void keep() { path_.clear(); }

 private:
  fs::path path_;
  int handle_;  // also deleted if the process is interrupted (gdp/cleanup.h)
};

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

}  // namespace

ReadResult read_image(const fs::path& path) {
  const std::string name = path.string();
  auto fail = [&name](std::string_view problem) { return InputError(fmt::format("{}: {}", name, problem)); };

  // Check the file ourselves first: OpenImageIO's messages do not carry the system's reason.
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw fail("cannot open: Is a directory");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw fail("cannot open: " + std::generic_category().message(errno));
  ::close(fd);

  // Keep alpha as stored (no premultiplication): gdp treats every channel as plain data.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(name, &config);
  if (!input) throw fail(fmt::format("not an image file OpenImageIO can read ({})", one_line(OIIO::geterror())));
  // FITS files often keep only a header in the primary HDU: use the first subimage with pixels.
  int subimage = 0;
  while (input->spec().width <= 0 || input->spec().height <= 0) {
    if (!input->seek_subimage(subimage + 1, 0)) break;
    ++subimage;
  }
  const OIIO::ImageSpec spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw fail("image has zero size");
  if (spec.depth > 1) throw fail("volume images (depth > 1) are not supported");
  if (spec.nchannels > 4) throw fail(fmt::format("{} channels; gdp supports 1 to 4", spec.nchannels));

  ReadResult result{Image(spec.width, spec.height, spec.nchannels), {}};
  result.info.sample_type = sample_type_of(spec.format);
  result.info.format_name = input->format_name();
  const std::string& format = result.info.format_name;
  result.info.lossy = format == "jpeg" || format == "webp" || format == "heif" || format == "jpeg2000";

  Image& image = result.image;
  const int channels = image.channels;
  const std::size_t row_samples = static_cast<std::size_t>(image.width) * channels;
  int band_rows = static_cast<int>(std::clamp<std::size_t>(kBandSamples / row_samples, 1, image.height));
  if (spec.tile_height > 0) band_rows = std::max(1, band_rows / spec.tile_height) * spec.tile_height;
  std::vector<float> band(row_samples * band_rows);
  for (int y0 = 0; y0 < image.height; y0 += band_rows) {
    const int y1 = std::min(image.height, y0 + band_rows);
    if (!read_band(*input, subimage, spec, y0, y1, band.data())) {
      throw fail("cannot read pixels: " + one_line(input->geterror()));
    }
    const std::size_t count = static_cast<std::size_t>(y1 - y0) * image.width;
    for (int c = 0; c < channels; ++c) {
      float* target = &image.at(c, 0, y0);
      const float* source = band.data() + c;
      for (std::size_t i = 0; i < count; ++i) target[i] = source[i * channels];
    }
  }
  return result;
}

void write_image(const fs::path& path, const Image& image, const WriteOptions& options) {
  const std::string name = path.string();
  auto fail = [&name](std::string_view problem) { return OutputError(fmt::format("{}: {}", name, problem)); };

  if (image.width <= 0 || image.height <= 0 || image.channels <= 0) throw fail("cannot write an empty image");
  if (image.data.size() != image.plane_size() * static_cast<std::size_t>(image.channels)) {
    throw fail("image data size does not match its dimensions");
  }
  // The plugin is chosen by the final name; the temporary name keeps the same extension.
  auto output = OIIO::ImageOutput::create(name);
  if (!output) {
    OIIO::geterror();  // clear OpenImageIO's pending message; ours names the cause
    if (!path.has_extension()) throw fail("cannot write: no file extension to choose an image format by");
    throw fail(fmt::format("cannot write: no image format for extension '{}'", path.extension().string()));
  }
  const std::string format = output->format_name();
  OIIO::ImageSpec spec(image.width, image.height, image.channels,
                       type_desc_of(choose_sample_type(format, options.sample_type)));
  spec.attribute("oiio:UnassociatedAlpha", 1);  // write alpha as given, never un-premultiply it
  // OpenImageIO 2.4 takes the quality as "Compression" = "CODEC:Q" (jpeg and webp also accept
  // "CompressionQuality"; heif does not); without it JPEG is written at quality 98.
  if (format == "jpeg" || format == "webp" || format == "heif") {
    const std::string codec = format == "heif" ? "heic" : format;
    spec.attribute("Compression", fmt::format("{}:{}", codec, std::clamp(options.jpeg_quality, 1, 100)));
  }
  const double bytes = static_cast<double>(image.data.size()) * spec.format.size();
  if (format == "tiff" && bytes > kBigTiffBytes) spec.attribute("tiff:bigtiff", 1);

  std::string why;
  const fs::path temp_path = create_temp_file(path, why);
  if (temp_path.empty()) throw fail("cannot write: " + why);
  TempFile temp(temp_path);
  // On failure close the writer before the temporary file is removed, so nothing recreates it.
  auto write_failed = [&]() {
    const std::string problem = one_line(output->geterror());
    output.reset();
    return fail("cannot write: " + problem);
  };
  if (!output->open(temp.path().string(), spec)) throw write_failed();

  // Interleave a band of rows at a time. For integer files clamp to [0, 1] here (NaN -> 0), so the
  // result never depends on how the writer converts out-of-range values.
  const bool integer_file = !output->spec().format.is_floating_point();
  const int channels = image.channels;
  const std::size_t row_samples = static_cast<std::size_t>(image.width) * channels;
  const int band_rows = static_cast<int>(std::clamp<std::size_t>(kBandSamples / row_samples, 1, image.height));
  std::vector<float> band(row_samples * band_rows);
  for (int y0 = 0; y0 < image.height; y0 += band_rows) {
    const int y1 = std::min(image.height, y0 + band_rows);
    const std::size_t count = static_cast<std::size_t>(y1 - y0) * image.width;
    for (int c = 0; c < channels; ++c) {
      const float* source = &image.data[(static_cast<std::size_t>(c) * image.height + y0) * image.width];
      float* target = band.data() + c;
      for (std::size_t i = 0; i < count; ++i) {
        const float v = source[i];
        target[i * channels] = integer_file ? (v > 0.0f ? std::min(v, 1.0f) : 0.0f) : v;
      }
    }
    if (!output->write_scanlines(y0, y1, 0, OIIO::TypeFloat, band.data())) throw write_failed();
  }
  if (!output->close()) throw write_failed();
  output.reset();

  std::error_code ec;
  fs::rename(temp.path(), path, ec);
  if (ec) throw fail("cannot move the finished file into place: " + ec.message());
  temp.keep();
}

bool is_lossy_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".jpg" || ext == ".jpeg" || ext == ".jpe" || ext == ".jfif" || ext == ".webp" || ext == ".heic" ||
         ext == ".heif" || ext == ".jp2" || ext == ".j2k";
}

}  // namespace gdp
