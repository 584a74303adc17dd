// Band sizing, sample type rules, message cleanup and half floats shared by the codec backends.
#include "io/codec_util.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>

namespace gdp::io {

int band_rows(int width, int height, int channels, int unit) {
  const std::size_t row_samples = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
  const std::size_t rows = std::clamp<std::size_t>(kBandSamples / row_samples, 1, static_cast<std::size_t>(height));
  if (unit <= 1) return static_cast<int>(rows);
  const std::size_t units = std::max<std::size_t>(1, rows / static_cast<std::size_t>(unit));
  return static_cast<int>(std::min<std::size_t>(units * static_cast<std::size_t>(unit), static_cast<std::size_t>(height)));
}

std::string one_line(std::string_view message) {
  std::string result;
  while (!message.empty()) {
    const std::size_t end = std::min(message.find('\n'), message.size());
    std::string_view line = message.substr(0, end);
    message.remove_prefix(std::min(end + 1, message.size()));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front()))) line.remove_prefix(1);
    if (line.empty()) continue;
    if (!result.empty()) result += "; ";
    result += line;
  }
  return result.empty() ? "unknown error" : result;
}

SampleType choose_sample_type(const std::string& format_name, const std::optional<SampleType>& requested) {
  const bool holds_float =
      format_name == "tiff" || format_name == "openexr" || format_name == "hdr" || format_name == "fits";
  if (!requested) return holds_float ? SampleType::Float : SampleType::UInt8;
  const bool float_requested = *requested == SampleType::Half || *requested == SampleType::Float ||
                               *requested == SampleType::Double;
  if (float_requested && !holds_float) return format_name == "png" ? SampleType::UInt16 : SampleType::UInt8;
  return *requested;
}

bool is_lossy_format(const std::string& format_name) {
  return format_name == "jpeg" || format_name == "webp" || format_name == "heif" || format_name == "jpeg2000";
}

std::size_t sample_bytes(SampleType type) {
  switch (type) {
    case SampleType::UInt8: return 1;
    case SampleType::UInt16: return 2;
    case SampleType::Half: return 2;
    case SampleType::Float: return 4;
    case SampleType::Double: return 8;
  }
  return 4;
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

CompressionSpec split_compression(const std::string& text) {
  const std::size_t colon = text.find(':');
  CompressionSpec spec{text.substr(0, colon), std::nullopt};
  for (char& ch : spec.name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (colon != std::string::npos) spec.level = text.substr(colon + 1);
  return spec;
}

}  // namespace gdp::io
