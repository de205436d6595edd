"""What pydrill ships and what it says about its types: the sdist holds every file git tracks
and none of what runs and builds leave in a checkout; pydrill/_core.pyi matches the compiled
core (mypy's stubtest for names and kinds, pybind11's docstrings for parameters); the package
passes mypy with the settings in pyproject.toml; its versions agree. (Installing the sdist
into a new environment, and running it from elsewhere, is checked by hand: it builds the C++
core, minutes, not for the suite.)"""

from __future__ import annotations

import ast
import importlib.metadata
import importlib.util
import inspect
import re
import shutil
import subprocess
import sys
import tarfile
import tomllib
from pathlib import Path

import pytest

import pydrill

ROOT = Path(__file__).resolve().parents[1]

#: What an sdist cannot build or install without.
REQUIRED = [
    "PKG-INFO",
    "pyproject.toml",
    "CMakeLists.txt",
    "README.md",
    "LICENSE",
    "pydrill/__init__.py",
    "pydrill/py.typed",
    "pydrill/_core.pyi",
    "cpp/cmake/version.hpp.in",
]

#: What runs, builds and tools leave in a checkout; none of it may reach the sdist.
PLANTED = [
    "dist/pydrill-0.0.0.tar.gz",
    "out/paper/report.md",
    "paper/report.md",
    "paper/cache/fig10a.json",
    "build/cpp/CMakeCache.txt",
    "build/cp311-cp311-linux_x86_64/CMakeCache.txt",
    ".venv/bin/python",
    ".mypy_cache/3.11/pydrill/cli.data.json",
    ".hypothesis/examples/0/1",
    ".pytest_cache/v/cache/lastfailed",
    ".ruff_cache/CACHEDIR.TAG",
    "dask-worker-space/worker-1/storage",
    "pydrill.egg-info/PKG-INFO",
    "pydrill/__pycache__/cli.cpython-311.pyc",
    "tests/__pycache__/conftest.cpython-311.pyc",
    "pydrill/_core.cpython-311-x86_64-linux-gnu.so",
    "minimal.h5",
    "minimal.h5.journal",
    "minimal.h5.lock",
    "sweeps/paper.h5",
    "atlas.nc",
    "regimes.png",
    "table.csv",
    "numbers.json",
]


def _tracked() -> list[str]:
    """The files git tracks in this checkout (those present: one deleted and not yet
    committed is nobody's to ship)."""
    if not (ROOT / ".git").exists() or shutil.which("git") is None:
        pytest.skip("not a git checkout: the sdist is checked against what git tracks")
    out = subprocess.run(
        ["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True
    ).stdout.decode()
    return [name for name in out.split("\0") if name and (ROOT / name).is_file()]


def test_sdist_holds_what_git_tracks_and_no_junk(tmp_path):
    # A copy of the checkout's tracked files with junk planted among them: the sdist is
    # built from that (scikit-build-core reads .gitignore and sdist.exclude, not git), so
    # what lies around in this checkout, or another engineer's files, cannot sway it.
    tracked = _tracked()
    src = tmp_path / "src"
    for name in tracked:
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, src / name)
    for name in PLANTED:
        assert name not in tracked, f"{name} is tracked: plant another name"
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        (src / name).write_text("junk\n")
    dist = tmp_path / "dist"
    build = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys; from scikit_build_core.build import build_sdist;"
            " print(build_sdist(sys.argv[1]))",
            str(dist),
        ],
        cwd=src,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert build.returncode == 0, build.stderr
    sdist = dist / build.stdout.split()[-1]
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert sdist.name == f"pydrill-{version}.tar.gz"
    with tarfile.open(sdist) as tar:
        members = [m.name for m in tar.getmembers() if m.isfile()]
    prefix = f"pydrill-{version}/"
    assert all(m.startswith(prefix) for m in members), members[:5]
    names = {m.removeprefix(prefix) for m in members}

    assert sorted(set(PLANTED) & names) == [], "junk in the sdist"
    assert sorted(set(REQUIRED) - names) == [], "missing from the sdist"
    assert sorted(set(tracked) - names) == [], "tracked, but left out of the sdist"
    assert sorted(names - set(tracked) - {"PKG-INFO"}) == [], "in the sdist, but not tracked"
    assert len(names) < 500 and sdist.stat().st_size < 20e6, (len(names), sdist.stat().st_size)


