"""ddes against real ROS 1 Noetic (genmsg, genpy, rosmsg under the system Python).

* md5 sum and full text of every bundled type: genmsg's ``compute_md5`` /
  ``compute_full_text`` run over ddes's own bundled files (and over the
  action messages ddes generates), and the installed genpy classes where
  Debian ships them (whose action messages come from the real genaction);
* serialized bytes of hypothesis-drawn values, both directions, and
  ``str(msg)`` against genpy's ``strify_message``;
* ``rosmsg show`` / ``rossrv show`` / ``md5`` output, with real rosmsg
  reading ddes's bundled package folder.
"""

from __future__ import annotations

import io
import json
from collections.abc import Callable
from contextlib import redirect_stdout
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings

from ddes.cli.main import main as ddes_main
from ddes.msg import (
    Message,
    default_registry,
    message_to_dict,
    serialize_message,
    strify_message,
)
from ddes.rospack import BUNDLED_PATH
from ddes.testing import messages

from ..console.rostools import ONE_COPY_OF_EACH_PACKAGE

pytestmark = pytest.mark.ros

Runner = Callable[..., Any]
_REG = default_registry()

_GENMSG_SCRIPT = r"""
import json, os, sys
import genmsg, genmsg.msg_loader as ml
from genmsg import gentools
req = json.load(sys.stdin)
roots = req["roots"]
msg_path, srv_path = {}, {}
for root in roots:
    for pkg in sorted(os.listdir(root)):
        for kind, table in (("msg", msg_path), ("srv", srv_path)):
            d = os.path.join(root, pkg, kind)
            if os.path.isdir(d):
                table.setdefault(pkg, []).append(d)
out = {"msg": {}, "srv": {}}
for t in req["msg"]:
    ctx = genmsg.MsgContext.create_default()
    spec = ml.load_msg_by_type(ctx, t, msg_path)
    ml.load_depends(ctx, spec, msg_path)
    out["msg"][t] = [gentools.compute_md5(ctx, spec), gentools.compute_full_text(ctx, spec)]
for t in req["srv"]:
    ctx = genmsg.MsgContext.create_default()
    spec = ml.load_srv_by_type(ctx, t, srv_path)
    ml.load_depends(ctx, spec, msg_path)
    out["srv"][t] = [gentools.compute_md5(ctx, spec),
                     gentools.compute_md5(ctx, spec.request),
                     gentools.compute_md5(ctx, spec.response),
                     gentools.compute_full_text(ctx, spec.request),
                     gentools.compute_full_text(ctx, spec.response)]
print(json.dumps(out))
"""

_GENPY_CLASSES_SCRIPT = r"""
import importlib, json, sys
out = {}
for t in json.load(sys.stdin):
    pkg, name = t.split("/")
    try:
        cls = getattr(importlib.import_module(pkg + ".msg"), name)
    except (ImportError, AttributeError):
        continue
    out[t] = [cls._md5sum, cls._full_text, list(cls.__slots__), list(cls._slot_types)]
print(json.dumps(out))
"""

_GENPY_WIRE_SCRIPT = r"""
import io, json, sys
import genpy
from genpy.message import get_message_class, strify_message

def build(cls, data):
    msg = cls()
    for name, type_ in zip(cls.__slots__, cls._slot_types):
        setattr(msg, name, value(type_, data[name]))
    return msg

def value(type_, data):
    base = type_.split("[")[0]
    if "[" in type_:
        if base in ("uint8", "char"):
            return bytes(data)
        return [value(base, d) for d in data]
    if base == "time":
        return genpy.Time(data["secs"], data["nsecs"])
    if base == "duration":
        return genpy.Duration(data["secs"], data["nsecs"])
    if isinstance(data, dict):
        return build(get_message_class(base), data)
    return data

out = []
for item in json.load(sys.stdin):
    cls = get_message_class(item["type"])
    msg = build(cls, item["dict"])
    buff = io.BytesIO()
    msg.serialize(buff)
    back = cls().deserialize(bytes.fromhex(item["hex"]))
    out.append({"hex": buff.getvalue().hex(), "str": str(msg), "str_of_ddes_bytes": str(back),
                "strify_nested": strify_message(back, indent="  ")})
print(json.dumps(out))
"""

