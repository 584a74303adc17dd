// gdp's typed errors (include/gdp/errors.h) as Python exception classes with the same messages.
#pragma once

#include <pybind11/pybind11.h>

namespace gdp::python {

// Adds gdp.Error, gdp.InputError, gdp.OutputError and gdp.UsageError to `m`, and translates the
// C++ exceptions into them.
void register_errors(pybind11::module_& m);

}  // namespace gdp::python
