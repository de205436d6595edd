"""What the API fuzz tests share: hypothesis's settings and the inputs thrown at every number.

Not a test module: imported by them (``pythonpath = ["tests"]`` in pyproject.toml)."""

import math

import numpy as np
from hypothesis import settings
from hypothesis import strategies as st

FUZZ = settings(derandomize=True, max_examples=60, deadline=None)

#: numbers at and past every edge: the floats' ends, subnormals, integers beyond a float
EXTREMES = [
    *(math.nan, math.inf, -math.inf, 0.0, -0.0, -1.0, 5e-324, 1e-308, 1e-300),
    *(1e15, 1e16, 1e300, 1e308, -1e308, 10**400, -(10**400), 2**63),
]
numbers = st.one_of(
    st.sampled_from(EXTREMES),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**20), max_value=10**20),
)
#: anything a caller might pass for a number: numpy scalars, 0-d and 1-d arrays, wrong types
values = st.one_of(
    numbers,
    st.floats(allow_nan=True, allow_infinity=True).map(np.float64),
    st.floats(width=32).map(np.float32),
    numbers.filter(lambda v: abs(v) < 2**63 or v != v).map(np.asarray),
    st.sampled_from([None, "abc", "", "8.3", "100 N", "1e999 N", b"1", [], [1.0], (2.0,)]),
    st.sampled_from([True, 1 + 2j, np.complex128(1), {}, {1.0}, np.array([1.0, 2.0])]),
)
