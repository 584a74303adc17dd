// The column gather's 8- and 16-bit samples: packed as the file writer rounds, unpacked to floats it stores alike.
#include "mpi/stored_samples.h"

#include <cstdint>
#include <cstring>

#include "io/codec_util.h"
#include "util/clones.h"

namespace gdp::mpi {
namespace {

// Compiled for x86-64-v3 and the baseline (this file is compiled with -ffp-contract=off: both
// round as io::to_u8 / to_u16 do in the writer, src/io/image_file_writer.cc).
template <class T>
GDP_CLONES void pack_as(const float* in, std::size_t n, T* out) {
  for (std::size_t i = 0; i < n; ++i) out[i] = sizeof(T) == 1 ? io::to_u8(in[i]) : io::to_u16(in[i]);
}

template <class T>
GDP_CLONES void unpack_as(const T* in, std::size_t n, float levels, float* out) {
  const float step = 1.0f / levels;
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(in[i]) * step;
}

}  // namespace

void pack(const float* in, std::size_t n, int levels, unsigned char* out) {
  if (levels == 255) pack_as(in, n, out);
  else if (levels == 65535) pack_as(in, n, reinterpret_cast<std::uint16_t*>(out));
  else std::memcpy(out, in, n * sizeof(float));
}

void unpack(const unsigned char* in, std::size_t n, int levels, float* out) {
  if (levels == 255) unpack_as(in, n, 255.0f, out);
  else if (levels == 65535) unpack_as(reinterpret_cast<const std::uint16_t*>(in), n, 65535.0f, out);
  else std::memcpy(out, in, n * sizeof(float));
}

}  // namespace gdp::mpi
