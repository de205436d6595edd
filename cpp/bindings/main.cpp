// pydrill._core: the C++ library seen from Python. Kept private; the public
// API is the pure-Python package that re-exports and documents it.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "pydrill/simulator.hpp"
#include "pydrill/version.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "pydrill C++ core (private: use the pydrill package)";
  m.attr("__version__") = pydrill::version();
  // std::invalid_argument already arrives as ValueError; SolverError keeps the
  // time the integration reached.
  static py::handle solver_error =
      py::exception<pydrill::SolverError>(m, "SolverError", PyExc_RuntimeError).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const pydrill::SolverError& e) {
      py::object err = py::reinterpret_borrow<py::object>(solver_error)(e.what());
      err.attr("t_reached") = e.t_reached();
      PyErr_SetObject(solver_error.ptr(), err.ptr());
    }
  });
  pydrill::bindings::bind_params(m);
  pydrill::bindings::bind_simulate(m);
  pydrill::bindings::bind_stability(m);
  pydrill::bindings::bind_table(m);
}
