"""Time and Duration: genpy semantics, checked on examples, against an
integer-nanosecond model (hypothesis), and against real genpy."""

from __future__ import annotations

import copy
import json
import math
import pickle

import pytest
from hypothesis import given
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesError
from ddes.time import (
    DAY,
    HOUR,
    MILLISECOND,
    NANOSECOND,
    SECOND,
    Duration,
    Time,
    WallDuration,
    WallTime,
)

from .tvalops import EVAL_SOURCE, random_cases

NS = 1_000_000_000


# -- the reference's observed examples (ros1-semantics.md §3.1) ------------------

def test_reference_examples() -> None:
    d = Duration.from_sec(-1.5)
    assert (d.secs, d.nsecs) == (-2, 500_000_000)
    t = Time(1, -1)
    assert (t.secs, t.nsecs) == (0, 999_999_999)
    with pytest.raises(TypeError):
        Time(0, -1)
    with pytest.raises(TypeError):
        Time(1) + Time(2)  # type: ignore[operator]
    with pytest.raises(TypeError):
        Time(1) * 2  # type: ignore[operator]
    with pytest.raises(TypeError):
        assert Time(1) < Duration(2)  # type: ignore[operator]
    assert (Time(1) == Duration(1)) is False
    with pytest.raises(ValueError):
        Time(1.5, 3)
    assert Duration(3) / Duration(2) == 1.5
    assert Duration(3) // Duration(2) == 1
    assert Time(1) - Time(2) == Duration(-1, 0)


def test_float_seconds_truncate_to_ns() -> None:
    assert Time(1.5) == Time(1, 500_000_000)
    assert Duration(-0.25).to_nsec() == -250_000_000
    assert Time.from_seconds(2.0) == Time(2)


def test_conversions_bool_str_repr_hash() -> None:
    t = Time(3, 5)
    assert t.to_nsec() == 3 * NS + 5
    assert t.to_sec() == pytest.approx(3.000000005)
    assert str(t) == "3000000005"
    assert repr(t) == "ddes.Time[3000000005]"
    assert repr(Duration(-1)) == "ddes.Duration[-1000000000]"
    assert not Time() and Time(0, 1)
    assert Duration().is_zero() and not Duration(0, 1).is_zero()
    assert hash(Time(1, 2)) == hash(Time(1, 2))
    assert len({Time(1), Time(1), Time(2)}) == 2


def test_pickle_and_copy() -> None:
    for v in (Time(5, 7), Duration(-3, 2), WallTime(1), WallDuration(2, 3)):
        assert pickle.loads(pickle.dumps(v)) == v
        assert type(pickle.loads(pickle.dumps(v))) is type(v)
        c = copy.deepcopy(v)
        assert c == v and c is not v
        assert copy.copy(v) == v


def test_time_algebra_kinds() -> None:
    assert Time(1) + Duration(2) == Time(3)
    assert Duration(2) + Time(1) == Time(3)
    assert Time(5) - Duration(2) == Time(3)
    assert isinstance(Time(5) - Time(2), Duration)
    assert -Duration(1, 5) == Duration(-2, 999_999_995)
    assert abs(Duration(-2)) == Duration(2)
    assert Duration(1) * 3 == Duration(3)
    assert 3 * Duration(1) == Duration(3)
    assert Duration(1) * 0.5 == Duration(0, 500_000_000)
    assert Duration(7) // 2 == Duration(3)
    assert Duration(7) % Duration(2) == Duration(1)
    assert divmod(Duration(7), Duration(2)) == (3, Duration(1))
    with pytest.raises(TypeError):
        Time(1) - 1  # type: ignore[operator]
    with pytest.raises(TypeError):
        Time(1) - Duration(2)  # negative time


def test_wall_and_ros_kinds_do_not_mix() -> None:
    with pytest.raises(TypeError):
        Time(1) + WallDuration(1)  # type: ignore[operator]
    with pytest.raises(TypeError):
        assert WallTime(1) < Time(2)  # type: ignore[operator]
    assert (WallTime(1) == Time(1)) is False
    assert WallTime(1) + WallDuration(1) == WallTime(2)
    assert WallTime(3) - WallTime(1) == WallDuration(2)


