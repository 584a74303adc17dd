// The extension module gdp._gdp: errors, applications and image functions (re-exported by gdp/__init__.py).
#include <pybind11/pybind11.h>

#include "apps.h"
#include "errors.h"

PYBIND11_MODULE(_gdp, m) {
  m.doc() =
      "gdp: gradient-domain processing of large planar and spherical images (seamless stitching, sharpening and "
      "smoothing, cloning, tone mapping) with the streaming multigrid solver of Kazhdan, Surendran and Hoppe "
      "(2010). Functions take numpy arrays and return arrays; the *_file forms stream files to files with the "
      "gdp CLI's options. docs/python.md has the details.";
  pybind11::options options;
  options.disable_function_signatures();  // each docstring starts with its own, in Python's terms
  gdp::python::register_errors(m);
  gdp::python::register_apps(m);
  gdp::python::register_images(m);
}
