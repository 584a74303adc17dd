// Reading an OpenEXR file's data and display windows from its header.
#include "io/exr_windows.h"

#include <cstdint>

#include <fmt/format.h>

#include "io/codec_util.h"
#include "io/codecs.h"
#include "io/exr_util.h"

namespace gdp::io {

std::optional<ExrWindows> exr_windows(const std::string& path) {
  if (!is_exr_file(path)) return std::nullopt;
  Imf::Header header;
  try {
    header = read_exr_header(path).header;
  } catch (const std::exception& e) {
    throw CodecError(fmt::format("not an OpenEXR file OpenEXR can read: {}", one_line(e.what())));
  }
  const auto size = [](int min, int max) {
    const std::int64_t n = std::int64_t{max} - min + 1;
    if (n < 1 || n > INT32_MAX) throw CodecError(fmt::format("a window from {} to {} is empty or too large", min, max));
    return static_cast<int>(n);
  };
  const Imath::Box2i data = header.dataWindow(), display = header.displayWindow();
  return ExrWindows{data.min.x,    data.min.y,    size(data.min.x, data.max.x),       size(data.min.y, data.max.y),
                    display.min.x, display.min.y, size(display.min.x, display.max.x), size(display.min.y, display.max.y)};
}

}  // namespace gdp::io
