// numpy arrays <-> gdp images: (H, W) or (H, W, C) arrays, integer samples normalised as files are.
#pragma once

#include <optional>
#include <string>

#include <pybind11/numpy.h>

#include "gdp/image.h"
#include "gdp/image_io.h"

namespace gdp::python {

// `value` as an array argument `name` of `function`; TypeError (naming the *_file form) otherwise.
pybind11::array array_arg(const pybind11::handle& value, const std::string& function, const std::string& name);

// An array's pixels as a planar float image: uint8 and uint16 samples become k / 255 and
// k / 65535 exactly as gdp's codecs convert them (bit for bit), bool 0 or 1, floats as they are.
// Throws UsageError (shape) or TypeError (dtype) naming the argument `name`.
Image to_image(const pybind11::array& array, const std::string& name);

// The sample type a file written from this array keeps by default: 8/16-bit for uint8/uint16,
// none (the format's own default) otherwise.
std::optional<SampleType> sample_type_of(const pybind11::array& array);

// True when the array holds 8- or 16-bit integers (display-encoded values, as in 8/16-bit files).
bool is_integer(const pybind11::array& array);

// A float32 array (H, W, C), or (H, W) when `two_d` and the image has one channel.
pybind11::array_t<float> to_array(const Image& image, bool two_d);

}  // namespace gdp::python
