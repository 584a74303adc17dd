// Registration of the module's functions, one group per source file.
#pragma once

#include <pybind11/pybind11.h>

namespace gdp::python {

void register_apps(pybind11::module_& m);    // stitch, sharpen, smooth, clone, tonemap (+ _file)
void register_images(pybind11::module_& m);  // read_image, write_image, reconstruct, to_pq, from_pq (+ _file)

}  // namespace gdp::python
