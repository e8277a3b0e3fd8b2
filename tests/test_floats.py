"""ddes._floats.left_sum: the same bits on every Python (sum() compensates from 3.12)."""

from __future__ import annotations

import functools
import operator

from hypothesis import given
from hypothesis import strategies as st

from ddes._floats import left_sum


def test_no_compensation() -> None:
    # 1e16 + 1.0 rounds back to 1e16, so left to right the 1.0 is lost; a compensated sum
    # (Python 3.12's sum()) gives 1.0
    assert left_sum([1e16, 1.0, -1e16]) == 0.0
    assert left_sum([]) == 0.0 and left_sum(iter([0.5])) == 0.5


def test_a_negative_zero_sums_to_zero_as_python_sum_did() -> None:
    assert str(left_sum([-0.0])) == "0.0"


@given(st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), max_size=30))
def test_left_to_right_from_zero(values: list[float]) -> None:
    want = functools.reduce(operator.add, values, 0.0)
    assert left_sum(values).hex() == want.hex()
