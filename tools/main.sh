#!/usr/bin/env bash
# The main job on the built-in defaults, after installing whatever is missing:
#   1. the paper's (W_ob, u) regime map for the 4-DOF laboratory string, swept with Dask on
#      this machine's cores into an HDF5 atlas (out/paper-atlas.h5), and its figures;
#   2. the paper's Fig. 4 stick-slip case simulated, summarised and drawn.
#   3. `pydrill reproduce`: the paper's Sections 3-4 recomputed into out/paper/report.md.
# Everything goes to out/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
bash tools/setup.sh
export PATH="$root/.venv/bin:$PATH"
mkdir -p out
# A fresh atlas each run (pydrill itself never overwrites an atlas of another spec).
rm -f out/paper-atlas.h5 out/paper-atlas.h5.journal
pydrill sweep sweeps/paper-wob-torque.toml --out out/paper-atlas.h5 --plot out/regimes-rest.png
pydrill atlas plot out/paper-atlas.h5 --initial equilibrium --out out/regimes-equilibrium.png
pydrill atlas plot out/paper-atlas.h5 --metric severity --out out/severity-rest.png
pydrill atlas plot out/paper-atlas.h5 --metric spectral_abscissa --out out/growth-rate.png
pydrill atlas plot out/paper-atlas.h5 --profile --x torque --set wob=100 --out out/profile-torque.png
pydrill atlas info out/paper-atlas.h5
# The driller's answer from the atlas: at each surface torque, the weights on bit that drill
# steadily from rest and from equilibrium with a stable steady state.
pydrill atlas safe out/paper-atlas.h5 > out/safe-windows.txt
pydrill atlas safe out/paper-atlas.h5 --set torque=8.5
pydrill map --dof 4 --plot out/operating-map.png > /dev/null
pydrill hopf --dof 4 --plot out/hopf-boundaries.png > /dev/null
pydrill bifurcation --dof 2 --vary wob --torque 8.1 --plot out/bifurcation.png > /dev/null
pydrill simulate --preset reduced-scale --dof 4 --wob 100 --torque 8.3 --t-end 300 \
  --json --plot out/stick-slip.png > out/stick-slip.json
pydrill simulate --preset reduced-scale --dof 4 --wob 100 --torque 8.3 --t-end 300
# The paper's Sections 3-4 recomputed with a report (a minute or two from scratch, README.md
# gives the time measured; less when out/paper/ already holds its atlases and analyses).
pydrill reproduce --out out/paper --no-progress
echo "wrote out/: paper-atlas.h5, regimes-rest.png, regimes-equilibrium.png, severity-rest.png,"
echo "            growth-rate.png, profile-torque.png, safe-windows.txt, operating-map.png,"
echo "            hopf-boundaries.png, bifurcation.png, stick-slip.png, stick-slip.json,"
echo "            paper/report.md and its figures"