def test_constants() -> None:
    assert NANOSECOND.to_nsec() == 1
    assert MILLISECOND * 1000 == SECOND
    assert HOUR * 24 == DAY
    assert Time.MAX > Time.MIN > Time.ZERO  # type: ignore[attr-defined]
    assert Duration.MIN < Duration.ZERO < Duration.MAX  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    "make, exc, fragment",
    [
        (lambda: Time(float("nan")), ValueError, "nan"),
        (lambda: Duration(float("inf")), ValueError, "inf"),
        (lambda: Time("3"), TypeError, "'3'"),
        (lambda: Duration(1, 2.5), TypeError, "2.5"),
        (lambda: Time(-1), TypeError, "must be positive"),
        (lambda: Duration.from_sec(None), TypeError, "None"),  # type: ignore[arg-type]
        (lambda: Time.now(), ddes.ROSInitException, "node.get_rostime"),
    ],
)
def test_bad_values_raise_typed_errors(make, exc, fragment) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(exc) as info:
        make()
    assert isinstance(info.value, DdesError)
    assert fragment in str(info.value)


# -- hypothesis: the algebra against a plain integer-nanosecond model ---------------

ns_st = st.integers(min_value=-(10**12), max_value=10**12)
pos_ns = st.integers(min_value=0, max_value=10**12)


@given(ns_st, ns_st)
def test_duration_sum_difference_model(a: int, b: int) -> None:
    da, db = Duration.from_nsec(a), Duration.from_nsec(b)
    assert (da + db).to_nsec() == a + b
    assert (da - db).to_nsec() == a - b
    assert (-da).to_nsec() == -a
    assert abs(da).to_nsec() == abs(a)
    assert (da < db) == (a < b) and (da <= db) == (a <= b) and (da == db) == (a == b)
    assert 0 <= da.nsecs < NS


@given(pos_ns, ns_st)
def test_time_plus_duration_model(t: int, d: int) -> None:
    tt, dd = Time.from_nsec(t), Duration.from_nsec(d)
    if t + d < 0:
        with pytest.raises(TypeError):
            tt + dd
    else:
        assert (tt + dd).to_nsec() == t + d
        assert ((tt + dd) - tt).to_nsec() == d


@given(st.integers(-(10**6), 10**6), st.integers(-(10**10), 10**10))
def test_constructor_canonical_form(secs: int, nsecs: int) -> None:
    d = Duration(secs, nsecs)
    assert d.to_nsec() == secs * NS + nsecs
    assert 0 <= d.nsecs < NS
    if secs * NS + nsecs >= 0:
        assert Time(secs, nsecs).to_nsec() == secs * NS + nsecs
    else:
        with pytest.raises(TypeError):
            Time(secs, nsecs)


@given(ns_st, st.integers(-1000, 1000))
def test_integer_multiplication_is_exact(a: int, k: int) -> None:
    assert (Duration.from_nsec(a) * k).to_nsec() == a * k


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_from_sec_truncates_like_genpy(f: float) -> None:
    secs = int(f)
    nsecs = int((f - secs) * 1_000_000_000)
    assert Duration.from_sec(f).to_nsec() == secs * NS + nsecs
    assert math.isclose(Duration.from_sec(f).to_sec(), f, abs_tol=2e-9)


# -- against real genpy ------------------------------------------------------------------

def _ddes_eval(cases: list) -> list:  # type: ignore[type-arg]
    namespace: dict = {}  # type: ignore[type-arg]
    exec(EVAL_SOURCE, namespace)
    return namespace["evaluate"](cases, Time, Duration)  # type: ignore[no-any-return]


def test_eval_harness_runs_locally() -> None:
    out = _ddes_eval([["add", ["Time", 1, 0], ["Duration", 2, 5]], ["add", ["Time", 1, 0], ["Time", 1, 0]]])
    assert out == [["Time", 3, 5], ["error", "TypeError"]]


@pytest.mark.ros
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_agrees_with_genpy_on_random_operations(ros_python, seed: int) -> None:  # type: ignore[no-untyped-def]
    cases = random_cases(seed, 3000)
    script = (
        EVAL_SOURCE
        + "\nimport json, sys\nfrom genpy import Time, Duration\n"
        + "print(json.dumps(evaluate(json.load(sys.stdin), Time, Duration)))\n"
    )
    theirs = ros_python(script, as_json=True, stdin=json.dumps(cases))
    ours = _ddes_eval(json.loads(json.dumps(cases)))
    mismatches = [(c, o, t) for c, o, t in zip(cases, ours, theirs) if o != t]
    assert not mismatches[:5], f"{len(mismatches)} mismatches, first: {mismatches[:5]}"
