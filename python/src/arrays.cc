// numpy arrays <-> planar gdp::Image, with the codecs' own integer conversions.
#include "arrays.h"

#include <cstdint>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "io/codec_util.h"

namespace py = pybind11;

namespace gdp::python {
namespace {

template <class T, class Convert>
Image convert(const py::array& array, int width, int height, int channels, Convert value) {
  const auto c = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!c) throw py::error_already_set();
  const T* p = c.data();
  Image image(width, height, channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int ch = 0; ch < channels; ++ch) image.at(ch, x, y) = value(*p++);
  return image;
}

}  // namespace

py::array array_arg(const py::handle& value, const std::string& function, const std::string& name) {
  if (!py::isinstance<py::array>(value))
    throw py::type_error(fmt::format("{}(): {} must be a numpy array, got {} ({}_file reads files)", function, name,
                                     py::str(py::type::of(value).attr("__name__")).cast<std::string>(), function));
  return py::reinterpret_borrow<py::array>(value);
}

bool is_integer(const py::array& array) {
  const char kind = array.dtype().kind();
  return kind == 'u' && (array.itemsize() == 1 || array.itemsize() == 2);
}

Image to_image(const py::array& array, const std::string& name) {
  if (array.ndim() != 2 && array.ndim() != 3)
    throw UsageError(fmt::format("{}: expected an array of shape (height, width) or (height, width, channels), "
                                 "got {} dimension(s)", name, array.ndim()));
  const auto dim = [&](int i) -> int {
    if (array.shape(i) > (1 << 30)) throw UsageError(fmt::format("{}: dimension {} is too large", name, i));
    return static_cast<int>(array.shape(i));
  };
  const int height = dim(0), width = dim(1), channels = array.ndim() == 3 ? dim(2) : 1;
  if (width < 1 || height < 1 || channels < 1)
    throw UsageError(fmt::format("{}: empty array ({}x{}x{})", name, width, height, channels));
  const char kind = array.dtype().kind();
  const auto size = array.itemsize();
  if (kind == 'u' && size == 1)
    return convert<std::uint8_t>(array, width, height, channels, [](std::uint8_t v) { return io::from_u8(v); });
  if (kind == 'u' && size == 2)
    return convert<std::uint16_t>(array, width, height, channels, [](std::uint16_t v) { return io::from_u16(v); });
  if (kind == 'b') return convert<bool>(array, width, height, channels, [](bool v) { return v ? 1.0f : 0.0f; });
  if (kind == 'f' && size <= 4) return convert<float>(array, width, height, channels, [](float v) { return v; });
  if (kind == 'f' && size == 8)
    return convert<double>(array, width, height, channels, [](double v) { return static_cast<float>(v); });
  throw py::type_error(fmt::format("{}: arrays of {} are not images (use uint8, uint16, bool or floats)", name,
                                   py::str(array.dtype()).cast<std::string>()));
}

std::optional<SampleType> sample_type_of(const py::array& array) {
  if (!is_integer(array)) return std::nullopt;
  return array.itemsize() == 1 ? SampleType::UInt8 : SampleType::UInt16;
}

py::array_t<float> to_array(const Image& image, bool two_d) {
  const auto h = static_cast<py::ssize_t>(image.height), w = static_cast<py::ssize_t>(image.width);
  const auto c = static_cast<py::ssize_t>(image.channels);
  py::array_t<float> out = two_d && c == 1 ? py::array_t<float>({h, w}) : py::array_t<float>({h, w, c});
  float* p = out.mutable_data();
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int ch = 0; ch < image.channels; ++ch) *p++ = image.at(ch, x, y);
  return out;
}

}  // namespace gdp::python
