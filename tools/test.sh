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
# One pytest worker per core it may use, at most 4 (pytest-xdist): alone, pytest keeps one
# core busy and the other mostly idle (measured on 2 cores: 17 min serial). PYDRILL_TEST_JOBS
# sets the count (0: no workers, every test in this process); "-n N" among the arguments too.
jobs=${PYDRILL_TEST_JOBS:-$(python -c 'import os; print(min(4, len(os.sched_getaffinity(0))))')}
python -m pytest -n "$jobs" "$@" || status=1
exit $status
