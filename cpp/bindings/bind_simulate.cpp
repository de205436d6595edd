#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>

#include "bindings.hpp"
#include "pydrill/simulator.hpp"

namespace py = pybind11;

namespace pydrill::bindings {
namespace {

// A read-only numpy view of a vector owned by the Result: no copy, and the
// Result stays alive as long as any view of it does.
template <typename T>
py::array view(const std::vector<T>& v, std::vector<py::ssize_t> shape, py::handle owner) {
  py::array a(py::dtype::of<T>(), std::move(shape), {}, v.data(), owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::dict summary_dict(const Summary& s) {
  py::dict d;
  d["regime"] = regime_name(s.regime);  // Python keeps the names
  d["window_start"] = s.window_start;
  d["window_end"] = s.window_end;
  d["bit_min"] = s.bit_min;
  d["bit_max"] = s.bit_max;
  d["bit_mean"] = s.bit_mean;
  d["top_min"] = s.top_min;
  d["top_max"] = s.top_max;
  d["top_mean"] = s.top_mean;
  d["severity"] = s.severity;
  d["bit_top_ratio"] = s.bit_top_ratio;
  d["stuck_fraction"] = s.stuck_fraction;
  d["period"] = s.period > 0 ? py::object(py::float_(s.period)) : py::object(py::none());
  d["stick_events"] = s.stick_events;
  d["static_torque"] = s.static_torque;
  d["omega_equilibrium"] = s.omega_equilibrium;
  d["note"] = s.note;
  d["caveat"] = s.caveat;
  return d;
}

py::dict stats_dict(const SolverStats& s) {
  py::dict d;
  d["method"] = method_name(s.method);
  d["method_reason"] = s.method_reason;
  d["stiffness_ratio"] = s.stiffness_ratio;
  d["steps"] = s.steps;
  d["rhs_evals"] = s.rhs_evals;
  d["jac_evals"] = s.jac_evals;
  d["lin_setups"] = s.lin_setups;
  d["lin_solves"] = s.lin_solves;
  d["nonlin_iters"] = s.nonlin_iters;
  d["nonlin_conv_fails"] = s.nonlin_conv_fails;
  d["err_test_fails"] = s.err_test_fails;
  d["root_evals"] = s.root_evals;
  d["reinits"] = s.reinits;
  d["switches"] = s.switches;
  d["wall_time"] = s.wall_time;
  return d;
}

}  // namespace

void bind_simulate(py::module_& m) {
  py::class_<SimulationOptions>(m, "SimulationOptions")
      .def(py::init<>())
      .def_readwrite("t_end", &SimulationOptions::t_end)
      .def_readwrite("t_out", &SimulationOptions::t_out)
      .def_readwrite("n_out", &SimulationOptions::n_out)
      .def_readwrite("state", &SimulationOptions::state)
      .def_readwrite("perturbation", &SimulationOptions::perturbation)
      .def_readwrite("rtol", &SimulationOptions::rtol)
      .def_readwrite("atol", &SimulationOptions::atol)
      .def_readwrite("max_step", &SimulationOptions::max_step)
      .def_readwrite("max_order", &SimulationOptions::max_order)
      .def_readwrite("max_steps", &SimulationOptions::max_steps)
      .def_readwrite("window_fraction", &SimulationOptions::window_fraction)
      .def_readwrite("max_switch_rate", &SimulationOptions::max_switch_rate)
      .def_property(
          "method", [](const SimulationOptions& o) { return std::string(method_name(o.method)); },
          [](SimulationOptions& o, const std::string& s) { o.method = parse_method(s); })
      .def_property(
          "friction",
          [](const SimulationOptions& o) {
            return std::string(o.friction == FrictionLaw::Exact ? "exact" : "karnopp");
          },
          [](SimulationOptions& o, const std::string& s) { o.friction = parse_friction(s); })
      .def_property(
          "initial",
          [](const SimulationOptions& o) {
            return std::string(o.initial == Initial::Rest          ? "rest"
                               : o.initial == Initial::Equilibrium ? "equilibrium"
                                                                   : "state");
          },
          [](SimulationOptions& o, const std::string& s) { o.initial = parse_initial(s); });

  py::class_<Result, std::shared_ptr<Result>>(m, "Result")
      .def_readonly("dof", &Result::dof)
      .def_readonly("wob", &Result::wob)
      .def_readonly("torque", &Result::torque)
      .def_property_readonly("t", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.t, {static_cast<py::ssize_t>(r.t.size())}, self);
      })
      .def_property_readonly("states", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.states, {static_cast<py::ssize_t>(r.t.size()), 2 * r.dof - 1}, self);
      })
      .def_property_readonly("top_angle", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.top_angle, {static_cast<py::ssize_t>(r.t.size())}, self);
      })
      .def_property_readonly("work_input", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.work_input, {static_cast<py::ssize_t>(r.t.size())}, self);
      })
      .def_property_readonly("viscous_loss", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.viscous_loss, {static_cast<py::ssize_t>(r.t.size())}, self);
      })
      .def_property_readonly("friction_loss", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.friction_loss, {static_cast<py::ssize_t>(r.t.size())}, self);
      })
      .def_property_readonly("energy", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.energy, {static_cast<py::ssize_t>(r.t.size())}, self);
      })
      .def_property_readonly("modes", [](py::object self) {
        const auto& r = self.cast<const Result&>();
        return view(r.modes, {static_cast<py::ssize_t>(r.t.size())}, self);
      })
      .def_property_readonly("switches", [](const Result& r) {
        py::list out;
        for (const auto& s : r.switches) {
          py::dict d;
          d["t"] = s.t;
          d["kind"] = switch_kind_name(s.kind);
          d["direction"] = s.direction;
          d["reaction_torque"] = s.reaction;
          d["root_residual"] = s.root_residual;
          out.append(d);
        }
        return out;
      })
      .def_property_readonly("stats", [](const Result& r) { return stats_dict(r.stats); })
      .def_property_readonly("summary", [](const Result& r) { return summary_dict(r.summary); });

  m.def(
      "simulate",
      [](const Params& p, double wob, double torque, const SimulationOptions& o) {
        // Ctrl-C: the run asks Python's signal handlers every 0.1 s. A handler that raises,
        // as the default KeyboardInterrupt does, stops the run; its exception is re-raised.
        SimulationOptions opt = o;
        // Only the main thread's run asks: elsewhere (Dask's worker threads) the answer is
        // always no, and taking the GIL to hear it could wait on a busy event loop.
        const py::module_ threading = py::module_::import("threading");
        if (threading.attr("current_thread")().is(threading.attr("main_thread")())) {
          opt.interrupt = [] {
            py::gil_scoped_acquire gil;
            return PyErr_CheckSignals() != 0;
          };
        }
        std::shared_ptr<Result> result;
        try {
          // The integration holds no Python objects: let other threads run.
          py::gil_scoped_release release;
          result = std::make_shared<Result>(simulate(p, wob, torque, opt));
        } catch (const Interrupted&) {
          throw py::error_already_set();  // what the handler raised, KeyboardInterrupt
        }
        return result;
      },
      py::arg("params"), py::arg("wob"), py::arg("torque"), py::arg("options"));
  m.def("stiffness_ratio", &stiffness_ratio, py::arg("params"));
  py::class_<StiffnessEstimate>(m, "StiffnessEstimate")
      .def_readonly("fastest_decay", &StiffnessEstimate::fastest_decay)
      .def_readonly("fastest_frequency", &StiffnessEstimate::fastest_frequency)
      .def_readonly("fundamental", &StiffnessEstimate::fundamental);
  m.def("estimate_stiffness", &estimate_stiffness, py::arg("params"),
        "Bounds on the fastest decay rate and natural frequency, and the fundamental: what "
        "method='auto' decides on.");
  m.def("mode_names", []() {
    return std::vector<std::string>{mode_name(Mode::SlipPositive), mode_name(Mode::SlipNegative),
                                    mode_name(Mode::Stick), mode_name(Mode::Band)};
  });
}

}  // namespace pydrill::bindings
