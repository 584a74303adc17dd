// Horizontal and floating-point differencing of TIFF rows, for strips gdp compresses itself.
#include "io/tiff_predictor.h"

#include <cstdint>
#include <cstring>

namespace gdp::io {

void horizontal_difference(unsigned char* row, int width, int channels, std::size_t bytes) {
  const std::size_t n = static_cast<std::size_t>(width) * channels;
  if (bytes == 1) {
    for (std::size_t i = n; i-- > static_cast<std::size_t>(channels);)
      row[i] = static_cast<unsigned char>(row[i] - row[i - channels]);
    return;
  }
  for (std::size_t i = n; i-- > static_cast<std::size_t>(channels);) {
    std::uint16_t a, b;
    std::memcpy(&a, row + i * 2, 2);
    std::memcpy(&b, row + (i - channels) * 2, 2);
    a = static_cast<std::uint16_t>(a - b);
    std::memcpy(row + i * 2, &a, 2);
  }
}

void float_difference(const unsigned char* row, unsigned char* out, int width, int channels, std::size_t bytes) {
  const std::size_t n = static_cast<std::size_t>(width) * channels;  // samples in the row
  // Byte b of a little-endian sample has significance b: it goes to plane bytes - 1 - b.
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t b = 0; b < bytes; ++b) out[(bytes - 1 - b) * n + i] = row[i * bytes + b];
  for (std::size_t i = n * bytes; i-- > static_cast<std::size_t>(channels);)
    out[i] = static_cast<unsigned char>(out[i] - out[i - channels]);
}

}  // namespace gdp::io
