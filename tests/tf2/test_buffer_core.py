"""ddes.tf2.BufferCore: one test per behaviour, and composition/inversion along any path."""

from __future__ import annotations

import logging
import math
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ddes import transformations as T
from ddes.errors import DdesError
from ddes.msg import get_message_class
from ddes.tf2 import (
    BufferCore,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TransformException,
)
from ddes.time import Time

TS = get_message_class("geometry_msgs/TransformStamped")


def ts(parent: str, child: str, t: float, xyz: tuple[float, float, float] = (0, 0, 0),
       q: tuple[float, float, float, float] = (0, 0, 0, 1)) -> Any:
    m = TS()
    m.header.frame_id, m.child_frame_id, m.header.stamp = parent, child, Time.from_sec(t)
    tr, rot = m.transform.translation, m.transform.rotation
    tr.x, tr.y, tr.z = xyz
    rot.x, rot.y, rot.z, rot.w = q
    return m


def xyz(msg: Any) -> tuple[float, float, float]:
    t = msg.transform.translation
    return t.x, t.y, t.z


def test_exceptions_are_transform_exceptions_in_the_ddes_tree() -> None:
    for cls in (LookupException, ConnectivityException, ExtrapolationException,
                InvalidArgumentException):
        assert issubclass(cls, TransformException) and issubclass(cls, DdesError)


def test_interpolation_lerps_translation_and_slerps_rotation() -> None:
    b = BufferCore()
    b.set_transform(ts("map", "base", 1, (0, 0, 0)), "a")
    b.set_transform(ts("map", "base", 2, (2, 0, 0), T.quaternion_from_euler(0, 0, 1.0)), "a")
    r = b.lookup_transform_core("map", "base", Time.from_sec(1.5))
    assert xyz(r) == (1.0, 0.0, 0.0)
    q = r.transform.rotation
    assert T.euler_from_quaternion([q.x, q.y, q.z, q.w])[2] == pytest.approx(0.5, abs=1e-15)
    assert r.header.stamp == Time.from_sec(1.5)


def test_time_zero_is_the_latest_common_time() -> None:
    b = BufferCore()
    for t in (1, 2, 3):
        b.set_transform(ts("a", "b", t, (t, 0, 0)), "n")
    b.set_transform(ts("b", "c", 2, (0, 1, 0)), "n")
    r = b.lookup_transform_core("a", "c", Time(0))
    assert r.header.stamp == Time(2) and xyz(r) == (2.0, 1.0, 0.0)
    assert b.get_latest_common_time("a", "c") == Time(2)


def test_static_transforms_hold_at_any_time_and_survive_clear() -> None:
    b = BufferCore()
    b.set_transform_static(ts("base", "laser", 5, (0.1, 0, 0.2)), "s")
    assert xyz(b.lookup_transform_core("base", "laser", Time(1000))) == (0.1, 0.0, 0.2)
    b.clear()
    assert b.can_transform_core("base", "laser", Time(3)) == (True, "")


def test_cache_pruning_and_old_data(caplog: pytest.LogCaptureFixture) -> None:
    b = BufferCore(2)
    for t in range(1, 6):
        assert b.set_transform(ts("a", "b", t), "n")
    assert [e[0] for e in b._storage("b")] == [3_000_000_000, 4_000_000_000, 5_000_000_000]
    with caplog.at_level(logging.WARNING, logger="ddes.tf2"):
        assert not b.set_transform(ts("a", "b", 2.5), "late")
        assert not b.set_transform(ts("a", "b", 5), "again")
    assert caplog.messages == [
        "TF_OLD_DATA ignoring data from the past (Possible reasons are listed at "
        "http://wiki.ros.org/tf/Errors%20explained) for frame b at time 2.500000 according to "
        "authority late",
        "TF_REPEATED_DATA ignoring data with redundant timestamp for frame b at time 5.000000 "
        "according to authority again"]
    with pytest.raises(ExtrapolationException, match="into the past"):
        b.lookup_transform_core("a", "b", Time(2))
    with pytest.raises(ExtrapolationException, match=r"0\.500000000s into the future"):
        b.lookup_transform_core("a", "b", Time.from_sec(5.5))


def test_validation_texts(caplog: pytest.LogCaptureFixture) -> None:
    b = BufferCore()
    with caplog.at_level(logging.ERROR, logger="ddes.tf2"):
        assert not b.set_transform(ts("a", "a", 1), "me")
        assert not b.set_transform(ts("a", "", 1), "me")
        assert not b.set_transform(ts("", "b", 1), "me")
        assert not b.set_transform(ts("a", "b", 1, (math.nan, 0, 0)), "me")
        assert not b.set_transform(ts("a", "b", 1, q=(0, 0, 0, 1.1)), "me")
    assert [m.split(":")[0] for m in caplog.messages] == [
        "TF_SELF_TRANSFORM", "TF_NO_CHILD_FRAME_ID", "TF_NO_FRAME_ID", "TF_NAN_INPUT",
        "TF_DENORMALIZED_QUATERNION"]
    assert b._getFrameStrings() == []
    assert b.set_transform(ts("/a", "/b", 1), "me")
    assert b._getFrameStrings() == ["b", "a"] and b._getParent("b", Time(1)) == "a"
    assert b._getParent("a", Time(1)) is None and b._frameExists("a")


