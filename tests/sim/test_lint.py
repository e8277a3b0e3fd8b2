"""ddes/sim keeps the trace path bit-exact: an AST scan for what differs between machines.

Refused in every module of ddes/sim: numpy (its transcendental functions use SIMD dispatch
that differs by up to 4 ulp between CPUs, its RNG streams are promised only per build and
machine, its reductions and BLAS change summation order), libm's transcendental functions
(``math.sin``, ``math.atan2``, ``math.exp`` ..., whose last bit differs between C libraries),
the ``@`` operator, the global ``random`` functions, ``hash()``, ``time``/``datetime``, and the
builtin ``sum()`` (from Python 3.12 it compensates the rounding of float sums, so the same sum
has other last bits on 3.11 and 3.12: sums are written as left-to-right additions from 0.0).
``math.sqrt`` (correctly rounded by IEEE 754), ``floor``/``ceil``/``copysign``/``isfinite``
and the trig of ``ddes.transformations`` are allowed.
"""

from __future__ import annotations

import ast
from pathlib import Path

import ddes.sim

ROOT = Path(ddes.sim.__file__).resolve().parent
MATH_ALLOWED = {"sqrt", "floor", "ceil", "copysign", "isfinite", "isnan", "isinf", "fabs", "inf",
                "nan", "pi", "tau", "e"}
BANNED_MODULES = {"numpy", "scipy", "time", "datetime", "cmath"}
BANNED_RANDOM = {"random", "uniform", "gauss", "normalvariate", "seed", "choice", "shuffle",
                 "randint", "sample", "getrandbits", "lognormvariate", "expovariate"}


def problems(source: str, where: str) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(source)):
        line = f"{where}:{getattr(node, 'lineno', 0)}"
        if isinstance(node, ast.Import):
            found += [f"{line} import {a.name}" for a in node.names
                      if a.name.split(".")[0] in BANNED_MODULES]
        elif isinstance(node, ast.ImportFrom):
            mod = (node.module or "").split(".")[0]
            if mod in BANNED_MODULES:
                found.append(f"{line} from {node.module} import")
            if mod == "math":
                found += [f"{line} from math import {a.name}" for a in node.names
                          if a.name not in MATH_ALLOWED]
            if mod == "random":
                found += [f"{line} from random import {a.name}" for a in node.names
                          if a.name in BANNED_RANDOM]
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            if node.value.id == "math" and node.attr not in MATH_ALLOWED:
                found.append(f"{line} math.{node.attr}")
            if node.value.id in ("np", "numpy"):
                found.append(f"{line} {node.value.id}.{node.attr}")
            if node.value.id == "random" and node.attr in BANNED_RANDOM:
                found.append(f"{line} random.{node.attr} (the global generator)")
        elif isinstance(node, (ast.BinOp, ast.AugAssign)) and isinstance(node.op, ast.MatMult):
            found.append(f"{line} @ (BLAS)")
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
              and node.func.id in ("hash", "sum")):
            found.append(f"{line} {node.func.id}()")
    return found


def test_ddes_sim_has_no_machine_dependent_math() -> None:
    files = sorted(ROOT.rglob("*.py"))
    assert len(files) >= 5
    found = [p for f in files for p in problems(f.read_text(), str(f.relative_to(ROOT.parent)))]
    assert found == []


def test_the_scan_catches_each_kind() -> None:
    bad = """
import numpy as np
from math import atan2
import math, random
x = np.sin(1.0) + math.exp(2.0) + random.random()
y = a @ b
z = hash("k")
w = sum(x * x for x in (0.1, 0.2))
"""
    found = problems(bad, "x.py")
    assert any("import numpy" in p for p in found) and any("from math import atan2" in p
                                                          for p in found)
    for words in ("np.sin", "math.exp", "random.random", "@ (BLAS)", "hash()", "sum()"):
        assert any(words in p for p in found), words
    assert problems("import math\nr = math.sqrt(2.0)\n", "ok.py") == []
