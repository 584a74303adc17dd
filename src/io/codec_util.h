// Rules shared by every codec backend: band sizes, sample type choice, message cleanup, sample conversion.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "gdp/image_io.h"
#include "multigrid/masked.h"

namespace gdp::io {

// Samples moved between a codec's interleaved layout and gdp's planar one per band (1 MiB):
// small enough to stay in cache and to never need a second whole-image buffer, large enough that
// the codecs still decode in big blocks. Measured on an 8000x4500 RGB image: as fast as a single
// whole-image read, while a whole-image interleaved buffer plus deinterleave was 40-60% slower.
inline constexpr std::size_t kBandSamples = std::size_t{1} << 18;

// Above this many bytes of pixel data a TIFF must be BigTIFF (classic TIFF offsets are 32-bit).
inline constexpr double kBigTiffBytes = 3.5 * 1024.0 * 1024.0 * 1024.0;

// Largest JPEG (in bytes of 8-bit pixels) that OpenImageIO's module writes through its checked
// file (OpenImageIO 2.4's JPEG writer buffers it whole in memory); see oiio_module/oiio_encoder.cc.
// gdp's own JPEG encoder streams every size through the checked file.
inline constexpr double kJpegBufferBytes = 512.0 * 1024.0 * 1024.0;

// Rows per band: about kBandSamples samples, at least one row, at most the image, and a whole
// number of `unit` rows (tile rows of a tiled file; 1 otherwise) unless that exceeds the image.
int band_rows(int width, int height, int channels, int unit = 1);

// Rows decoded by a scanline library into a column window: `decode(row pointers, count)` fills
// `count` rows of `row_bytes`; `out` receives bytes [skip, skip + out_row) of each, straight when
// the window is whole rows, else through `scratch`. Returns what decode returns (false: failed).
template <class Decode>
bool decode_rows(int count, std::size_t row_bytes, std::size_t skip, std::size_t out_row, unsigned char* out,
                 std::vector<unsigned char>& scratch, Decode&& decode) {
  const bool direct = skip == 0 && out_row == row_bytes;
  std::vector<unsigned char*> rows(static_cast<std::size_t>(count));
  if (!direct) scratch.resize(row_bytes * rows.size());
  for (int y = 0; y < count; ++y) rows[y] = (direct ? out : scratch.data()) + y * row_bytes;
  if (!decode(rows.data(), count)) return false;
  if (!direct)
    for (int y = 0; y < count; ++y) std::memcpy(out + y * out_row, rows[y] + skip, out_row);
  return true;
}

// Codec messages may span several lines; join the non-empty ones with "; ".
std::string one_line(std::string_view message);

// Sample type to ask the writer for. Writers that store floating point (TIFF, OpenEXR, Radiance
// HDR, FITS) default to Float, all others to UInt8. A floating-point type asked of a writer that
// cannot store it becomes UInt16 for PNG and UInt8 otherwise. The encoder may still adjust the
// type to what the format stores (TIFF Half -> Float, JPEG UInt16 -> UInt8, OpenEXR Double ->
// Float and integers -> Half as OpenImageIO 2.4 did, and in OpenImageIO 2.4: HDR anything ->
// Float, WebP/BMP/PPM UInt16 -> UInt8, FITS UInt16 -> Int16); the samples written follow that
// adjusted type.
SampleType choose_sample_type(const std::string& format_name, const std::optional<SampleType>& requested);

// True for format names (OpenImageIO's names) that do not keep exact values.
bool is_lossy_format(const std::string& format_name);

// Bytes of one sample of UInt8, UInt16 or Float (the types bands hold); 8 for Double, 2 for Half.
std::size_t sample_bytes(SampleType type);
// The type a band of decoded rows keeps samples of this type in: 8- and 16-bit integers as they
// are, every floating-point type as Float.
inline SampleType band_type(SampleType type) {
  return type == SampleType::UInt8 || type == SampleType::UInt16 ? type : SampleType::Float;
}

// 8- and 16-bit samples are converted to and from float by gdp itself, the same bit for bit in
// every backend: k * (1.0f / max) one way; clamp to [0, 1] (NaN -> 0), * max + 0.5f and truncate
// the other. The clamp without a branch on a floating-point test, so that loops of it vectorise
// (the same result as v > 0 ? min(v, 1) : 0 for every float: checked over all 2^32 of them).
inline float clamp01(float v) { return multigrid::masked(1.0f < v ? 1.0f : v, v > 0.0f); }
// f(std::integral_constant<int, N>{}) with N = ch for 1 to 4 channels (a constant that lets a
// pixel loop vectorise), else N = 0 (the count at run time).
template <class F>
void with_channel_count(int ch, F&& f) {
  switch (ch) {
    case 1: return f(std::integral_constant<int, 1>{});
    case 2: return f(std::integral_constant<int, 2>{});
    case 3: return f(std::integral_constant<int, 3>{});
    case 4: return f(std::integral_constant<int, 4>{});
    default: return f(std::integral_constant<int, 0>{});
  }
}
inline float from_u8(std::uint8_t v) { return static_cast<float>(v) * (1.0f / 255.0f); }
inline float from_u16(std::uint16_t v) { return static_cast<float>(v) * (1.0f / 65535.0f); }
inline std::uint8_t to_u8(float v) { return static_cast<std::uint8_t>(clamp01(v) * 255.0f + 0.5f); }
inline std::uint16_t to_u16(float v) { return static_cast<std::uint16_t>(clamp01(v) * 65535.0f + 0.5f); }


// Lower-case extension without the dot ("TIF" -> "tif").
std::string lower_extension(const std::string& path);

// WriteOptions::compression "NAME[:LEVEL]": NAME in lower case, and the text after ':' if any.
struct CompressionSpec {
  std::string name;
  std::optional<std::string> level;
};
CompressionSpec split_compression(const std::string& text);

// A codec's compression names with their codes, for Encoder::compression_refusal().
template <class Code>
struct CompressionName {
  const char* name;
  Code code;
};

// The code named in `names` (or `fallback` for a name not there).
template <class Code, std::size_t N>
Code compression_code(const CompressionName<Code> (&names)[N], const std::string& name, Code fallback) {
  for (const auto& n : names)
    if (name == n.name) return n.code;
  return fallback;
}

// Empty when `compression`'s name is in `names`, else "a, b, c" followed by `levels`.
template <class Code, std::size_t N>
std::string compression_refusal(const CompressionName<Code> (&names)[N], const std::string& compression,
                                const char* levels) {
  const std::string name = split_compression(compression).name;
  std::string list;
  for (const auto& n : names) {
    if (name == n.name) return {};
    list += (list.empty() ? "" : ", ") + std::string(n.name);
  }
  return list + " " + levels;
}

}  // namespace gdp::io
