// In-memory multi-channel float image, stored channel by channel (planar).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace gdp {

// Pixel values of integer files are normalised to [0, 1]; float files keep their values.
// Storage is planar: channel c, row y, column x lives at data[(c * height + y) * width + x].
struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> data;

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
      : width(w), height(h), channels(c),
        data(static_cast<std::size_t>(w) * h * c, fill) {}

  std::size_t plane_size() const { return static_cast<std::size_t>(width) * height; }
  std::size_t index(int c, int x, int y) const { return (c * static_cast<std::size_t>(height) + y) * width + x; }
  float& at(int c, int x, int y) { return data[index(c, x, y)]; }
  float at(int c, int x, int y) const { return data[index(c, x, y)]; }
  std::span<float> plane(int c) { return {data.data() + c * plane_size(), plane_size()}; }
  std::span<const float> plane(int c) const { return {data.data() + c * plane_size(), plane_size()}; }
  std::span<float> row(int c, int y) { return {data.data() + index(c, 0, y), static_cast<std::size_t>(width)}; }
  std::span<const float> row(int c, int y) const {
    return {data.data() + index(c, 0, y), static_cast<std::size_t>(width)};
  }
};

}  // namespace gdp