def test_exception_texts() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "b", 1), "n")
    b.set_transform(ts("x", "y", 1), "n")
    with pytest.raises(LookupException) as e1:
        b.lookup_transform_core("a", "nope", Time(0))
    assert str(e1.value) == '"nope" passed to lookupTransform argument source_frame does not exist. '
    with pytest.raises(InvalidArgumentException) as e2:
        b.lookup_transform_core("", "b", Time(0))
    assert str(e2.value) == ("Invalid argument passed to lookupTransform argument target_frame "
                             "in tf2 frame_ids cannot be empty")
    with pytest.raises(ConnectivityException) as e3:
        b.lookup_transform_core("a", "y", Time(0))
    assert str(e3.value) == ("Could not find a connection between 'a' and 'y' because they are "
                             "not part of the same tree.Tf has two or more unconnected trees.")


def test_loop_detection() -> None:
    b = BufferCore()
    b.set_transform(ts("a", "b", 1), "n")
    b.set_transform(ts("b", "a", 1), "n")
    b.set_transform(ts("q", "r", 1), "n")
    with pytest.raises(LookupException, match="The tf tree is invalid because it contains a "
                                              "loop.\nFrame b exists with parent a."):
        b.lookup_transform_core("r", "a", Time(1))


def test_yaml_and_string() -> None:
    b = BufferCore()
    assert b.all_frames_as_yaml() == "{}"
    b.set_transform(ts("a", "b", 1), "/pub")
    b.set_transform(ts("a", "b", 3), "/pub")
    assert b.all_frames_as_string() == "Frame b exists with parent a.\n"
    assert b.all_frames_as_yaml(Time(4)) == (
        "b: \n  parent: 'a'\n  broadcaster: '/pub'\n  rate: 1.000\n"
        "  most_recent_transform: 3.000\n  oldest_transform: 1.000\n  transform_delay: 1.000\n"
        "  buffer_length: 2.000\n")


def test_full_lookup_through_a_fixed_frame() -> None:
    b = BufferCore()
    b.set_transform(ts("odom", "base", 1, (1, 0, 0)), "n")
    b.set_transform(ts("odom", "base", 2, (3, 0, 0)), "n")
    r = b.lookup_transform_full_core("base", Time(2), "base", Time(1), "odom")
    assert xyz(r) == (-2.0, 0.0, 0.0) and r.header.stamp == Time(2)


angles = st.floats(-3.0, 3.0)
offsets = st.floats(-10.0, 10.0)


@st.composite
def trees(draw: Any) -> tuple[list[int], list[tuple[Any, ...]]]:
    n = draw(st.integers(2, 7))
    parents = [-1] + [draw(st.integers(0, i - 1)) for i in range(1, n)]
    links = [(draw(offsets), draw(offsets), draw(offsets), draw(angles), draw(angles),
              draw(angles)) for _ in range(n)]
    return parents, links


def pose(msg: Any) -> list[list[float]]:
    t, q = msg.transform.translation, msg.transform.rotation
    return T.concatenate_matrices(T.translation_matrix([t.x, t.y, t.z]),
                                  T.quaternion_matrix([q.x, q.y, q.z, q.w]))


@given(trees(), st.data())
def test_composing_and_inverting_along_any_path_agrees_with_direct_lookups(
        tree: tuple[list[int], list[tuple[Any, ...]]], data: st.DataObject) -> None:
    parents, links = tree
    b = BufferCore()
    for i in range(1, len(parents)):
        x, y, z, r, p, w = links[i]
        make = b.set_transform_static if i % 2 else b.set_transform
        make(ts(f"f{parents[i]}", f"f{i}", 7, (x, y, z), tuple(T.quaternion_from_euler(r, p, w))),
             "h")
    n = len(parents)
    a, m, c = (data.draw(st.integers(0, n - 1)) for _ in range(3))
    direct = pose(b.lookup_transform_core(f"f{a}", f"f{c}", Time(7)))
    via = T.concatenate_matrices(pose(b.lookup_transform_core(f"f{a}", f"f{m}", Time(7))),
                                 pose(b.lookup_transform_core(f"f{m}", f"f{c}", Time(0))))
    inverse = T.inverse_matrix(pose(b.lookup_transform_core(f"f{c}", f"f{a}", Time(7))))
    for row_d, row_v, row_i in zip(direct, via, inverse, strict=True):
        for d, v, i in zip(row_d, row_v, row_i, strict=True):
            assert d == pytest.approx(v, abs=1e-9) and d == pytest.approx(i, abs=1e-9)
