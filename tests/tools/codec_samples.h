// Small valid files of every format gdp decodes itself: seeds for the fuzz targets (fuzz/) and the mutation test.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gdp::test {

// The codecs gdp decodes itself, as the fuzz targets and the mutation test name them.
const std::vector<std::string>& sample_codecs();

// Writes a few small files of `codec` ("png", "tiff", "jpeg", "exr", "fits") into `dir`, one per
// variant the decoder handles differently (sample types, channel counts, compressions, tiles,
// several pages, GeoTIFF tags), and returns their paths. Throws std::exception on failure.
std::vector<std::filesystem::path> write_codec_samples(const std::filesystem::path& dir, const std::string& codec);

}  // namespace gdp::test
