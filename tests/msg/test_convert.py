"""Dicts, YAML and genpy's fill_message_args rules."""

from __future__ import annotations

import pytest

from ddes import Duration, Time
from ddes.errors import ROSMessageException
from ddes.msg import (
    default_keys,
    dict_to_message,
    fill_message_args,
    get_message_class,
    get_printable_message_args,
    get_service_class,
    message_to_dict,
    message_to_yaml,
    yaml_to_message,
)

Header = get_message_class("std_msgs/Header")
Point = get_message_class("geometry_msgs/Point")
Pose = get_message_class("geometry_msgs/Pose")
PoseStamped = get_message_class("geometry_msgs/PoseStamped")
Odometry = get_message_class("nav_msgs/Odometry")
Image = get_message_class("sensor_msgs/Image")
CameraInfo = get_message_class("sensor_msgs/CameraInfo")
GoalStatusArray = get_message_class("actionlib_msgs/GoalStatusArray")
DurationMsg = get_message_class("std_msgs/Duration")
TimeRef = get_message_class("sensor_msgs/TimeReference")
AddTwoInts = get_service_class("rospy_tutorials/AddTwoInts")


def test_message_to_dict_nested() -> None:
    ps = PoseStamped(header=Header(seq=1, stamp=Time(2, 3), frame_id="map"))
    ps.pose.position.x = 1.5
    assert message_to_dict(ps) == {
        "header": {"seq": 1, "stamp": {"secs": 2, "nsecs": 3}, "frame_id": "map"},
        "pose": {"position": {"x": 1.5, "y": 0.0, "z": 0.0},
                 "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 0.0}},
    }
    assert message_to_dict(Image(data=b"\x01\xff"))["data"] == [1, 255]
    arr = GoalStatusArray(status_list=[get_message_class("actionlib_msgs/GoalStatus")(status=3)])
    assert message_to_dict(arr)["status_list"][0]["status"] == 3


def test_dict_to_message() -> None:
    ps = dict_to_message(PoseStamped, {"header": {"stamp": {"secs": 4}, "frame_id": "odom"},
                                       "pose": {"position": {"y": 2}}})
    assert ps.header.stamp == Time(4) and ps.header.frame_id == "odom"
    assert ps.pose.position.y == 2.0 and isinstance(ps.pose.position.y, float)
    assert dict_to_message(Image, {"data": [1, 2]}).data == b"\x01\x02"
    assert dict_to_message(DurationMsg, {"data": -1_500_000_000}).data == Duration(-2, 500_000_000)
    assert dict_to_message(Odometry, None) == Odometry()
    assert dict_to_message(Point, {"x": "1e+16", "y": "inf", "z": ".5"}).y == float("inf")


@pytest.mark.parametrize(("cls", "data", "match"), [
    (Point, {"w": 1}, r"No field name \[w\]; geometry_msgs/Point has fields x, y, z"),
    (PoseStamped, {"pose": {"position": {"q": 1}}}, r"No field name \[pose\.position\.q\]"),
    (Point, {"x": "abc"}, r"field x \(float64\) cannot take 'abc'"),
    (Header, {"seq": -1}, r"field seq \(uint32\) cannot take -1 .*\[0, 4294967295\]"),
    (Header, {"seq": 1.5}, r"field seq \(uint32\) cannot take 1.5 .*an integer"),
    (Header, {"seq": True}, r"field seq \(uint32\) cannot take True"),
    (Header, {"stamp": {"secs": 1, "ns": 2}}, r"field stamp \(time\): unknown keys \['ns'\]"),
    (Header, {"stamp": "now"}, r"field stamp \(time\) cannot take 'now'"),
    (Header, {"stamp": {"secs": -1}}, r"field stamp \(time\): .*positive"),
    (CameraInfo, {"K": [1.0]}, r"field K \(float64\[9\]\) has 1 elements; it needs exactly 9"),
    (Image, {"data": [256]}, r"field data\[0\] \(uint8\[\]\) cannot take 256"),
    (Image, {"data": 5}, r"field data \(uint8\[\]\) cannot take 5 .*a list"),
    (PoseStamped, {"pose": 3}, r"field pose \(geometry_msgs/Pose\) cannot take 3"),
    (Point, [1, 2], r"geometry_msgs/Point: expected a dict of fields"),
    (get_message_class("std_msgs/Bool"), {"data": 2}, r"field data \(bool\) cannot take 2"),
    (get_message_class("std_msgs/String"), {"data": 5}, r"field data \(string\) cannot take 5"),
])
def test_dict_to_message_errors(cls: type, data: object, match: str) -> None:
    with pytest.raises(ROSMessageException, match=match):
        dict_to_message(cls, data)  # type: ignore[arg-type]


def test_yaml_round_trip_of_echo_text() -> None:
    odom = Odometry(child_frame_id="base: link")
    odom.header.stamp = Time(7, 8)
    odom.pose.covariance[3] = 1e-300
    assert message_to_yaml(odom) == str(odom)
    assert yaml_to_message(Odometry, str(odom)) == odom
    with pytest.raises(ROSMessageException, match="invalid YAML for nav_msgs/Odometry"):
        yaml_to_message(Odometry, "a: [")


# --- fill_message_args (genpy rules) -----------------------------------------------------


def test_single_dict_fills_by_name() -> None:
    req = AddTwoInts._request_class()
    fill_message_args(req, [{"a": 10, "b": 5}])
    assert (req.a, req.b) == (10, 5)


def test_positional_args_must_match_count() -> None:
    req = AddTwoInts._request_class()
    fill_message_args(req, [1, 2])
    assert (req.a, req.b) == (1, 2)
    with pytest.raises(ROSMessageException,
                       match=r"^Too many arguments:\n \* Given: \[1, 2, 3\]\n \* Expected: "
                             r"\['a', 'b'\]$"):
        fill_message_args(req, [1, 2, 3])
    with pytest.raises(ROSMessageException,
                       match=r"^Not enough arguments:\n \* Given: \[1\]\n \* Expected: "
                             r"\['a', 'b'\]$"):
        fill_message_args(req, [1])


def test_nested_from_lists_and_dicts() -> None:
    pose = Pose()
    fill_message_args(pose, [[1.0, 2.0, 3.0], {"w": 1.0}])
    assert pose.position == Point(1.0, 2.0, 3.0)
    assert pose.orientation.w == 1.0


def test_now_and_auto_keys() -> None:
    keys = default_keys(Time(12, 5))
    ps = PoseStamped()
    fill_message_args(ps, [{"header": "auto"}], keys)
    assert ps.header.stamp == Time(12, 5)
    tr = TimeRef()
    fill_message_args(tr, [{"time_ref": "now", "header": {"stamp": "now"}}], keys)
    assert tr.time_ref == Time(12, 5) and tr.header.stamp == Time(12, 5)
    with pytest.raises(ROSMessageException, match=r"^No key named \[later\]$"):
        fill_message_args(tr, [{"time_ref": "later"}], keys)


def test_time_from_int_ns_and_secs_nsecs() -> None:
    tr = TimeRef()
    fill_message_args(tr, [{"time_ref": 1_500_000_000}])
    assert tr.time_ref == Time(1, 500_000_000)
    fill_message_args(tr, [{"time_ref": {"secs": 3, "nsecs": 4}}])
    assert tr.time_ref == Time(3, 4)
    d = DurationMsg()
    fill_message_args(d, [[-1, 0]])
    assert d.data == Duration(-1)


def test_arrays() -> None:
    arr = GoalStatusArray()
    fill_message_args(arr, [{"status_list": [{"status": 1}, [[{"secs": 1, "nsecs": 0}, "g"], 2,
                                                             "t"]]}])
    assert [s.status for s in arr.status_list] == [1, 2]
    assert arr.status_list[1].goal_id.id == "g"
    ci = CameraInfo()
    with pytest.raises(ROSMessageException,
                       match=r"^Field \[K\] has incorrect number of elements: 2 != 9$"):
        fill_message_args(ci, [{"K": [1.0, 2.0]}])
    with pytest.raises(ROSMessageException,
                       match=r"^Field \[D\] must be a list or tuple instead of: int$"):
        fill_message_args(ci, [{"D": 5}])
    fill_message_args(ci, [{"D": [0.5]}])
    assert ci.D == [0.5]


def test_unknown_field_and_bad_args() -> None:
    with pytest.raises(ROSMessageException, match=r"^No field name \[position\.w\]$"):
        fill_message_args(Pose(), [{"position": {"w": 1}}])
    with pytest.raises(ROSMessageException, match=r"invalid msg_args type: 5"):
        fill_message_args(Pose(), [5, 6])


def test_none_means_empty_string_and_no_args() -> None:
    h = Header(frame_id="x")
    fill_message_args(h, [{"frame_id": None}])
    assert h.frame_id == ""
    e = get_message_class("std_msgs/Empty")()
    fill_message_args(e, None)
    fill_message_args(e, [])


def test_printable_args() -> None:
    assert get_printable_message_args(AddTwoInts._request_class()) == "a b"
    assert get_printable_message_args(Pose()) == (
        "position.x position.y position.z orientation.x orientation.y orientation.z "
        "orientation.w")