def test_core_stub_matches_the_compiled_core(tmp_path):
    # stubtest imports pydrill._core and compares it with pydrill/_core.pyi; an allowlist
    # entry that no longer matches anything is an error too (the list stays true). From a
    # directory of its own, as a user's: stubtest takes the installed package (the checkout,
    # installed editable by tools/setup.sh), whose other modules are mypy's business below;
    # from the checkout it would analyse them all again, without pyproject.toml's settings.
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy.stubtest",
            "pydrill._core",
            "--allowlist",
            str(ROOT / "tests" / "stubtest_allowlist.txt"),
        ],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stdout + run.stderr


def _doc_signatures(obj, name: str) -> list[list[tuple[str, bool]]]:
    """The parameters (name, has a default) of each signature pybind11 writes at the top of
    ``obj``'s docstring (one, or one per overload: ``1. name(...) -> ...``)."""
    found = []
    for line in (obj.__doc__ or "").splitlines():
        m = re.match(rf"(?:\d+\. )?{re.escape(name)}\((.*)\) -> ", line)
        if m is None:
            continue
        params, depth, part = [], 0, ""
        for ch in m[1] + ",":
            depth += (ch in "[(") - (ch in "])")
            if ch == "," and depth == 0:
                if part.strip():
                    params.append((part.split(":")[0].strip(), " = " in part))
                part = ""
            else:
                part += ch
        found.append(params)
    return found


def _stub_signatures(defs: list[ast.FunctionDef]) -> list[list[tuple[str, bool]]]:
    out = []
    for d in defs:
        a = d.args
        names = [x.arg for x in a.posonlyargs + a.args]
        has = [False] * (len(names) - len(a.defaults)) + [True] * len(a.defaults)
        kw = [
            (x.arg, dflt is not None) for x, dflt in zip(a.kwonlyargs, a.kw_defaults, strict=True)
        ]
        out.append(list(zip(names, has, strict=True)) + kw)
    return out


def test_core_stub_has_the_cores_parameters():
    # stubtest cannot read a pybind11 function's parameters (inspect.signature fails on
    # them), so it passes a stub whose arguments are wrong; pybind11 writes them at the top
    # of each docstring: the stub's names, order and defaults must be those.
    from pydrill import _core

    tree = ast.parse((ROOT / "pydrill" / "_core.pyi").read_text())

    def defs(body, name):
        return [n for n in body if isinstance(n, ast.FunctionDef) and n.name == name]

    checked = 0
    for name, obj in vars(_core).items():
        if inspect.isclass(obj):
            body = next(
                (n.body for n in tree.body if isinstance(n, ast.ClassDef) and n.name == name), []
            )
            members = [(f"{name}.{m}", v, defs(body, m)) for m, v in vars(obj).items()]
        else:
            members = [(name, obj, defs(tree.body, name))]
        for qual, member, stub in members:
            doc = _doc_signatures(member, qual.rsplit(".", 1)[-1]) if callable(member) else []
            if not doc or not stub:  # no pybind11 signature, or left to stubtest (missing)
                continue
            assert _stub_signatures(stub) == doc, qual
            checked += 1
    assert checked >= 20  # the module's functions and the classes' methods


def test_package_passes_mypy():
    # The files and settings are pyproject.toml's [tool.mypy]; its cache (.mypy_cache) makes
    # a second run take seconds (the first, about 40 s).
    run = subprocess.run(
        [sys.executable, "-m", "mypy"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stdout + run.stderr


def test_code_passes_ruff():
    # The lint rules and the format are pyproject.toml's [tool.ruff]: every Python file in the
    # checkout (package, tests, benchmarks, tools) is checked, as a commit should leave it.
    if importlib.util.find_spec("ruff") is None:
        pytest.skip("ruff is not installed (tools/setup.sh installs it; pip install ruff)")
    for args in (["check", "--no-cache", "."], ["format", "--check", "--no-cache", "."]):
        run = subprocess.run(
            [sys.executable, "-m", "ruff", *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert run.returncode == 0, f"ruff {args[0]}:\n" + run.stdout + run.stderr


def test_versions_agree():
    # pyproject.toml names the distribution's version, CMakeLists.txt the core's (which
    # pydrill.__version__ reports); the installed metadata is pyproject's at install time.
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    cmake = re.search(r"project\(pydrill VERSION (\S+)", (ROOT / "CMakeLists.txt").read_text())
    assert cmake is not None
    assert project == cmake[1] == pydrill.__version__
    assert importlib.metadata.version("pydrill") == pydrill.__version__


def test_package_ships_its_types():
    here = Path(pydrill.__file__).parent
    assert (here / "py.typed").is_file()
    assert (here / "_core.pyi").is_file()
