#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pydrill/stability.hpp"

namespace py = pybind11;

namespace pydrill::bindings {
namespace {

py::dict crossing_dict(const Crossing& c) {
  py::dict d;
  d["type"] = crossing_type_name(c.type);  // Python keeps the names
  d["delta"] = c.delta;
  d["frequency"] = c.type == CrossingType::Hopf ? py::object(py::float_(c.frequency)) : py::object(py::none());
  d["direction"] = c.direction;
  d["multiplicity"] = c.multiplicity;
  return d;
}

// The inverse of crossing_dict: crossings found earlier, handed back.
Crossing crossing_from(const py::dict& d) {
  Crossing c;
  // The core reads only delta, direction and multiplicity of crossings handed back, and
  // Python's Crossing has always been passed through with any type string: anything but
  // "fold" stays accepted (as a Hopf crossing) rather than becoming a new ValueError.
  c.type = d["type"].cast<std::string>() == "fold" ? CrossingType::Fold : CrossingType::Hopf;
  c.delta = d["delta"].cast<double>();
  c.frequency = d["frequency"].is_none() ? 0.0 : d["frequency"].cast<double>();
  c.direction = d["direction"].cast<int>();
  c.multiplicity = d["multiplicity"].cast<int>();
  return c;
}

py::dict point_dict(const StabilityPoint& s) {
  py::dict d;
  d["omega"] = s.omega;
  d["wob"] = s.wob;
  d["torque"] = s.torque;
  d["delta"] = s.delta;
  d["unstable"] = s.unstable;
  d["stable"] = s.stable;
  d["delta_margin"] = s.delta_margin;
  d["spectral_abscissa"] = s.spectral_abscissa;
  d["eigenvalues"] = s.eigenvalues;
  return d;
}

// Ctrl-C, as in simulate: the O(dof²) calls ask Python's signal handlers every 0.1 s. A
// handler that raises, as the default KeyboardInterrupt does, stops the computation; its
// exception is re-raised. Only the main thread asks: elsewhere (Dask's worker threads) the
// answer is always no, and taking the GIL to hear it could wait on a busy event loop.
std::function<bool()> python_signals() {
  const py::module_ threading = py::module_::import("threading");
  if (!threading.attr("current_thread")().is(threading.attr("main_thread")())) return {};
  return [] {
    py::gil_scoped_acquire gil;
    return PyErr_CheckSignals() != 0;
  };
}

// compute(interrupt) on the string p without the GIL (it holds no Python objects: other
// threads run meanwhile), stopped by Ctrl-C. A string of fewer than 100 inertias is done long
// before the first question (0.1 s; 500 pipes take 0.06 s): it is spared the look at the thread, a
// few µs that a loop over many points of a short string would feel.
template <typename F>
auto interruptible(const Params& p, F&& compute) {
  const std::function<bool()> interrupt = p.dof() >= 100 ? python_signals() : nullptr;
  try {
    py::gil_scoped_release release;
    return std::forward<F>(compute)(interrupt);
  } catch (const StabilityInterrupted&) {
    throw py::error_already_set();  // what the handler raised, KeyboardInterrupt
  }
}

}  // namespace

void bind_stability(py::module_& m) {
  m.def("stribeck_slope", &stribeck_slope, py::arg("params"), py::arg("wob"), py::arg("omega"));
  m.def("boundary_wob", &boundary_wob, py::arg("params"), py::arg("delta"), py::arg("omega"));
  m.def("bit_impedance", &bit_impedance, py::arg("params"), py::arg("lam"));
  m.def("jacobian", &jacobian, py::arg("params"), py::arg("delta"));
  m.def(
      "eigenvalues",
      [](const Params& p, double delta) {
        py::gil_scoped_release release;
        return eigenvalues(p, delta);
      },
      py::arg("params"), py::arg("delta"));
  m.def(
      "structured_eigenvalues",
      [](const Params& p, double delta) {
        return interruptible(
            p, [&](const auto& interrupt) { return structured_eigenvalues(p, delta, interrupt); });
      },
      py::arg("params"), py::arg("delta"));
  m.def(
      "roots_of_impedance",
      [](const Params& p, double delta) {
        return interruptible(p, [&](const auto& interrupt) -> std::optional<std::vector<std::complex<double>>> {
          std::vector<std::complex<double>> z;
          if (!roots_of_impedance(p, delta, z, interrupt)) return std::nullopt;
          return z;
        });
      },
      py::arg("params"), py::arg("delta"));
  m.def("characteristic_polynomial", &characteristic_polynomial, py::arg("params"), py::arg("delta"));
  m.def("hurwitz_determinants", &hurwitz_determinants, py::arg("ascending"));
  m.def("hopf_deltas_dof2", &hopf_deltas_dof2, py::arg("params"));
  m.def("first_lyapunov_coefficient", &first_lyapunov_coefficient, py::arg("params"), py::arg("delta"),
        py::arg("frequency"));
  m.def(
      "critical_deltas",
      [](const Params& p) {
        const std::vector<Crossing> c =
            interruptible(p, [&](const auto& interrupt) { return critical_deltas(p, interrupt); });
        py::list out;
        for (const auto& x : c) out.append(crossing_dict(x));
        return out;
      },
      py::arg("params"));
  m.def(
      "stability_at_velocity",
      [](const Params& p, double wob, double omega) {
        return point_dict(interruptible(
            p, [&](const auto& interrupt) { return stability_at_velocity(p, wob, omega, interrupt); }));
      },
      py::arg("params"), py::arg("wob"), py::arg("omega"));
  m.def(
      "stability_at_torque",
      [](const Params& p, double wob, double torque, std::optional<py::list> crossings) {
        std::vector<StabilityPoint> points;
        if (crossings) {
          std::vector<Crossing> known;
          for (const auto& item : *crossings) known.push_back(crossing_from(item.cast<py::dict>()));
          points = interruptible(p, [&](const auto& interrupt) {
            return stability_at_torque(p, known, wob, torque, interrupt);
          });
        } else {
          points = interruptible(
              p, [&](const auto& interrupt) { return stability_at_torque(p, wob, torque, interrupt); });
        }
        py::list out;
        for (const auto& s : points) out.append(point_dict(s));
        return out;
      },
      py::arg("params"), py::arg("wob"), py::arg("torque"), py::arg("crossings") = py::none());
}

}  // namespace pydrill::bindings
