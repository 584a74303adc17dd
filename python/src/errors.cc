// gdp's typed errors as Python exceptions: gdp.Error and its subclasses, each also a built-in one.
#include "errors.h"

#include <string>

#include "gdp/errors.h"

namespace py = pybind11;

namespace gdp::python {
namespace {

// Classes live as long as the interpreter: kept as plain references, never released.
PyObject* error_class = nullptr;
PyObject* input_class = nullptr;
PyObject* output_class = nullptr;
PyObject* usage_class = nullptr;

PyObject* add_class(py::module_& m, const char* name, py::object bases, const char* doc) {
  const std::string qualified = std::string("gdp.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!cls) throw py::error_already_set();
  m.add_object(name, py::handle(cls));  // add_object takes a reference of its own
  return cls;
}

}  // namespace

void register_errors(py::module_& m) {
  error_class = add_class(m, "Error", py::reinterpret_borrow<py::object>(PyExc_Exception),
                          "Base of every error gdp reports; str(e) is the message the gdp CLI prints.");
  const auto with = [](PyObject* builtin) {
    return py::make_tuple(py::handle(error_class), py::handle(builtin));
  };
  input_class = add_class(m, "InputError", with(PyExc_ValueError),
                          "An input (file or array) is missing, unreadable, or has content gdp cannot use.");
  output_class = add_class(m, "OutputError", with(PyExc_OSError),
                           "An output file could not be written (nothing is left behind).");
  usage_class = add_class(m, "UsageError", with(PyExc_ValueError),
                          "Options or arguments are invalid or inconsistent with each other.");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_class, e.what());
    } catch (const OutputError& e) {
      PyErr_SetString(output_class, e.what());
    } catch (const UsageError& e) {
      PyErr_SetString(usage_class, e.what());
    } catch (const Error& e) {
      PyErr_SetString(error_class, e.what());
    }
  });
}

}  // namespace gdp::python
