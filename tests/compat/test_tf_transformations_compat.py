"""tf.transformations / tf_conversions.transformations in rospy scripts (ddes.compat.tf).

Each wrapper returns exactly ddes.transformations' values with Noetic's types (float64 arrays,
tuples, floats); scripts import the module under all of tf's spellings; real Noetic agrees on a
list of inputs within 1e-12 and on every return type.
"""

from __future__ import annotations

import inspect
import json
import math
import random
import textwrap
from pathlib import Path
from typing import Any

import numpy
import pytest
from hypothesis import given
from hypothesis import strategies as st

import ddes
from ddes import transformations as T
from ddes.compat.scripts import run_script
from ddes.compat.tf import transformations as tt
from ddes.errors import DdesValueError

angle = st.floats(-7.0, 7.0, allow_nan=False)
coord = st.floats(-5.0, 5.0, allow_nan=False)
quat = st.lists(coord, min_size=4, max_size=4).filter(lambda q: sum(v * v for v in q) > 1e-3)
axes = st.sampled_from(sorted(T._AXES2TUPLE))


def _is_array(value: Any, shape: tuple[int, ...]) -> None:
    assert type(value) is numpy.ndarray
    assert value.dtype == numpy.float64
    assert value.shape == shape


@given(angle, angle, angle, axes, quat, quat, st.floats(0.0, 1.0))
def test_the_wrappers_are_ddes_values_with_noetic_types(ai: float, aj: float, ak: float,
                                                        ax: str, q0: list[float],
                                                        q1: list[float], f: float) -> None:
    m = T.euler_matrix(ai, aj, ak, ax)
    d = [q0[0] + 6.0, q0[1], q0[2]]  # never zero: an axis
    pairs: list[tuple[Any, Any, tuple[int, ...]]] = [
        (tt.euler_matrix(ai, aj, ak, ax), m, (4, 4)),
        (tt.quaternion_from_euler(ai, aj, ak, ax), T.quaternion_from_euler(ai, aj, ak, ax), (4,)),
        (tt.quaternion_matrix(q0), T.quaternion_matrix(q0), (4, 4)),
        (tt.quaternion_from_matrix(m), T.quaternion_from_matrix(m), (4,)),
        (tt.quaternion_multiply(q0, q1), T.quaternion_multiply(q0, q1), (4,)),
        (tt.quaternion_conjugate(q0), T.quaternion_conjugate(q0), (4,)),
        (tt.quaternion_inverse(q0), T.quaternion_inverse(q0), (4,)),
        (tt.quaternion_slerp(q0, q1, f), T.quaternion_slerp(q0, q1, f), (4,)),
        (tt.quaternion_about_axis(ai, q0[:3]), T.quaternion_about_axis(ai, q0[:3]), (4,)),
        (tt.translation_matrix(q0[:3]), T.translation_matrix(q0[:3]), (4, 4)),
        (tt.translation_from_matrix(m), T.translation_from_matrix(m), (3,)),
        (tt.concatenate_matrices(m, m), T.concatenate_matrices(m, m), (4, 4)),
        (tt.inverse_matrix(m), T.inverse_matrix(m), (4, 4)),
        (tt.unit_vector(q0), T.unit_vector(q0), (4,)),
        (tt.identity_matrix(), T.identity_matrix(), (4, 4)),
        (tt.rotation_matrix(ai, d, q1[:3]), T.rotation_matrix(ai, d, q1[:3]), (4, 4)),
        (tt.scale_matrix(f, q1[:3], d), T.scale_matrix(f, q1[:3], d), (4, 4)),
        (tt.compose_matrix(q0[:3], q1[:3], [ai, aj, ak], q1[1:], [0, 0, 0, 1]),
         T.compose_matrix(q0[:3], q1[:3], [ai, aj, ak], q1[1:], [0, 0, 0, 1]), (4, 4)),
        (tt.random_quaternion([f, f / 2, 1 - f]), T.random_quaternion([f, f / 2, 1 - f]), (4,)),
        (tt.random_rotation_matrix([f, 0.3, 0.6]), T.random_rotation_matrix([f, 0.3, 0.6]),
         (4, 4)),
    ]
    for mine, ref, shape in pairs:
        _is_array(mine, shape)
        assert mine.tolist() == ref  # the very bits of ddes.transformations
    e = tt.euler_from_quaternion(q0, ax)
    assert type(e) is tuple and all(type(v) is float for v in e)
    assert e == T.euler_from_quaternion(q0, ax)
    e = tt.euler_from_matrix(tt.euler_matrix(ai, aj, ak, ax), ax)
    assert type(e) is tuple and e == T.euler_from_matrix(m, ax)
    n = tt.vector_norm(q0)
    assert type(n) is float and n == T.vector_norm(q0)
    assert tt.is_same_transform(m, m) is True


@given(st.lists(st.lists(coord, min_size=3, max_size=3), min_size=1, max_size=4)
       .filter(lambda rows: all(sum(v * v for v in r) > 1e-6 for r in rows)))
