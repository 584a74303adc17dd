// libFuzzer target: PNG files through gdp's decoding API.
#include "decode_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return gdp::fuzz::decode_input(data, size, {"\x89PNG"});
}
