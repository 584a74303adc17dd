// Reading and writing image files (PNG/TIFF/JPEG by gdp's codecs, others through OpenImageIO's module), with atomic writes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gdp/image.h"

namespace gdp {

// Sample type of a file on disk.
enum class SampleType { UInt8, UInt16, Half, Float, Double };

// What a file held besides its pixels, so outputs can default to the input's format.
struct ImageFileInfo {
  SampleType sample_type = SampleType::Float;
  std::string format_name;  // OpenImageIO's name: "png", "jpeg", "tiff", "openexr", ...
  bool lossy = false;        // true for formats that do not keep exact values (JPEG, ...)
};

struct ReadResult {
  Image image;
  ImageFileInfo info;
};

// Reads a whole image. Throws InputError naming the file and the problem.
ReadResult read_image(const std::filesystem::path& path);

// Where a raster lies on the Earth (GeoTIFF): the model coordinates of the top-left pixel's
// corner, the pixel size (north up), and the GeoKeyDirectory with its parameters (the CRS).
struct GeoReference {
  double origin_x = 0, origin_y = 0, scale_x = 0, scale_y = 0;
  std::vector<std::uint16_t> keys;      // GeoKeyDirectoryTag (34735)
  std::vector<double> double_params;    // GeoDoubleParamsTag (34736)
  std::string ascii_params;             // GeoAsciiParamsTag (34737)
};

// Where an image lies in a larger frame (OpenEXR's data window in its display window): its
// top-left pixel at (x, y) in the frame's pixel coordinates (which may be negative), the frame
// [frame_x, frame_x + frame_width) x [frame_y, frame_y + frame_height).
struct FramePlacement {
  int x = 0, y = 0;
  int frame_x = 0, frame_y = 0, frame_width = 0, frame_height = 0;
};

struct WriteOptions {
  std::optional<SampleType> sample_type;  // default: Float for tiff/exr/hdr/fits, else UInt8
  int jpeg_quality = 95;                  // 1..100
  bool tiled = false;                     // tiled TIFF / OpenEXR (other formats: OutputError)
  std::string compression;                // TIFF: "none", "zip" (deflate; "zip:1".."zip:9"), "lzw", "packbits", "jpeg", "zstd",
                                          // "lzma", others -> zip; other formats: OpenImageIO "Compression"; empty: the format's default
  int tile_size = 256;                    // tile width and height with `tiled`: a positive multiple of 16
  std::string fits_header = {};           // FITS: header cards (80 characters each) to add, e.g. a WCS
  std::optional<GeoReference> geo = std::nullopt;  // TIFF: written as GeoTIFF tags (other formats: ignored)
  std::optional<FramePlacement> frame = std::nullopt;  // OpenEXR: data and display windows (others: ignored)
};

// UsageError when `compression` (WriteOptions::compression, --compression) is not one the codec
// writing `path` knows (TIFF, OpenEXR: their names; PNG: none; JPEG: jpeg:QUALITY; formats of
// OpenImageIO's module: left to it). Front ends (the CLI, Python) check before a run; ImageFileWriter
// itself takes an unknown name as the format's default.
void check_compression(const std::filesystem::path& path, const std::string& compression);

// Writes an image to a temporary file in the output's directory and renames it into place,
// so no partial file is ever visible under the final name. Integer outputs are clamped to
// [0, 1]; float outputs are written as they are. Throws OutputError (nothing left behind).
void write_image(const std::filesystem::path& path, const Image& image, const WriteOptions& options);

// The sample type named by the CLI's --depth: "8", "16", "half", "float"; empty: none (nullopt).
// Anything else throws UsageError.
std::optional<SampleType> parse_depth(std::string_view depth);

// True when the file name's extension names a lossy format (JPEG, WebP, ...).
bool is_lossy_extension(const std::filesystem::path& path);

}  // namespace gdp
