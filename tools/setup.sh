#!/usr/bin/env bash
# Makes a Debian machine ready for pydrill, doing only what is missing:
#   1. Debian packages (SUNDIALS, Catch2, a C++ compiler) through apt-get when root,
#      or a clear message saying what to install otherwise;
#   2. a virtual environment in .venv with the build tools and test dependencies;
#   3. the build: the Python package (editable, so edits to pydrill/ take effect at once;
#      the C++ extension rebuilds incrementally) and, with --cpp, the C++ library, tests
#      and example in build/cpp for ctest.
# Safe to run again and again; the README's two commands call it.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
want_cpp=0
for arg in "$@"; do
  case "$arg" in
    --cpp) want_cpp=1 ;;
    *) echo "setup.sh: unknown option $arg" >&2; exit 2 ;;
  esac
done
say() { printf '\033[1m[setup]\033[0m %s\n' "$*" >&2; }

# --- 1. Debian packages ---------------------------------------------------------------
python=${PYTHON:-python3}
packages=(libsundials-dev libeigen3-dev catch2 g++ make)
if ! "$python" -c 'import venv, ensurepip' >/dev/null 2>&1; then packages+=(python3-venv); fi
if ! "$python" -c 'import sysconfig, os, sys; sys.exit(not os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h")))' >/dev/null 2>&1; then
  packages+=(python3-dev)
fi
# For the tests (--cpp) only, and only where it can be installed: Debian's netCDF-C tools,
# whose ncdump tests/test_atlas_netcdf.py reads atlases with (skipped without it).
if ((want_cpp)) && { [ "$(id -u)" = 0 ] || { command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; }; }; then
  packages+=(netcdf-bin)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [ "$(id -u)" = 0 ]; then
    say "installing Debian packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    say "installing Debian packages with sudo: ${missing[*]}"
    sudo DEBIAN_FRONTEND=noninteractive apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  else
    echo "pydrill needs these Debian packages, which are not installed: ${missing[*]}" >&2
    echo "Install them as root, then run this command again:" >&2
    echo "    sudo apt-get install ${missing[*]}" >&2
    exit 1
  fi
fi

# --- 2. virtual environment -----------------------------------------------------------
venv="$root/.venv"
if [ ! -x "$venv/bin/python" ]; then
  say "creating the virtual environment $venv"
  "$python" -m venv "$venv"
fi
stamp="$venv/.pydrill-deps"
deps_hash=$(sha1sum pyproject.toml tools/setup.sh | sha1sum | cut -c1-16)
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$deps_hash" ]; then
  say "installing build tools and dependencies into .venv"
  "$venv/bin/python" -m pip install -q --upgrade pip
  "$venv/bin/python" -m pip install -q "scikit-build-core>=0.10" "pybind11>=2.10" "cmake>=3.18" ninja
  # The runtime and test dependencies declared in pyproject.toml.
  "$venv/bin/python" - <<'PY' > "$venv/.pydrill-requirements.txt"
import tomllib
meta = tomllib.load(open("pyproject.toml", "rb"))["project"]
reqs = list(meta["dependencies"])
for extra in ("test", "dashboard"):
    reqs += [r for r in meta.get("optional-dependencies", {}).get(extra, []) if not r.startswith("pydrill")]
reqs.append("ruff>=0.5")
print("\n".join(reqs))
PY
  "$venv/bin/python" -m pip install -q -r "$venv/.pydrill-requirements.txt"
  echo "$deps_hash" > "$stamp"
fi

# --- 3. build -------------------------------------------------------------------------
say "building pydrill (Python package + C++ extension)"
PATH="$venv/bin:$PATH" "$venv/bin/python" -m pip install -q --no-build-isolation --no-deps -e . 2>&1 \
  | grep -v "^WARNING: Location" || true
"$venv/bin/python" -c "import pydrill" || { echo "pydrill failed to build or import" >&2; exit 1; }

if ((want_cpp)); then
  say "building the C++ library, tests and example (build/cpp)"
  PATH="$venv/bin:$PATH" cmake -S . -B build/cpp -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  PATH="$venv/bin:$PATH" cmake --build build/cpp -j "$(nproc)"
fi
