"""Generated message classes: construction rules, attributes, equality, copies, text."""

from __future__ import annotations

import copy
import pickle
from pathlib import Path

import pytest

from ddes import Duration, Time
from ddes.errors import DdesAttributeError, DdesTypeError
from ddes.msg import Message, MessageRegistry, get_message_class, get_service_class
from ddes.rospack import BUNDLED_PATH

String = get_message_class("std_msgs/String")
Header = get_message_class("std_msgs/Header")
Point = get_message_class("geometry_msgs/Point")
Pose = get_message_class("geometry_msgs/Pose")
Odometry = get_message_class("nav_msgs/Odometry")
Empty = get_message_class("std_msgs/Empty")
GoalStatus = get_message_class("actionlib_msgs/GoalStatus")
GoalStatusArray = get_message_class("actionlib_msgs/GoalStatusArray")
Log = get_message_class("rosgraph_msgs/Log")
Image = get_message_class("sensor_msgs/Image")
CameraInfo = get_message_class("sensor_msgs/CameraInfo")


def test_class_attributes_like_genpy() -> None:
    assert Odometry._type == "nav_msgs/Odometry"
    assert Odometry._md5sum == "cd5e73d190d741a2f92e81eda573aca7"
    assert Odometry._has_header is True
    assert Point._has_header is False
    assert Odometry.__slots__ == ("header", "child_frame_id", "pose", "twist")
    assert Odometry._slot_types == ["std_msgs/Header", "string",
                                    "geometry_msgs/PoseWithCovariance",
                                    "geometry_msgs/TwistWithCovariance"]
    assert Odometry._full_text.startswith("# This represents an estimate")
    assert issubclass(Odometry, Message)
    assert Odometry.__name__ == "Odometry"
    assert GoalStatus.SUCCEEDED == 3 and GoalStatus.LOST == 9
    assert Log.DEBUG == 1 and Log.FATAL == 16


def test_zero_defaults() -> None:
    odom = Odometry()
    assert odom.header.stamp == Time(0) and isinstance(odom.header.stamp, Time)
    assert odom.child_frame_id == ""
    assert odom.pose.covariance == [0.0] * 36
    assert Image().data == b""
    assert CameraInfo().D == [] and CameraInfo().K == [0.0] * 9
    assert GoalStatusArray().status_list == []
    assert type(get_message_class("std_msgs/Duration")().data) is Duration


def test_defaults_are_not_shared() -> None:
    a, b = Odometry(), Odometry()
    a.header.seq = 5
    a.pose.covariance[0] = 1.0
    assert b.header.seq == 0 and b.pose.covariance[0] == 0.0


def test_positional_and_keyword_construction() -> None:
    p = Point(1.0, 2.0, 3.0)
    assert (p.x, p.y, p.z) == (1.0, 2.0, 3.0)
    assert Point(y=2.0) == Point(0.0, 2.0, 0.0)
    assert Point(None, 2.0, None) == Point(y=2.0)
    assert Pose(position=None).position == Point()


@pytest.mark.parametrize(("args", "kwds", "error", "match"), [
    ((1.0, 2.0), {}, DdesTypeError, r"Invalid number of arguments, args should be "
                                    r"\['x', 'y', 'z'\] args are\(1.0, 2.0\)"),
    ((1.0, 2.0, 3.0, 4.0), {}, DdesTypeError, "Invalid number of arguments"),
    ((1.0, 2.0, 3.0), {"x": 1.0}, DdesTypeError, "only use args OR keywords, not both"),
    ((), {"w": 1.0}, DdesAttributeError, r"w is not an attribute of Point"),
])
def test_construction_errors(args: tuple[object, ...], kwds: dict[str, object],
                             error: type[Exception], match: str) -> None:
    with pytest.raises(error, match=match):
        Point(*args, **kwds)


def test_construction_errors_are_builtin_types_too() -> None:
    with pytest.raises(TypeError):
        Point(1.0)
    with pytest.raises(AttributeError):
        Point(q=1)
    with pytest.raises(TypeError):
        Empty(1)
    with pytest.raises(AttributeError, match="no fields"):
        Empty(a=1)
    assert Empty() == Empty()


def test_equality() -> None:
    assert Point(1, 2, 3) == Point(1, 2, 3)
    assert Point(1, 2, 3) != Point(1, 2, 4)
    assert Point() != Header()
    assert Point() != "x"
    a = get_message_class("std_msgs/Float64MultiArray")(data=[1.0, 2.0])
    b = get_message_class("std_msgs/Float64MultiArray")(data=(1.0, 2.0))
    assert a == b  # lists and tuples compare equal, as in genpy
    with pytest.raises(TypeError):
        hash(Point())


