// Decoding one fuzz input from an in-memory file (memfd) through gdp::ImageFileReader.
#include "decode_input.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "gdp/size_check.h"
#include "io/codec.h"
#include "io/tiff_pages.h"

namespace gdp::fuzz {
namespace {

constexpr long long kMaxPixels = 1 << 18;  // no image the fuzzer makes up may need more memory

// The file the decoders open: an in-memory file, written afresh for each input.
const std::string& input_path(const std::uint8_t* data, std::size_t size) {
  static const int fd = [] {
    // Formats gdp leaves to OpenImageIO's module fail at once (the fuzz build has none).
    setenv("GDP_OIIO_MODULE", "/nonexistent/libgdp_oiio.so", 1);
    set_size_check([](long long w, long long h, int) {
      if (w * h > kMaxPixels) throw std::length_error("beyond the fuzz targets' pixel limit");
    });
    const int f = memfd_create("gdp-fuzz", 0);
    if (f < 0) std::abort();
    return f;
  }();
  static const std::string path = "/proc/self/fd/" + std::to_string(fd);
  if (ftruncate(fd, 0) != 0 || pwrite(fd, data, size, 0) != static_cast<ssize_t>(size)) std::abort();
  return path;
}

// Every row of one page, then a window of its middle columns; gdp::Error is bad input reported.
void read_page(const std::string& path, int page) {
  try {
    ImageFileReader whole(path, false, ColumnRange{}, page);
    std::vector<float> row(static_cast<std::size_t>(whole.width()) * whole.channels());
    for (int y = 0; y < whole.height(); ++y) whole.read_row(y, row);
    const int w = whole.width();
    ImageFileReader window(path, false, ColumnRange{w / 3, w / 3 + (w + 1) / 2}, page);
    for (int y = 0; y < window.height(); ++y) window.read_row(y, row);
  } catch (const gdp::Error&) {
  }
}

}  // namespace

int decode_input(const std::uint8_t* data, std::size_t size, std::initializer_list<std::string_view> signatures,
                 bool pages) {
  const std::string_view head(reinterpret_cast<const char*>(data), size);
  bool known = false;
  for (std::string_view s : signatures) known = known || head.starts_with(s);
  if (!known) return -1;
  const std::string& path = input_path(data, size);
  read_page(path, 0);
  if (!pages) return 0;
  std::vector<io::TiffPage> list;
  try {
    list = io::tiff_pages(path);
  } catch (const io::CodecError&) {
    return 0;
  }
  for (int page = 1; page < static_cast<int>(list.size()) && page < 4; ++page) read_page(path, page);
  return 0;
}

}  // namespace gdp::fuzz
