// What gdp's OpenEXR decoder and encoder share: OpenImageIO's channel order, channel names, OpenEXR's threads.
#pragma once

#include <OpenEXR/ImfHeader.h>

#include <string>
#include <vector>

namespace gdp::io {

// The first part's header of an OpenEXR file, read on its own (before OpenEXR's file reader reads
// the table of blocks), and the file's version field. Throws what OpenEXR throws.
struct ExrHeader {
  Imf::Header header;
  int version = 0;
};
ExrHeader read_exr_header(const std::string& path);

// The order in which OpenImageIO 2.4 presents an OpenEXR file's channels (and gdp did while it
// read OpenEXR through it): by layer ("diffuse." of "diffuse.R"; no layer first), then R, G, B,
// Y, A, Z and their aliases (X, Y, Z in a layer that has X and Y or Z), then by name. Returns
// indices into `names`.
std::vector<int> exr_channel_order(const std::vector<std::string>& names);

// Channel names gdp writes for `channels` channels: Y, YA, RGB, RGBA; beyond four R, G, B, A,
// channel4, channel5, ... (OpenImageIO's names).
std::vector<std::string> exr_channel_names(int channels);

// The thread count to open a file with: OpenEXR keeps two block buffers per thread. Tiled files
// get two threads, which (de)compress the tiles of a tile row in parallel (the process-wide pool
// is set to two threads on first use); scanline files none: a band of rows is smaller than a
// block row, so OpenEXR (de)compresses one block at a time anyway, and one buffer is enough
// (8192-wide RGB DWAB blocks are 256 rows: 13 MB each).
int exr_threads(bool tiled);

}  // namespace gdp::io