def test_equality_across_classes_of_same_type(tmp_path: Path) -> None:
    # a registry of its own over the bundled folder (no parent) builds its own classes
    other = MessageRegistry([BUNDLED_PATH], parent=None).get_message_class("geometry_msgs/Point")
    assert other is not Point
    assert other(1, 2, 3) == Point(1, 2, 3)
    (tmp_path / "geometry_msgs" / "msg").mkdir(parents=True)
    (tmp_path / "geometry_msgs" / "msg" / "Point.msg").write_text("float64 x\nfloat64 y\n"
                                                                   "float32 z\n")
    changed = MessageRegistry([tmp_path]).get_message_class("geometry_msgs/Point")
    assert changed(1, 2, 3) != Point(1, 2, 3)


def test_copy_and_deepcopy() -> None:
    odom = Odometry(child_frame_id="base")
    shallow = copy.copy(odom)
    assert shallow == odom and shallow.header is odom.header
    deep = copy.deepcopy(odom)
    assert deep == odom and deep.header is not odom.header
    deep.header.stamp = Time(5)
    assert odom.header.stamp == Time(0)


def test_pickle_round_trip() -> None:
    odom = Odometry(child_frame_id="base")
    odom.header.stamp = Time(1, 2)
    back = pickle.loads(pickle.dumps(odom))
    assert back == odom and type(back) is Odometry


def test_str_is_rostopic_echo_yaml() -> None:
    msg = GoalStatusArray(status_list=[GoalStatus(text="a", status=1)])
    msg.header.stamp = Time(3, 40)
    assert str(msg) == (
        "header: \n"
        "  seq: 0\n"
        "  stamp: \n"
        "    secs: 3\n"
        "    nsecs:        40\n"
        "  frame_id: ''\n"
        "status_list: \n"
        "  - \n"
        "    goal_id: \n"
        "      stamp: \n"
        "        secs: 0\n"
        "        nsecs:         0\n"
        "      id: ''\n"
        "    status: 1\n"
        '    text: "a"'
    )
    assert repr(msg) == str(msg)
    assert str(Empty()) == ""


def test_str_of_arrays() -> None:
    JointState = get_message_class("sensor_msgs/JointState")
    js = JointState(name=["a", "yes"], position=[1.5], velocity=[], effort=(2.0,))
    text = str(js)
    assert "name: \n  - a\n  - 'yes'\n" in text
    assert "position: [1.5]\nvelocity: []\neffort: [2.0]" in text
    assert "data: [1, 2]" in str(Image(data=b"\x01\x02"))


def test_service_class() -> None:
    srv = get_service_class("rospy_tutorials/AddTwoInts")
    assert srv._type == "rospy_tutorials/AddTwoInts"
    assert srv._md5sum == "6a2e34150c00229791cc89ff309fff21"
    req = srv._request_class(a=1, b=2)
    assert req._type == "rospy_tutorials/AddTwoIntsRequest"
    assert srv._request_class._md5sum == "36d09b846be0b371c5f190354dd3153e"
    assert srv._response_class(3).sum == 3
    assert srv._request_class._full_text == "int64 a\nint64 b\n"
    assert get_service_class("rospy_tutorials/AddTwoInts") is srv


def test_action_messages_match_genaction() -> None:
    goal = get_message_class("actionlib_tutorials/FibonacciActionGoal")()
    assert goal.__slots__ == ("header", "goal_id", "goal")
    assert goal.goal._type == "actionlib_tutorials/FibonacciGoal"
    assert goal._has_header
    result = get_message_class("actionlib_tutorials/FibonacciActionResult")()
    assert result.status._type == "actionlib_msgs/GoalStatus"
    assert get_message_class("actionlib_tutorials/FibonacciAction").__slots__ == (
        "action_goal", "action_result", "action_feedback")


def test_python_keyword_fields_are_remapped(tmp_path: Path) -> None:
    (tmp_path / "kw" / "msg").mkdir(parents=True)
    (tmp_path / "kw" / "msg" / "K.msg").write_text("int32 from\nstring self\nint32 IF=1\n")
    K = MessageRegistry([tmp_path]).get_message_class("kw/K")
    assert K.__slots__ == ("from_", "self_")
    k = K(from_=3, self_="s")
    assert (k.from_, k.self_) == (3, "s")
    assert K.IF == 1
    assert "from" in K._full_text and K._md5sum == MessageRegistry([tmp_path]).md5sum("kw/K")


def test_generated_source_is_kept_for_inspection() -> None:
    src = Odometry._generated_source
    assert "def _serialize_to_bytes(self):" in src
    assert "def _deserialize_from(self, _d):" in src
