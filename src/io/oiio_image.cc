// Image file reading and atomic writing (temporary file + rename) for gdp::Image, over OpenImageIO.
#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <random>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// Floats handed to OpenImageIO per write_scanlines call (64 MiB), so writing never copies the
// whole image into an interleaved buffer at once.
constexpr std::size_t kWriteChunkFloats = std::size_t{1} << 24;

// Above this many bytes of pixel data a TIFF must be BigTIFF (classic TIFF offsets are 32-bit).
constexpr double kBigTiffBytes = 3.5 * 1024.0 * 1024.0 * 1024.0;

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return s;
}

// OpenImageIO messages may span several lines; join them into one and drop empty ones.
std::string one_line(std::string_view message) {
  std::string result;
  std::size_t start = 0;
  while (start <= message.size()) {
    std::size_t end = message.find('\n', start);
    if (end == std::string_view::npos) end = message.size();
    std::string_view line = message.substr(start, end - start);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front()))) line.remove_prefix(1);
    if (!line.empty()) {
      if (!result.empty()) result += "; ";
      result += line;
    }
    start = end + 1;
  }
  return result;
}

std::string errno_text(int error) { return std::generic_category().message(error); }

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

bool is_float_type(SampleType type) {
  return type == SampleType::Half || type == SampleType::Float || type == SampleType::Double;
}

bool is_lossy_format(const std::string& format_name) {
  return format_name == "jpeg" || format_name == "webp" || format_name == "heif" || format_name == "jpeg2000";
}

// Sample type to ask the writer for. Writers that store floating point (TIFF, OpenEXR, Radiance
// HDR, FITS) default to Float, all others to UInt8. A floating-point type asked of a writer that
// cannot store it becomes UInt16 for PNG (OpenImageIO itself would pick UInt8) and UInt8 otherwise.
// OpenImageIO's open() may still adjust the type to what the plugin stores (checked for 2.4: TIFF
// Half -> Float, OpenEXR Double -> Float and integers -> Half, HDR anything -> Float, JPEG/WebP/BMP/
// PNM-via-.ppm UInt16 -> UInt8); the samples written follow that adjusted spec.
SampleType choose_sample_type(const std::string& format_name, const std::optional<SampleType>& requested) {
  const bool holds_float =
      format_name == "tiff" || format_name == "openexr" || format_name == "hdr" || format_name == "fits";
  if (!requested) return holds_float ? SampleType::Float : SampleType::UInt8;
  if (is_float_type(*requested) && !holds_float) return format_name == "png" ? SampleType::UInt16 : SampleType::UInt8;
  return *requested;
}

// A freshly created, empty temporary file next to the output; removed on destruction unless kept.
class TempFile {
 public:
  explicit TempFile(fs::path path) : path_(std::move(path)) {}
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (!path_.empty()) {
      std::error_code ignored;
      fs::remove(path_, ignored);
    }
  }
  const fs::path& path() const { return path_; }
  void keep() { path_.clear(); }

 private:
  fs::path path_;
};

// Creates ".NAME.tmp-PID-RANDOM.EXT" exclusively in the output's directory. Returns the error text
// (empty on success) so the caller can name the output file in its message.
std::string create_temp_file(const fs::path& path, fs::path& temp) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status)) return fmt::format("no such directory '{}'", dir.string());
  if (!fs::is_directory(status)) return fmt::format("'{}' is not a directory", dir.string());
  std::random_device device;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const std::string name = fmt::format(".{}.tmp-{}-{:08x}{}", path.stem().string(), static_cast<long>(::getpid()),
                                         static_cast<unsigned>(device()), path.extension().string());
    temp = dir / name;
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return {};
    }
    if (errno != EEXIST) {
      temp.clear();
      return errno_text(errno);
    }
  }
  temp.clear();
  return "cannot find an unused temporary file name";
}

}  // namespace

