// Streams of image rows: how files, in-memory images and the solver hand rows to each other.
#pragma once

#include <span>

#include "gdp/image.h"

namespace gdp {

// Rows are channel-major: row[c * width + x] is channel c at column x.

// A source of rows, read in order y = 0, 1, ..., height - 1, each once per pass; rewind()
// starts a new pass at row 0.
class RowReader {
 public:
  virtual ~RowReader() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual int channels() const = 0;
  // Fills `out` (channels * width samples) with row y. Throws gdp::InputError on bad data.
  virtual void read_row(int y, std::span<float> out) = 0;
  virtual void rewind() = 0;
  // A hint that, from the next row read on, only columns [begin, end) of every row are needed
  // (a rank of a distributed solve): readers may then decode only those and leave the other
  // samples of `out` as they are. Readers that ignore it stay correct.
  virtual void set_columns(int /*begin*/, int /*end*/) {}
};

// A destination for rows, written in order y = 0, 1, ..., height - 1; commit() after the
// last row makes the result visible (a file appears under its final name only then).
class RowWriter {
 public:
  virtual ~RowWriter() = default;
  virtual void write_row(int y, std::span<const float> row) = 0;
  virtual void commit() {}
  // Called before the first row when only columns [begin, end) of the rows written will hold
  // results (a rank of a distributed solve writes its own columns); writers that transform
  // rows pass it on, writers that gather columns from several processes need it.
  virtual void set_columns(int /*begin*/, int /*end*/) {}
  // L (255 or 65535) when the writer stores every sample v as the integer round(clamp01(v) * L),
  // so any value that rounds to the same integer may stand for v (the column gather sends 8- or
  // 16-bit samples); 0 when it keeps floats. May get the output ready (a file opens its codec).
  virtual int stored_levels() { return 0; }
};

// Rows of an in-memory image.
class ImageRowReader final : public RowReader {
 public:
  explicit ImageRowReader(const Image& image) : image_(image) {}
  int width() const override { return image_.width; }
  int height() const override { return image_.height; }
  int channels() const override { return image_.channels; }
  void read_row(int y, std::span<float> out) override {
    for (int c = 0; c < image_.channels; ++c) {
      const auto r = image_.row(c, y);
      std::copy(r.begin(), r.end(), out.begin() + static_cast<std::ptrdiff_t>(c) * image_.width);
    }
  }
  void rewind() override {}

 private:
  const Image& image_;
};

// Rows written into an in-memory image (already sized by the caller).
class ImageRowWriter final : public RowWriter {
 public:
  explicit ImageRowWriter(Image& image) : image_(image) {}
  void write_row(int y, std::span<const float> row) override {
    for (int c = 0; c < image_.channels; ++c) {
      const auto in = row.subspan(static_cast<std::size_t>(c) * image_.width, image_.width);
      std::copy(in.begin(), in.end(), image_.row(c, y).begin());
    }
  }

 private:
  Image& image_;
};

}  // namespace gdp
