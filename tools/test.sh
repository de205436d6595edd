#!/usr/bin/env bash
# Every test: the C++ tests (ctest) and the Python tests (pytest), after installing
# whatever is missing (tools/setup.sh). Extra arguments go to pytest.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
bash tools/setup.sh --cpp
export PATH="$root/.venv/bin:$PATH"

status=0
echo "=== ctest ==="
ctest --test-dir build/cpp --output-on-failure -j 2 || status=1
echo "=== pytest ==="
python -m pytest "$@" || status=1
exit $status
