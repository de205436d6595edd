// Compiled, not run (ctest compiles.overloads): the calls a C++ program
// naturally writes must pick one overload. stability_at_torque(p, wob, u, {}) was ambiguous
// once an optional interrupt callback joined the overload that takes known crossings.
#include <pydrill/stability.hpp>

#include <functional>
#include <vector>

int main() {
  const pydrill::Params p = pydrill::preset("reduced-scale", 4);
  const std::vector<pydrill::Crossing> known = pydrill::critical_deltas(p);
  const std::function<bool()> never = [] { return false; };
  bool stop = false;
  std::size_t n = 0;
  n += pydrill::stability_at_torque(p, 40.0, 8.3).size();
  n += pydrill::stability_at_torque(p, 40.0, 8.3, {}).size();
  n += pydrill::stability_at_torque(p, 40.0, 8.3, nullptr).size();
  n += pydrill::stability_at_torque(p, 40.0, 8.3, never).size();
  n += pydrill::stability_at_torque(p, 40.0, 8.3, [&] { return stop; }).size();
  n += pydrill::stability_at_torque(p, known, 40.0, 8.3).size();
  n += pydrill::stability_at_torque(p, known, 40.0, 8.3, {}).size();
  n += pydrill::stability_at_torque(p, known, 40.0, 8.3, [&] { return stop; }).size();
  n += pydrill::critical_deltas(p, {}).size() + pydrill::critical_deltas(p, nullptr).size();
  n += pydrill::structured_eigenvalues(p, 0.01, {}).size();
  n += pydrill::stability_at_velocity(p, 40.0, 30.0, {}).eigenvalues.size();
  std::vector<std::complex<double>> roots;
  n += pydrill::roots_of_impedance(p, 0.01, roots, {}) ? 1U : 0U;
  return n > 0 ? 0 : 1;
}
