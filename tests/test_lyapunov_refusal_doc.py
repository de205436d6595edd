"""Crossing.lyapunov's docstring (and docs/api.md, made from it) said nothing of a refusal,
though first_lyapunov_coefficient refuses a pair whose i·frequency lies more than 1 % of the
frequency from every eigenvalue at delta (commit f09d4d0): the docstring says so, and the rule
it states holds against LAPACK's eigenvalues of the same string."""

import inspect
import math
from pathlib import Path

import numpy as np
import pytest

import pydrill
from pydrill import stability as st

API = Path(__file__).resolve().parents[1] / "docs" / "api.md"


def _said(text: str) -> str:
    return " ".join(text.split())


def test_the_docstring_and_the_reference_say_a_non_hopf_pair_is_refused():
    doc = _said(inspect.getdoc(st.Crossing.lyapunov))
    for words in ("ValueError", "more than 1 % of the frequency", "critical_deltas"):
        assert words in doc, doc
    assert "refused" in _said(inspect.getdoc(st.Crossing.criticality))
    assert "more than 1 % of the frequency from every eigenvalue" in _said(API.read_text())


@pytest.mark.parametrize(("scale", "refused"), [(1.005, False), (1.02, True), (1.5, True)])
def test_the_stated_rule_holds(scale, refused):
    """A Hopf crossing's frequency moved by 0.5 % passes, by 2 % or 50 % is refused: the
    distance to the nearest eigenvalue, from numpy, is what the docstring's 1 % measures."""
    p = pydrill.preset("reduced-scale", dof=4)
    hopf = next(c for c in st.critical_deltas(p) if c.type == "hopf")
    w = hopf.frequency * scale
    nearest = np.min(np.abs(st.eigenvalues(p, hopf.delta) - 1j * w))
    assert (nearest > 0.01 * w) == refused  # (independent of the core's Newton estimate)
    moved = st.Crossing("hopf", hopf.delta, w, hopf.direction, hopf.multiplicity)
    if refused:
        with pytest.raises(ValueError, match="are not a Hopf point"):
            moved.lyapunov(p)
        with pytest.raises(ValueError, match="are not a Hopf point"):
            moved.criticality(p)
    else:
        assert math.isfinite(moved.lyapunov(p))
