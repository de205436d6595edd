#pragma once

#include <pybind11/pybind11.h>

namespace pydrill::bindings {
void bind_params(pybind11::module_& m);
void bind_simulate(pybind11::module_& m);
void bind_stability(pybind11::module_& m);
void bind_table(pybind11::module_& m);
}  // namespace pydrill::bindings
