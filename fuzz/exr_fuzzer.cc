// libFuzzer target: OpenEXR files through gdp's decoding API.
#include "decode_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return gdp::fuzz::decode_input(data, size, {"\x76\x2f\x31\x01"});
}
