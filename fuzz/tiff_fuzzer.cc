// libFuzzer target: TIFF (classic and BigTIFF, either byte order; its pages and GeoTIFF tags too) files through gdp's decoding API.
#include "decode_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return gdp::fuzz::decode_input(data, size, {"II", "MM"}, true);
}