# real rosmsg sees one copy of each package, ddes's (see ONE_COPY_OF_EACH_PACKAGE)
_ROSMSG_SCRIPT = ONE_COPY_OF_EACH_PACKAGE + r"""
import io, json, os, sys
from contextlib import redirect_stdout, redirect_stderr
req = json.load(sys.stdin)
os.environ["ROS_PACKAGE_PATH"] = req["path"]
os.environ.pop("CMAKE_PREFIX_PATH", None)
import rosmsg
out = []
for argv in req["commands"]:
    sys.argv = list(argv)
    buf, err = io.StringIO(), io.StringIO()
    with redirect_stdout(buf), redirect_stderr(err):
        try:
            rosmsg.rosmsgmain(rosmsg.MODE_SRV if argv[0] == "rossrv" else rosmsg.MODE_MSG)
        except SystemExit:
            pass
    out.append(buf.getvalue())
print(json.dumps(out))
"""


def _action_message_root(tmp_path: Path) -> Path:
    """ddes's generated action messages written out as .msg files (genmsg has no .action)."""
    for type_name in _REG.iter_types("msg"):
        spec = _REG.get_msg_spec(type_name)
        if spec.filename.endswith(".action"):
            pkg, name = type_name.split("/")
            folder = tmp_path / pkg / "msg"
            folder.mkdir(parents=True, exist_ok=True)
            (folder / f"{name}.msg").write_text(spec.text, encoding="utf-8")
    return tmp_path


def test_md5_and_full_text_of_every_bundled_type_match_genmsg(ros_python: Runner,
                                                              tmp_path: Path) -> None:
    msg_types = list(_REG.iter_types("msg"))
    srv_types = list(_REG.iter_types("srv"))
    roots = [str(BUNDLED_PATH), str(_action_message_root(tmp_path))]
    ref = ros_python(_GENMSG_SCRIPT, as_json=True,
                     stdin=json.dumps({"roots": roots, "msg": msg_types, "srv": srv_types}))
    assert sorted(ref["msg"]) == sorted(msg_types)
    for t in msg_types:
        cls = _REG.get_message_class(t)
        assert [cls._md5sum, cls._full_text] == ref["msg"][t], t
    for t in srv_types:
        srv = _REG.get_service_class(t)
        assert [srv._md5sum, srv._request_class._md5sum, srv._response_class._md5sum,
                srv._request_class._full_text, srv._response_class._full_text] == ref["srv"][t], t


def test_every_type_debian_ships_matches_its_genpy_class(ros_python: Runner) -> None:
    msg_types = list(_REG.iter_types("msg"))
    ref = ros_python(_GENPY_CLASSES_SCRIPT, as_json=True, stdin=json.dumps(msg_types))
    assert len(ref) > 150
    # the action messages of these packages were made by the real genaction.py
    assert "nav_msgs/GetMapActionGoal" in ref and "actionlib/TestRequestGoal" in ref
    for t, (md5, full, slots, slot_types) in ref.items():
        cls = _REG.get_message_class(t)
        assert (cls._md5sum, cls._full_text) == (md5, full), t
        assert (list(cls.__slots__), cls._slot_types) == (slots, slot_types), t


def _draw_examples(types: list[str], per_type: int) -> list[Message]:
    """Deterministic hypothesis examples of each type (derandomized, no database)."""
    drawn: list[Message] = []
    for type_name in types:

        @settings(max_examples=per_type, derandomize=True, deadline=None, database=None,
                  suppress_health_check=list(HealthCheck))
        @given(messages(_REG.get_message_class(type_name), max_size=3))
        def collect(msg: Message) -> None:
            drawn.append(msg)

        collect()
    return drawn


