// Compiled, not run (ctest compiles.names): pydrill's names beside the
// standard library's, as a short program brings both in. A `pydrill::complex` alias made
// complex<double> ambiguous after `using namespace std; using namespace pydrill;`.
#include <pydrill/equilibrium.hpp>
#include <pydrill/model.hpp>
#include <pydrill/simulator.hpp>
#include <pydrill/stability.hpp>
#include <pydrill/version.hpp>

#include <complex>
#include <vector>

using namespace std;
using namespace pydrill;

int main() {
  const Params p = preset("reduced-scale", 4);
  const complex<double> z = bit_impedance(p, complex<double>(0.0, 1.0));
  const vector<complex<double>> ev = eigenvalues(p, 0.01);
  return abs(z) > 0 && !ev.empty() ? 0 : 1;
}
