#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pydrill/equilibrium.hpp"
#include "pydrill/params.hpp"

namespace py = pybind11;

namespace pydrill::bindings {

void bind_params(py::module_& m) {
  py::class_<Params>(m, "Params")
      .def(py::init<>())
      .def_readwrite("inertias", &Params::inertias)
      .def_readwrite("stiffnesses", &Params::stiffnesses)
      .def_readwrite("dampings", &Params::dampings)
      .def_readwrite("top_damping", &Params::top_damping)
      .def_readwrite("bit_damping", &Params::bit_damping)
      .def_readwrite("bit_radius", &Params::bit_radius)
      .def_readwrite("mu_coulomb", &Params::mu_coulomb)
      .def_readwrite("mu_static", &Params::mu_static)
      .def_readwrite("stribeck_decay", &Params::stribeck_decay)
      .def_readwrite("stribeck_velocity", &Params::stribeck_velocity)
      .def_readwrite("karnopp_band", &Params::karnopp_band)
      .def_property_readonly("dof", &Params::dof)
      .def("validate", &Params::validate);
  m.def("preset", &preset, py::arg("name"), py::arg("dof"));
  m.def("preset_names", &preset_names);
  m.def("equilibrium_velocities", &equilibrium_velocities, py::arg("params"), py::arg("wob"),
        py::arg("torque"));
  m.def("equilibrium_torque", &equilibrium_torque, py::arg("params"), py::arg("wob"), py::arg("omega"));
  m.def("equilibrium_state", &equilibrium_state, py::arg("params"), py::arg("wob"), py::arg("omega"));
}

}  // namespace pydrill::bindings
