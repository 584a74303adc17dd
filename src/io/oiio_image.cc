// Whole-image reading and writing: the streaming reader and writer, row after row.
#include <cctype>
#include <string>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"

namespace gdp {

ReadResult read_image(const std::filesystem::path& path) {
  ImageFileReader reader(path, false);
  ReadResult result{Image(reader.width(), reader.height(), reader.channels()), reader.info()};
  ImageRowWriter rows(result.image);
  std::vector<float> row(static_cast<std::size_t>(reader.width()) * reader.channels());
  for (int y = 0; y < reader.height(); ++y) {
    reader.read_row(y, row);
    rows.write_row(y, row);
  }
  return result;
}

void write_image(const std::filesystem::path& path, const Image& image, const WriteOptions& options) {
  if (image.data.size() != image.plane_size() * static_cast<std::size_t>(std::max(image.channels, 0)))
    throw OutputError(fmt::format("{}: image data size does not match its dimensions", path.string()));
  ImageFileWriter writer(path, image.width, image.height, image.channels, options);
  ImageRowReader rows(image);
  std::vector<float> row(static_cast<std::size_t>(image.width) * image.channels);
  for (int y = 0; y < image.height; ++y) {
    rows.read_row(y, row);
    writer.write_row(y, row);
  }
  writer.commit();
}

std::optional<SampleType> parse_depth(std::string_view depth) {
  if (depth.empty()) return std::nullopt;
  if (depth == "8") return SampleType::UInt8;
  if (depth == "16") return SampleType::UInt16;
  if (depth == "half") return SampleType::Half;
  if (depth == "float") return SampleType::Float;
  throw UsageError(fmt::format("--depth must be 8, 16, half or float, got '{}'", depth));
}

bool is_lossy_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".jpg" || ext == ".jpeg" || ext == ".jpe" || ext == ".jfif" || ext == ".webp" || ext == ".heic" ||
         ext == ".heif" || ext == ".jp2" || ext == ".j2k";
}

}  // namespace gdp