def test_norms_along_an_axis_are_ddes_norms(rows: list[list[float]]) -> None:
    data = numpy.array(rows)
    norms = tt.vector_norm(data, axis=1)
    _is_array(norms, (len(rows),))
    assert norms.tolist() == [T.vector_norm(r) for r in rows]
    units = tt.unit_vector(data, axis=1)
    _is_array(units, (len(rows), 3))
    assert units.tolist() == [[v / T.vector_norm(r) for v in r] for r in rows]
    out = numpy.empty(len(rows))
    assert tt.vector_norm(data, axis=1, out=out) is None
    assert out.tolist() == norms.tolist()
    total = tt.vector_norm(data)
    _is_array(total, (1,))
    assert total.tolist() == [T.vector_norm([v for r in rows for v in r])]


def test_without_numpy_the_results_are_lists(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(tt, "_numpy", lambda: None)
    assert tt.quaternion_from_euler(0.1, 0.2, 0.3) == T.quaternion_from_euler(0.1, 0.2, 0.3)
    assert type(tt.quaternion_from_euler(0.1, 0.2, 0.3)) is list
    assert tt.euler_matrix(0.1, 0.2, 0.3) == T.euler_matrix(0.1, 0.2, 0.3)
    assert tt.unit_vector([3.0, 4.0]) == [0.6, 0.8]
    assert tt.vector_norm([3.0, 4.0]) == 5.0


def test_left_out_functions_say_why() -> None:
    with pytest.raises(AttributeError, match="does not provide decompose_matrix: it needs an "
                                             "eigen- or singular value decomposition"):
        tt.decompose_matrix  # noqa: B018
    with pytest.raises(AttributeError, match="has no attribute 'no_such'"):
        tt.no_such  # noqa: B018
    with pytest.raises(DdesValueError, match="unknown Euler axis sequence 'abcd'"):
        tt.euler_matrix(0, 0, 0, "abcd")


def test_random_quaternion_outside_a_script_needs_rand() -> None:
    with pytest.raises(DdesValueError, match=r"pass three numbers in \[0, 1\)"):
        tt.random_quaternion()
    with pytest.raises(AssertionError, match="takes three numbers"):
        tt.random_quaternion([0.5, 0.5])


SCRIPT = """
import rospy
import tf
import tf.transformations
import tf_conversions
from tf.transformations import euler_from_quaternion, quaternion_from_euler
from tf_conversions import transformations as tc
import tf.transformations as tft
rospy.init_node("user")
q = tf.transformations.quaternion_from_euler(0.1, -0.2, 0.3)
print(type(q).__name__, q.dtype, q.tolist() == list(quaternion_from_euler(0.1, -0.2, 0.3)))
print(type(euler_from_quaternion(q)).__name__, [round(v, 12) for v in euler_from_quaternion(q)])
print(tc.quaternion_matrix is tft.quaternion_matrix, tf_conversions.transformations is tc)
print(tft.random_quaternion().tolist())
try:
    from tf.transformations import decompose_matrix
except ImportError as e:
    print("ImportError")
try:
    tf_conversions.posemath
except AttributeError as e:
    print("no posemath:", "PyKDL" in str(e))
"""


def _run(tmp_path: Path, seed: int) -> list[str]:
    path = tmp_path / "user.py"
    path.write_text(textwrap.dedent(SCRIPT))
    world = ddes.World(seed=seed)
    printed: list[str] = []
    done, _ = run_script(world, path, print_line=lambda t, _e: printed.append(t))
    world.run(until=1)
    assert done.ok and done.value == 0
    return printed


def test_scripts_import_the_module_under_every_name(tmp_path: Path) -> None:
    printed = _run(tmp_path, 3)
    assert printed[:3] == ["ndarray float64 True", "tuple [0.1, -0.2, 0.3]", "True True"]
    assert printed[4:] == ["ImportError", "no posemath: True"]
    # random_quaternion() draws from the world's seeded stream: the same seed, the same draw
    q = json.loads(printed[3])
    assert abs(math.sqrt(sum(v * v for v in q)) - 1.0) < 1e-12
    assert _run(tmp_path, 3)[3] == printed[3]
    assert _run(tmp_path, 4)[3] != printed[3]


# -- real Noetic ---------------------------------------------------------------------------------
def describe(value: Any) -> Any:
    """A return value as JSON: its kind (ndarray with dtype and shape, tuple, float, bool) and
    its numbers."""
    if type(value).__name__ == "ndarray":
        return ["ndarray", str(value.dtype), list(value.shape), value.tolist()]
    if isinstance(value, tuple):
        return ["tuple", [describe(v) for v in value]]
    return [type(value).__name__, value if isinstance(value, bool) else float(value)]


def evaluate(tt: Any, c: dict[str, Any]) -> dict[str, Any]:
    a, q0, q1, m, f, t = c["angles"], c["q0"], c["q1"], c["m"], c["f"], c["t"]
    ax = c["axes"]
    em = tt.euler_matrix(a[0], a[1], a[2], ax)
    return {k: describe(v) for k, v in {
        "identity": tt.identity_matrix(),
        "tm": tt.translation_matrix(t),
        "tfm": tt.translation_from_matrix(tt.concatenate_matrices(
            tt.translation_matrix(t), tt.quaternion_matrix(q0))),
        "cat": tt.concatenate_matrices(m, tt.quaternion_matrix(q1), m),
        "inv": tt.inverse_matrix(m),
        "norm": tt.vector_norm(q1),
        "norm_axis": tt.vector_norm([q0[:3], q1[:3]], axis=1),
        "unit": tt.unit_vector(q0),
        "unit_axis": tt.unit_vector([q0[:3], q1[:3]], axis=1),
        "em": em,
        "efm": tt.euler_from_matrix(em, ax),
        "efm3": tt.euler_from_matrix(em[:3, :3], ax),
        "efq": tt.euler_from_quaternion(q0, ax),
        "qfe": tt.quaternion_from_euler(a[0], a[1], a[2], ax),
        "about": tt.quaternion_about_axis(f * 6, t),
        "qm": tt.quaternion_matrix(q0),
        "qfm": tt.quaternion_from_matrix(tt.quaternion_matrix(q0)),
        "mul": tt.quaternion_multiply(q0, q1),
        "conj": tt.quaternion_conjugate(q0),
        "qinv": tt.quaternion_inverse(q0),
        "slerp": tt.quaternion_slerp(q0, q1, f),
        "slerp_spin": tt.quaternion_slerp(q0, q1, f, 1, False),
        "rot": tt.rotation_matrix(a[0], t),
        "rot_point": tt.rotation_matrix(a[1], t, q1[:3]),
        "scale": tt.scale_matrix(f + 0.5),
        "scale_origin": tt.scale_matrix(f + 0.5, t),
        "scale_dir": tt.scale_matrix(f + 0.5, t, q0[:3]),
        "compose": tt.compose_matrix([1 + f, 2.0, 0.5], [0.1, f, 0.2], a, t,
                                     [0.0, 0.0, 0.0, 1.0]),
        "compose_persp": tt.compose_matrix(None, None, a, t, [0.1, 0.0, f, 1.0]),
        "same": tt.is_same_transform(m, m),
        "not_same": tt.is_same_transform(m, em),
        "randq": tt.random_quaternion([f, c["r"][0], c["r"][1]]),
        "randm": tt.random_rotation_matrix([c["r"][1], f, c["r"][0]]),
    }.items()}


REAL = """
import json, sys
import tf.transformations as tt
ns = {}
exec(sys.stdin.read(), ns)
print(json.dumps([ns['evaluate'](tt, c) for c in ns['CASES']]))
"""


def cases(seed: int, n: int) -> list[dict[str, Any]]:
    rnd = random.Random(seed)
    out = []
    for k in range(n):
        angles = [rnd.uniform(-4, 4) for _ in range(3)]
        if k % 10 == 0:
            angles[1] = math.pi / 2  # gimbal lock
        out.append({"axes": sorted(T._AXES2TUPLE)[k % 24], "angles": angles,
                    "q0": [rnd.gauss(0, 1) for _ in range(4)],
                    "q1": [rnd.gauss(0, 1) for _ in range(4)],
                    "m": [[rnd.uniform(-2, 2) for _ in range(4)] for _ in range(4)],
                    "f": rnd.random(), "r": [rnd.random(), rnd.random()],
                    "t": [rnd.uniform(-3, 3) for _ in range(3)]})
    return out


def same(mine: Any, ref: Any, where: str) -> None:
    if isinstance(ref, list):
        assert isinstance(mine, list) and len(mine) == len(ref), where
        for x, y in zip(mine, ref, strict=True):
            same(x, y, where)
    elif isinstance(ref, (bool, str)):
        assert mine == ref, f"{where}: {mine!r} != {ref!r}"
    else:
        assert abs(mine - ref) <= 1e-12 * max(1.0, abs(ref)), f"{where}: {mine} != {ref}"


@pytest.mark.ros
def test_matches_noetic_values_and_types(ros_python: Any) -> None:
    chosen = cases(11, 120)
    source = ("from typing import Any\n" + inspect.getsource(describe) + "\n"
              + inspect.getsource(evaluate) + f"\nCASES = {json.dumps(chosen)}\n")
    theirs = ros_python(REAL, as_json=True, stdin=source)
    kinds = set()
    for c, ref in zip(chosen, theirs, strict=True):
        mine = json.loads(json.dumps(evaluate(tt, c)))
        assert mine.keys() == ref.keys()
        for key, value in ref.items():
            kinds.add((key, value[0]))
            same(mine[key], value, f"{key} {c['axes']}")
    # the kinds Noetic answers with, so a change of type on either side shows here
    assert {k for k, kind in kinds if kind == "tuple"} == {"efm", "efm3", "efq"}
    assert {k for k, kind in kinds if kind == "float"} == {"norm"}
    assert {k for k, kind in kinds if kind == "bool"} == {"same", "not_same"}
