// The column gather's samples in the output's stored type: 8- or 16-bit on the way to rank 0, floats that store alike there.
#pragma once

#include <cstdint>
#include <cstring>

#include "io/codec_util.h"

namespace gdp::mpi {

// Bytes a sample takes on the way for a writer's RowWriter::stored_levels(): 1, 2, or a float's.
inline std::size_t sent_bytes(int levels) { return levels == 255 ? 1 : levels == 65535 ? 2 : sizeof(float); }

// n samples as the writer will store them (io::to_u8 / io::to_u16, its own rounding), or as they are.
inline void pack(const float* in, std::size_t n, int levels, unsigned char* out) {
  if (levels == 255) {
    for (std::size_t i = 0; i < n; ++i) out[i] = io::to_u8(in[i]);
  } else if (levels == 65535) {
    auto* to = reinterpret_cast<std::uint16_t*>(out);
    for (std::size_t i = 0; i < n; ++i) to[i] = io::to_u16(in[i]);
  } else {
    std::memcpy(out, in, n * sizeof(float));
  }
}

// Floats that the writer stores as the integers packed (q / L, within a rounding of it), or the floats.
inline void unpack(const unsigned char* in, std::size_t n, int levels, float* out) {
  if (levels == 255) {
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(in[i]) * (1.0f / 255.0f);
  } else if (levels == 65535) {
    const auto* from = reinterpret_cast<const std::uint16_t*>(in);
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(from[i]) * (1.0f / 65535.0f);
  } else {
    std::memcpy(out, in, n * sizeof(float));
  }
}

}  // namespace gdp::mpi
