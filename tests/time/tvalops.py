"""Randomized Time/Duration operations, evaluated the same way on ddes and on genpy.

``EVAL_SOURCE`` is plain Python run both here (with ddes's classes) and under
real ROS's system Python (with genpy's), so the two results can be compared
case by case.
"""

from __future__ import annotations

import random
from typing import Any

EVAL_SOURCE = r'''
def _enc(v, Time, Duration):
    if isinstance(v, Time):
        return ["Time", v.secs, v.nsecs]
    if isinstance(v, Duration):
        return ["Duration", v.secs, v.nsecs]
    if isinstance(v, bool):
        return ["bool", v]
    if isinstance(v, int):
        return ["int", v]
    if isinstance(v, float):
        return ["float", repr(v)]
    if isinstance(v, tuple):
        return ["tuple"] + [_enc(x, Time, Duration) for x in v]
    if isinstance(v, str):
        return ["str", v]
    return ["other", type(v).__name__]

def _mk(spec, Time, Duration):
    kind, a, b = spec
    cls = Time if kind == "Time" else Duration
    if kind in ("Time", "Duration"):
        return cls(a, b)
    if kind == "TimeF":
        return Time(a)
    if kind == "DurationF":
        return Duration(a)
    if kind == "TimeFS":
        return Time.from_sec(a)
    if kind == "DurationFS":
        return Duration.from_sec(a)
    return a

def evaluate(cases, Time, Duration):
    import operator
    ops = {
        "add": operator.add, "sub": operator.sub, "mul": operator.mul,
        "truediv": operator.truediv, "floordiv": operator.floordiv, "mod": operator.mod,
        "divmod": divmod, "lt": operator.lt, "le": operator.le, "gt": operator.gt,
        "ge": operator.ge, "eq": operator.eq, "ne": operator.ne,
    }
    out = []
    for case in cases:
        op = case[0]
        try:
            if op == "make":
                r = _mk(case[1], Time, Duration)
            elif op in ops:
                r = ops[op](_mk(case[1], Time, Duration), _mk(case[2], Time, Duration))
            elif op == "neg":
                r = -_mk(case[1], Time, Duration)
            elif op == "abs":
                r = abs(_mk(case[1], Time, Duration))
            elif op == "bool":
                r = bool(_mk(case[1], Time, Duration))
            elif op == "to_sec":
                r = _mk(case[1], Time, Duration).to_sec()
            elif op == "to_nsec":
                r = _mk(case[1], Time, Duration).to_nsec()
            elif op == "str":
                r = str(_mk(case[1], Time, Duration))
            elif op == "hash_eq":
                r = hash(_mk(case[1], Time, Duration)) == hash(_mk(case[2], Time, Duration))
            elif op == "is_zero":
                r = _mk(case[1], Time, Duration).is_zero()
            else:
                raise AssertionError(op)
            out.append(_enc(r, Time, Duration))
        except AttributeError:
            out.append(["error", "AttributeError"])
        except (TypeError, ValueError, ZeroDivisionError, OverflowError) as e:
            base = [c.__name__ for c in type(e).__mro__ if c.__name__ in
                    ("TypeError", "ValueError", "ZeroDivisionError", "OverflowError")]
            out.append(["error", base[0]])
    return out
'''


def _value(rng: random.Random) -> list[Any]:
    kind = rng.choice(["Time", "Duration", "Duration", "TimeF", "DurationF", "TimeFS",
                       "DurationFS", "int", "float"])
    big = rng.random() < 0.2
    if kind in ("Time", "Duration"):
        secs = rng.randint(-5, 2**31 if big else 50)
        nsecs = rng.randint(-3_000_000_000, 3_000_000_000)
        return [kind, secs, nsecs]
    if kind in ("TimeF", "DurationF", "TimeFS", "DurationFS"):
        return [kind, round(rng.uniform(-3, 1e6 if big else 100), rng.randint(0, 9)), 0]
    if kind == "int":
        return ["int", rng.randint(-5, 5), 0]
    return ["float", rng.choice([0.5, 1.5, -2.25, 3.0, 1e-3, 7.0]), 0]


def random_cases(seed: int, n: int) -> list[list[Any]]:
    """``n`` random operations (deterministic for a seed)."""
    rng = random.Random(seed)
    unary = ["make", "neg", "abs", "bool", "to_sec", "to_nsec", "str", "is_zero"]
    binary = ["add", "sub", "mul", "truediv", "floordiv", "mod", "divmod", "lt", "le", "gt",
              "ge", "eq", "ne", "hash_eq"]
    cases: list[list[Any]] = []
    for _ in range(n):
        if rng.random() < 0.35:
            cases.append([rng.choice(unary), _value(rng)])
        else:
            cases.append([rng.choice(binary), _value(rng), _value(rng)])
    return cases
