/// @file Module.cpp
/// The extension module conftrack._conftrack: error translation and the
/// registration of the bindings (one file per concept). The Python API
/// proper, with pandas DataFrames, is python/conftrack/__init__.py.

#include "conftrack/core/Error.hpp"

#include <pybind11/pybind11.h>

#include "Bindings.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_conftrack, m) {
  m.doc() = "conftrack C++ core; use the package conftrack";
  // Bad input: the CLI's one-line message, as FileNotFoundError for a
  // missing file and ValueError for the rest.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) {
        std::rethrow_exception(p);
      }
    } catch (const conftrack::MissingFileError& e) {
      PyErr_SetString(PyExc_FileNotFoundError, e.what());
    } catch (const conftrack::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  conftrack::python::bindDetector(m);
  conftrack::python::bindEvents(m);
  conftrack::python::bindReconstruction(m);
  conftrack::python::bindEvaluation(m);
}