ReadResult read_image(const fs::path& path) {
  const std::string name = path.string();
  auto fail = [&name](std::string_view problem) { return InputError(fmt::format("{}: {}", name, problem)); };

  // Check the file ourselves first: OpenImageIO's messages do not carry the system's reason.
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw fail("cannot open: Is a directory");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw fail("cannot open: " + errno_text(errno));
  ::close(fd);

  // Keep alpha as stored (no premultiplication): gdp treats every channel as plain data.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(name, &config);
  if (!input) {
    const std::string why = one_line(OIIO::geterror());
    throw fail("not an image file OpenImageIO can read" + (why.empty() ? std::string() : " (" + why + ")"));
  }
  const OIIO::ImageSpec spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw fail("image has zero size");
  if (spec.depth > 1) throw fail("volume images (depth > 1) are not supported");
  if (spec.nchannels > 4) throw fail(fmt::format("{} channels; gdp supports 1 to 4", spec.nchannels));

  ReadResult result;
  result.info.sample_type = sample_type_of(spec.format);
  result.info.format_name = input->format_name();
  result.info.lossy = is_lossy_format(result.info.format_name);

  // One read_image call (OpenImageIO reads and converts in large blocks), then deinterleave.
  const int channels = spec.nchannels;
  result.image = Image(spec.width, spec.height, channels);
  Image& image = result.image;
  std::vector<float> interleaved;
  float* target = image.data.data();
  if (channels > 1) {
    interleaved.resize(image.data.size());
    target = interleaved.data();
  }
  if (!input->read_image(0, 0, 0, channels, OIIO::TypeFloat, target)) {
    throw fail("cannot read pixels: " + one_line(input->geterror()));
  }
  input->close();
  if (channels > 1) {
    const std::size_t pixels = image.plane_size();
    for (int c = 0; c < channels; ++c) {
      float* plane = image.plane(c).data();
      const float* source = interleaved.data() + c;
      for (std::size_t i = 0; i < pixels; ++i) plane[i] = source[i * channels];
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
    throw fail(fmt::format("cannot write: no image format for extension '{}'", path.extension().string()));
  }
  const std::string format_name = output->format_name();
  const SampleType type = choose_sample_type(format_name, options.sample_type);
  OIIO::ImageSpec spec(image.width, image.height, image.channels, type_desc_of(type));
  spec.attribute("oiio:UnassociatedAlpha", 1);  // write alpha as given, never un-premultiply it
  // OpenImageIO 2.4 takes the quality as "Compression" = "CODEC:Q" (jpeg and webp also accept
  // "CompressionQuality"; heif does not); without it JPEG is written at quality 98.
  if (format_name == "jpeg" || format_name == "webp" || format_name == "heif") {
    const std::string codec = format_name == "heif" ? "heic" : format_name;
    spec.attribute("Compression", fmt::format("{}:{}", codec, std::clamp(options.jpeg_quality, 1, 100)));
  }
  const double bytes = static_cast<double>(image.data.size()) * spec.format.size();
  if (format_name == "tiff" && bytes > kBigTiffBytes) spec.attribute("tiff:bigtiff", 1);

  fs::path temp_path;
  if (std::string why = create_temp_file(path, temp_path); !why.empty()) throw fail("cannot write: " + why);
  TempFile temp(temp_path);
  // On failure close the writer before the temporary file is removed, so nothing recreates it.
  auto write_failed = [&]() {
    std::string why = one_line(output->geterror());
    output.reset();
    return fail("cannot write: " + why);
  };
  if (!output->open(temp.path().string(), spec)) throw write_failed();

  // Interleave a block of rows at a time. For integer files clamp to [0, 1] here (NaN -> 0), so the
  // result never depends on how the conversion treats out-of-range values.
  const bool integer_file = !output->spec().format.is_floating_point();
  const int channels = image.channels;
  const std::size_t row_floats = static_cast<std::size_t>(image.width) * channels;
  const int block_rows = static_cast<int>(std::clamp<std::size_t>(kWriteChunkFloats / row_floats, 1, image.height));
  std::vector<float> block(row_floats * block_rows);
  for (int y0 = 0; y0 < image.height; y0 += block_rows) {
    const int y1 = std::min(image.height, y0 + block_rows);
    for (int y = y0; y < y1; ++y) {
      float* row = block.data() + (y - y0) * row_floats;
      for (int c = 0; c < channels; ++c) {
        std::span<const float> source = image.row(c, y);
        for (int x = 0; x < image.width; ++x) {
          const float v = source[x];
          row[static_cast<std::size_t>(x) * channels + c] = integer_file ? (v > 0.0f ? std::min(v, 1.0f) : 0.0f) : v;
        }
      }
    }
    if (!output->write_scanlines(y0, y1, 0, OIIO::TypeFloat, block.data())) {
      throw write_failed();
    }
  }
  if (!output->close()) throw write_failed();
  output.reset();

  std::error_code ec;
  fs::rename(temp.path(), path, ec);
  if (ec) throw fail("cannot move the finished file into place: " + ec.message());
  temp.keep();
}

bool is_lossy_extension(const fs::path& path) {
  const std::string ext = lowercase(path.extension().string());
  return ext == ".jpg" || ext == ".jpeg" || ext == ".jpe" || ext == ".jfif" || ext == ".webp" || ext == ".heic" ||
         ext == ".heif" || ext == ".jp2" || ext == ".j2k";
}

}  // namespace gdp
