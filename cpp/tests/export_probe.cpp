// A shared library of a user's that links pydrill::pydrill (ctest exported_symbols reads
// its exports): a static libpydrill inside it must add none of its own, as in the Python
// module. It calls into most of the library so that most objects are linked in.
#include <pydrill/simulator.hpp>
#include <pydrill/stability.hpp>

__attribute__((visibility("default"))) int pydrill_export_probe() {
  const pydrill::Params p = pydrill::preset("reduced-scale", 4);
  pydrill::SimulationOptions o;
  o.t_end = 1.0;
  for (pydrill::Method m : {pydrill::Method::DOP853, pydrill::Method::BDF, pydrill::Method::ERK}) {
    o.method = m;
    pydrill::simulate(p, 100.0, 8.3, o);
  }
  return static_cast<int>(pydrill::stability_at_torque(p, 40.0, 8.3).size());
}
