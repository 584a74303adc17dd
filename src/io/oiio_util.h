// Helpers shared by the OpenImageIO file reader and writer: messages, sample types, band sizes.
#pragma once

#include <OpenImageIO/imageio.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "gdp/image_io.h"

namespace gdp::io {

// Samples moved between OpenImageIO's interleaved layout and gdp's planar one per call (1 MiB):
// small enough to stay in cache and to never need a second whole-image buffer, large enough that
// OpenImageIO still decodes in big blocks. Measured on an 8000x4500 RGB image: as fast as a single
// read_image() call, while a whole-image interleaved buffer plus deinterleave was 40-60% slower.
inline constexpr std::size_t kBandSamples = std::size_t{1} << 18;

// Above this many bytes of pixel data a TIFF must be BigTIFF (classic TIFF offsets are 32-bit).
inline constexpr double kBigTiffBytes = 3.5 * 1024.0 * 1024.0 * 1024.0;

// Largest JPEG (in bytes of 8-bit pixels) written through io::CheckedFile, which OpenImageIO
// 2.4's JPEG writer buffers whole in memory; larger ones are written to the file directly.
inline constexpr double kJpegBufferBytes = 512.0 * 1024.0 * 1024.0;

// Rows per band: about kBandSamples samples, at least one row, at most the image, and a whole
// number of `unit` rows (tile rows of a tiled file; 1 otherwise) unless that exceeds the image.
int band_rows(int width, int height, int channels, int unit = 1);

// OpenImageIO messages may span several lines; join the non-empty ones with "; ".
std::string one_line(std::string_view message);

SampleType sample_type_of(OIIO::TypeDesc type);
OIIO::TypeDesc type_desc_of(SampleType type);

// Sample type to ask the writer for. Writers that store floating point (TIFF, OpenEXR, Radiance
// HDR, FITS) default to Float, all others to UInt8. A floating-point type asked of a writer that
// cannot store it becomes UInt16 for PNG (OpenImageIO itself would pick UInt8) and UInt8 otherwise.
// OpenImageIO's open() may still adjust the type to what the plugin stores (seen in 2.4: TIFF
// Half -> Float, OpenEXR Double -> Float and integers -> Half, HDR anything -> Float, JPEG/WebP/
// BMP/PPM UInt16 -> UInt8, FITS UInt16 -> Int16); the samples written follow that adjusted spec.
SampleType choose_sample_type(const std::string& format_name, const std::optional<SampleType>& requested);

// UINT8 or UINT16 when every channel of `spec` is stored so, else UNKNOWN. gdp converts such
// samples to and from float itself: OpenImageIO 2.4 converts a few scanlines per task on its
// thread pool, which made writing a 256-pixel-wide 8-bit image 7x slower than the encoding
// itself, and reading 8-bit files some 30% slower. The results are the same bit for bit
// (k * (1.0f / max) one way; clamp to [0, 1], * max + 0.5f and truncate the other).
OIIO::TypeDesc native_integer_type(const OIIO::ImageSpec& spec);

// True for OpenImageIO format names that do not keep exact values.
bool is_lossy_format(const std::string& format_name);

}  // namespace gdp::io
