// multiblend's seam files: an 8-bit palette PNG whose sample value is the layer index (libpng).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "blend/seams.h"

namespace gdp::blending {

// The value of pixels no layer covers in a palette seam file (so at most 255 layers).
inline constexpr int kPaletteNone = 255;

// Whether `path` is a PNG of palette colour type (false for grey PNGs: gdp's own label maps).
bool is_palette_png(const std::string& path);

// Writes the labels as a palette PNG: index = layer (0 = the first), kPaletteNone where none
// covers; each layer its own colour in the palette for viewing. Written to a temporary beside
// `path`, renamed at the end. UsageError past 255 layers; IoError when it cannot be written.
void write_palette_seams(const LabelPlane& labels, int layers, const std::string& path);

// A palette PNG's indices, row by row in order (bit depths 1 to 8). InputError naming the file.
class PaletteRows {
 public:
  explicit PaletteRows(const std::string& path);
  ~PaletteRows();
  int width() const;
  int height() const;
  void read_row(std::span<std::uint8_t> row);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace gdp::blending
