// The column gather's samples in the output's stored type: 8- or 16-bit on the way to rank 0, floats that store alike there.
#pragma once

#include <cstddef>

namespace gdp::mpi {

// Bytes a sample takes on the way for a writer's RowWriter::stored_levels(): 1, 2, or a float's.
inline std::size_t sent_bytes(int levels) { return levels == 255 ? 1 : levels == 65535 ? 2 : sizeof(float); }

// n samples as the writer will store them (io::to_u8 / io::to_u16, its own rounding), or as they are.
void pack(const float* in, std::size_t n, int levels, unsigned char* out);

// Floats that the writer stores as the integers packed (q / L, within a rounding of it), or the floats.
void unpack(const unsigned char* in, std::size_t n, int levels, float* out);

}  // namespace gdp::mpi
