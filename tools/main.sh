#!/usr/bin/env bash
# The main job on the built-in defaults, after installing whatever is missing:
# the paper's stick-slip case (reduced-scale string, dof 4, W_ob = 100 N, u = 8.3 N m)
# simulated from rest, its summary as JSON, and its figure. Results go to out/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
bash tools/setup.sh
export PATH="$root/.venv/bin:$PATH"
mkdir -p out
pydrill simulate --preset reduced-scale --dof 4 --wob 100 --torque 8.3 --t-end 300 \
  --json --plot out/stick-slip.png > out/stick-slip.json
pydrill simulate --preset reduced-scale --dof 4 --wob 100 --torque 8.3 --t-end 300
echo "wrote out/stick-slip.json and out/stick-slip.png"
