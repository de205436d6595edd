""" "Did you mean …?": one edit away, checked against every string one edit makes."""

import itertools
import random

import pytest

from pydrill.suggest import _one_edit, did_you_mean


def _edits(word: str, alphabet: str) -> set[str]:
    """Every string one edit from ``word``: a letter deleted, inserted or changed, or two
    neighbours swapped (brute force)."""
    out = set()
    for k in range(len(word) + 1):
        out.add(word[:k] + word[k + 1 :])
        out.update(word[:k] + c + word[k:] for c in alphabet)
        out.update(word[:k] + c + word[k + 1 :] for c in alphabet if k < len(word))
        if k + 1 < len(word):
            out.add(word[:k] + word[k + 1] + word[k] + word[k + 2 :])
    out.discard(word)
    return out


def test_one_edit_is_exactly_the_strings_one_edit_makes():
    rng = random.Random(0)
    alphabet = "abc"
    words = ["".join(w) for n in range(5) for w in itertools.product(alphabet, repeat=n)]
    for a in rng.sample(words, 60):
        near = _edits(a, alphabet)
        for b in words:
            assert _one_edit(a, b) == (b in near), (a, b)


@pytest.mark.parametrize(
    ("name", "choices", "meant"),
    [
        ("bfd", ["auto", "dop853", "bdf", "adams", "erk"], "bdf"),  # two letters swapped
        ("torqe", ["wob", "torque"], "torque"),
        ("Torque", ["wob", "torque"], "torque"),
        ("t_ned", ["t_end", "initial"], "t_end"),
        ("speed", ["t_end", "initial", "friction"], None),
        ("x", ["y", "z"], None),
    ],
)
def test_did_you_mean(name, choices, meant):
    assert did_you_mean(name, choices) == (f" (did you mean {meant!r}?)" if meant else "")
