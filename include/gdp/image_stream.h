// Image files read and written row by row, with decoding and encoding on background threads.
#pragma once

#include <filesystem>
#include <memory>
#include <span>

#include "gdp/image_io.h"
#include "gdp/rows.h"

namespace gdp {

// Reads an image file in bands of rows (whole tile rows for tiled files), never the whole
// image. With prefetch, a background thread decodes the next band while the caller uses the
// current one. Errors (also the decoder thread's) are InputError naming the file.
class ImageFileReader final : public RowReader {
 public:
  explicit ImageFileReader(const std::filesystem::path& path, bool prefetch = true);
  ~ImageFileReader() override;
  const ImageFileInfo& info() const;
  int width() const override;
  int height() const override;
  int channels() const override;
  void read_row(int y, std::span<float> out) override;
  void rewind() override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes an image file row by row to a temporary name next to it (encoding on a background
// thread, a band of rows at a time); commit() finishes it and renames it into place. Destroyed
// without commit(), it deletes the temporary file: nothing is left behind. Integer outputs are
// clamped to [0, 1]. Errors are OutputError naming the final file.
class ImageFileWriter final : public RowWriter {
 public:
  ImageFileWriter(const std::filesystem::path& path, int width, int height, int channels, const WriteOptions& options);
  ~ImageFileWriter() override;
  void write_row(int y, std::span<const float> row) override;
  void commit() override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gdp