WIRE_TYPES = [
    "std_msgs/String", "std_msgs/Header", "std_msgs/Duration", "std_msgs/Byte", "std_msgs/Char",
    "std_msgs/Float32MultiArray", "std_msgs/UInt8MultiArray", "std_msgs/ColorRGBA",
    "geometry_msgs/TransformStamped", "geometry_msgs/PolygonStamped",
    "geometry_msgs/PoseWithCovarianceStamped", "sensor_msgs/LaserScan", "sensor_msgs/Imu",
    "sensor_msgs/JointState", "sensor_msgs/PointCloud2", "sensor_msgs/NavSatFix",
    "sensor_msgs/Range", "sensor_msgs/Image", "sensor_msgs/CameraInfo",
    "sensor_msgs/MultiDOFJointState", "nav_msgs/Odometry", "nav_msgs/Path",
    "nav_msgs/OccupancyGrid", "actionlib_msgs/GoalStatusArray", "rosgraph_msgs/Clock",
    "rosgraph_msgs/Log", "visualization_msgs/MarkerArray", "tf2_msgs/TFMessage",
    "dynamic_reconfigure/ConfigDescription", "nav_msgs/GetMapActionResult",
    "actionlib/TestRequestActionGoal",
]


def test_serialized_bytes_and_str_match_genpy(ros_python: Runner) -> None:
    drawn = _draw_examples(WIRE_TYPES, per_type=4)
    items = [{"type": m._type, "dict": message_to_dict(m), "hex": serialize_message(m).hex()}
             for m in drawn]
    assert len(items) >= 3 * len(WIRE_TYPES)
    ref = ros_python(_GENPY_WIRE_SCRIPT, as_json=True, stdin=json.dumps(items))

    for msg, item, got in zip(drawn, items, ref):
        assert got["hex"] == item["hex"], msg._type
        assert got["str"] == str(msg), msg._type
        assert got["str_of_ddes_bytes"] == str(msg), msg._type
        assert got["strify_nested"] == strify_message(msg, indent="  "), msg._type


ROSMSG_COMMANDS = [
    ["rosmsg", "show", "nav_msgs/Odometry"],
    ["rosmsg", "show", "actionlib_msgs/GoalStatus"],
    ["rosmsg", "show", "-r", "actionlib_msgs/GoalStatus"],
    ["rosmsg", "show", "visualization_msgs/MarkerArray"],
    ["rosmsg", "show", "rosgraph_msgs/Log"],
    ["rosmsg", "show", "sensor_msgs/LaserScan.msg"],
    ["rosmsg", "show", "Pose"],
    ["rosmsg", "info", "dynamic_reconfigure/ConfigDescription"],
    ["rosmsg", "md5", "geometry_msgs/Twist"],
    ["rosmsg", "md5", "Twist"],
    ["rosmsg", "package", "rosgraph_msgs"],
    ["rosmsg", "package", "-s", "actionlib_msgs"],
    ["rossrv", "show", "std_srvs/SetBool"],
    ["rossrv", "show", "roscpp_tutorials/TwoInts"],
    ["rossrv", "show", "nav_msgs/GetPlan"],
    ["rossrv", "show", "-r", "sensor_msgs/SetCameraInfo"],
    ["rossrv", "show", "AddTwoInts"],
    ["rossrv", "show", "dynamic_reconfigure/Reconfigure"],
    ["rossrv", "package", "nav_msgs"],
    ["rossrv", "md5", "std_srvs/Trigger"],
]


def _ddes_output(argv: list[str]) -> str:
    buf = io.StringIO()
    with redirect_stdout(buf):
        ddes_main(argv)
    return buf.getvalue()


@pytest.mark.parametrize("argv", ROSMSG_COMMANDS, ids=" ".join)
def test_rosmsg_output_matches_real_rosmsg(ros_python: Runner, argv: list[str]) -> None:
    ref = ros_python(_ROSMSG_SCRIPT, as_json=True,
                     stdin=json.dumps({"path": str(BUNDLED_PATH), "commands": [argv]}))
    assert _ddes_output(argv) == ref[0]
