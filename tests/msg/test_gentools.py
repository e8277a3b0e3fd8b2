"""md5 sums and full text: the test vectors of ros1-semantics.md §4.6 and the algorithm."""

from __future__ import annotations

import hashlib

import pytest

from ddes.msg import get_message_class, get_service_class
from ddes.msg.gentools import all_dependencies, compute_full_text, compute_md5, compute_md5_text
from ddes.msg.parser import parse_msg
from ddes.msg.spec import MsgSpec

VECTORS = [
    ("std_msgs/String", "992ce8a1687cec8c8bd883ec73ca41d1"),
    ("std_msgs/Header", "2176decaecbce78abc3b96ef049fabed"),
    ("std_msgs/Empty", "d41d8cd98f00b204e9800998ecf8427e"),
    ("std_msgs/Bool", "8b94c1b53db61fb6aed406028ad6332a"),
    ("std_msgs/Float64", "fdb28210bfa9d7c91146260178d9a584"),
    ("geometry_msgs/Vector3", "4a842b65f413084dc2b10fb484ea7f17"),
    ("geometry_msgs/Twist", "9f195f881246fdfa2798d1d3eebca84a"),
    ("geometry_msgs/TransformStamped", "b5764a33bfeb3588febc2682852579b0"),
    ("sensor_msgs/LaserScan", "90c7ef2dc6895d81024acba2ac42f369"),
    ("sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2"),
    ("nav_msgs/Odometry", "cd5e73d190d741a2f92e81eda573aca7"),
    ("rosgraph_msgs/Clock", "a9c97c1d230cfc112e270351a944ee47"),
    ("actionlib_msgs/GoalID", "302881f31927c1df708a2dbab0e80ee8"),
    ("actionlib_msgs/GoalStatus", "d388f9b87b3c471f784434d671988d4a"),
    ("actionlib_msgs/GoalStatusArray", "8b2b82f13216d0a8ea88bd3af735e619"),
    ("actionlib_tutorials/FibonacciActionGoal", "006871c7fa1d0e3d5fe2226bf17b2a94"),
    ("actionlib_tutorials/FibonacciGoal", "6889063349a00b249bd1661df429d822"),
    ("rospy_tutorials/Floats", "420cd38b6b071cd49f2970c3e2cee511"),
]

SRV_VECTORS = [
    ("std_srvs/Empty", "d41d8cd98f00b204e9800998ecf8427e"),
    ("std_srvs/SetBool", "09fb03525b03e7ea1fd3992bafd87e16"),
    ("std_srvs/Trigger", "937c9679a518e3a18d831e57125ea522"),
    ("rospy_tutorials/AddTwoInts", "6a2e34150c00229791cc89ff309fff21"),
    ("roscpp_tutorials/TwoInts", "6a2e34150c00229791cc89ff309fff21"),
]


@pytest.mark.parametrize(("type_name", "md5"), VECTORS)
def test_md5_vectors(type_name: str, md5: str) -> None:
    assert get_message_class(type_name)._md5sum == md5


@pytest.mark.parametrize(("type_name", "md5"), SRV_VECTORS)
def test_srv_md5_vectors(type_name: str, md5: str) -> None:
    assert get_service_class(type_name)._md5sum == md5


def test_nested_types_hash_as_md5_without_brackets() -> None:
    vec = get_message_class("geometry_msgs/Vector3")._md5sum
    twist_text = f"{vec} linear\n{vec} angular"
    assert hashlib.md5(twist_text.encode()).hexdigest() == "9f195f881246fdfa2798d1d3eebca84a"
    header = get_message_class("std_msgs/Header")._md5sum
    status = get_message_class("actionlib_msgs/GoalStatus")._md5sum
    text = f"{header} header\n{status} status_list"
    assert hashlib.md5(text.encode()).hexdigest() == "8b2b82f13216d0a8ea88bd3af735e619"


def test_service_md5_is_request_then_response_text() -> None:
    bool_md5 = get_message_class("std_msgs/Bool")._md5sum
    srv = get_service_class("std_srvs/SetBool")
    assert srv._request_class._md5sum == bool_md5
    assert srv._response_class._md5sum == get_service_class("std_srvs/Trigger")._response_class._md5sum
    assert hashlib.md5(b"bool data" + b"bool success\nstring message").hexdigest() == srv._md5sum


def _specs(*items: tuple[str, str]) -> dict[str, MsgSpec]:
    return {name: parse_msg(text, name) for name, text in items}


def test_md5_text_constants_first_and_comments_dropped() -> None:
    specs = _specs(("p/Inner", "int32 a\n"),
                   ("p/T", "# comment\nint32 x  # c\nstring S = a # b\nInner[4] ins\n"
                           "float32[] fs\nuint8 K=3 # k\n"))
    inner_md5 = compute_md5(specs["p/Inner"], specs.__getitem__)
    text = compute_md5_text(specs["p/T"], lambda n: compute_md5(specs[n], specs.__getitem__))
    assert text == f"string S=a # b\nuint8 K=3\nint32 x\n{inner_md5} ins\nfloat32[] fs"


def test_full_text_dependencies_depth_first_unique() -> None:
    specs = _specs(("p/A", "B b\nC c\nB b2\n"), ("p/B", "C c\nint8 x"), ("p/C", "int8 y\n"),)
    assert all_dependencies(specs["p/A"], specs.__getitem__) == ["p/B", "p/C"]
    sep = "=" * 80
    assert compute_full_text(specs["p/A"], specs.__getitem__) == (
        f"B b\nC c\nB b2\n\n{sep}\nMSG: p/B\nC c\nint8 x\n{sep}\nMSG: p/C\nint8 y\n")


def test_full_text_without_dependencies_is_the_text() -> None:
    specs = _specs(("p/A", "int8 x\n\n"))
    assert compute_full_text(specs["p/A"], specs.__getitem__) == "int8 x\n\n"
