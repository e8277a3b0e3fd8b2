"""The genmsg grammar: fields, constants, arrays, type resolution, and malformed input."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from ddes.errors import InvalidMsgSpec
from ddes.msg.parser import (
    AUTOGEN,
    action_message_texts,
    convert_constant_value,
    parse_action,
    parse_msg,
    parse_srv,
)
from ddes.msg.spec import parse_type, resolve_type


def test_fields_constants_and_comments() -> None:
    text = (
        "# a comment\n"
        "Header header   # the header\n"
        "\n"
        "uint8 KIND_A = 1  # first kind\n"
        "string NAME = hello # not a comment\n"
        "float64 PI=3.14\n"
        "bool ON = True\n"
        "Point[3] corners\n"
        "geometry_msgs/Pose pose\n"
        "time t\n"
        "duration[] ds\n"
        "byte b\n"
        "char c\n"
    )
    spec = parse_msg(text, "pkg/Thing")
    assert spec.types == ["std_msgs/Header", "pkg/Point[3]", "geometry_msgs/Pose", "time",
                          "duration[]", "byte", "char"]
    assert spec.names == ["header", "corners", "pose", "t", "ds", "b", "c"]
    assert spec.has_header()
    consts = {c.name: c for c in spec.constants}
    assert consts["KIND_A"].val == 1 and consts["KIND_A"].val_text == "1"
    assert consts["NAME"].val == "hello # not a comment"
    assert consts["NAME"].val_text == "hello # not a comment"
    assert consts["PI"].val == 3.14
    assert consts["ON"].val is True
    assert [c.line for c in spec.constants] == [4, 5, 6, 7]
    assert spec.text == text


def test_string_constant_keeps_everything_after_equals() -> None:
    spec = parse_msg("string EQ = a=b # c\n", "p/T")
    assert spec.constants[0].val == "a=b # c"


def test_header_without_package_context_and_builtins() -> None:
    spec = parse_msg("Header h\nint32[] xs\nFoo f\n", "")
    assert spec.types == ["std_msgs/Header", "int32[]", "Foo"]


def test_header_not_first_means_no_header() -> None:
    assert not parse_msg("int32 x\nHeader header\n", "p/T").has_header()
    assert not parse_msg("Header h\n", "p/T").has_header()


@pytest.mark.parametrize(("type_", "expected"), [
    ("int32", ("int32", False, None)),
    ("int32[]", ("int32", True, None)),
    ("Point[12]", ("Point", True, 12)),
])
def test_parse_type(type_: str, expected: tuple[str, bool, int | None]) -> None:
    assert parse_type(type_) == expected


def test_resolve_type() -> None:
    assert resolve_type("String", "std_msgs") == "std_msgs/String"
    assert resolve_type("String[]", "std_msgs") == "std_msgs/String[]"
    assert resolve_type("std_msgs/String", "foo") == "std_msgs/String"
    assert resolve_type("uint16[]", "std_msgs") == "uint16[]"
    assert resolve_type("Header", "foo") == "std_msgs/Header"


@pytest.mark.parametrize(("type_", "text", "value"), [
    ("uint8", "255", 255), ("int8", "-128", -128), ("char", "0", 0), ("byte", "127", 127),
    ("uint64", str(2**64 - 1), 2**64 - 1), ("int64", str(-(2**63)), -(2**63)),
    ("float32", "1e3", 1000.0), ("bool", "0", False), ("bool", "1", True),
    ("string", "  spaced  ", "spaced"),
])
def test_constant_values(type_: str, text: str, value: object) -> None:
    assert convert_constant_value(type_, text) == value


def test_srv_pieces_keep_genmsg_text() -> None:
    spec = parse_srv("int64 a\nint64 b\n---\nint64 sum\n", "rospy_tutorials/AddTwoInts")
    assert spec.request.text == "int64 a\nint64 b\n"
    assert spec.response.text == "int64 sum\n\n"
    assert spec.request.full_name == "rospy_tutorials/AddTwoIntsRequest"
    assert spec.response.fields[0].line == 4


def test_srv_separator_may_carry_trailing_text() -> None:
    spec = parse_srv("int64 a\n--- trailing\nint64 b", "p/S")
    assert spec.response.names == ["b"]


def test_action_generates_seven_messages_like_genaction() -> None:
    texts = action_message_texts("int32 order\n---\nint32[] sequence\n---\nint32[] sequence",
                                 "Fibonacci")
    assert texts["Goal"] == AUTOGEN + "int32 order\n"
    assert texts["Result"] == AUTOGEN + "int32[] sequence\n"
    assert texts["Feedback"] == AUTOGEN + "int32[] sequence\n"
    assert texts["ActionGoal"] == (AUTOGEN + "\nHeader header\nactionlib_msgs/GoalID goal_id\n"
                                   "FibonacciGoal goal\n")
    assert texts["Action"] == (AUTOGEN + "\nFibonacciActionGoal action_goal\n"
                               "FibonacciActionResult action_result\n"
                               "FibonacciActionFeedback action_feedback\n")
    spec = parse_action("int32 order\n---\n---\n", "actionlib_tutorials/Fibonacci")
    assert sorted(spec.messages) == sorted(["Action", "ActionGoal", "ActionResult",
                                            "ActionFeedback", "Goal", "Result", "Feedback"])
    assert spec.messages["ActionGoal"].types == [
        "std_msgs/Header", "actionlib_msgs/GoalID", "actionlib_tutorials/FibonacciGoal"]


def test_action_error_names_action_file_line() -> None:
    with pytest.raises(InvalidMsgSpec, match=r"F\.action:3: .*'1x'"):
        parse_action("int32 a\n---\nint32 1x\n---\n", "p/F", filename="F.action")


# Each malformed definition with the error it must raise: (kind, text, match).
MALFORMED = [
    ("msg", "int32 x\nint32 x\n", r"T\.msg:2: duplicate field name 'x' \(first declared on line 1\)"),
    ("msg", "foo/bar/Baz x\n", r"T\.msg:1: 'foo/bar/Baz' is not a legal message field type"),
    ("msg", "int32 1x\n", r"T\.msg:1: '1x' is not a legal message field name"),
    ("msg", "int32 x-y\n", r"T\.msg:1: 'x-y' is not a legal message field name"),
    ("msg", "int32 x y\n", r"T\.msg:1: invalid declaration 'int32 x y'"),
    ("msg", "int32\tx\n", r"T\.msg:1: invalid declaration .*not tabs"),
    ("msg", "\n\nint32[abc] x\n", r"T\.msg:3: 'int32\[abc\]' has an invalid array size"),
    ("msg", "int32[3][2] x\n", r"T\.msg:1: 'int32\[3\]\[2\]': only 1-dimensional"),
    ("msg", "int32[ x\n", r"T\.msg:1: 'int32\[' has an unclosed array bracket"),
    ("msg", "1nt32 x\n", r"T\.msg:1: '1nt32' is not a legal message field type"),
    ("msg", "uint8 X=256\n", r"T\.msg:1: invalid value '256' for constant X of type uint8: "
                            r"cannot coerce \[256\] to uint8 \(out of bounds \[0, 255\]\)"),
    ("msg", "int8 X=-129\n", r"T\.msg:1: .*out of bounds \[-128, 127\]"),
    ("msg", "char C=-1\n", r"T\.msg:1: .*out of bounds \[0, 255\]"),
    ("msg", "byte B=128\n", r"T\.msg:1: .*out of bounds \[-128, 127\]"),
    ("msg", "uint64 U=18446744073709551616\n", r"T\.msg:1: .*out of bounds"),
    ("msg", "int32 X=abc\n", r"T\.msg:1: invalid value 'abc' for constant X of type int32"),
    ("msg", "float32 F=1.0.0\n", r"T\.msg:1: invalid value '1.0.0' for constant F"),
    ("msg", "bool B=maybe\n", r"T\.msg:1: invalid value 'maybe' for constant B of type bool"),
    ("msg", "time T=1\n", r"T\.msg:1: 'time' is not a legal constant type"),
    ("msg", "int32[] A=1\n", r"T\.msg:1: 'int32\[\]' is not a legal constant type"),
    ("msg", "Foo F=1\n", r"T\.msg:1: 'Foo' is not a legal constant type"),
    ("msg", "int32 1X=1\n", r"T\.msg:1: '1X' is not a legal constant name"),
    ("msg", "int32 X=1=2\n", r"T\.msg:1: invalid constant declaration"),
    ("msg", "int32 X=1\nint32 X=2\n", r"T\.msg:2: duplicate constant 'X'"),
    ("msg", "int32 x\nint32 x=1\n", r"T\.msg:2: constant 'x' has the name of the field on line 1"),
    ("srv", "int32 a\n", r"T\.srv:1: a \.srv file needs exactly 1 '---' separator line, found 0"),
    ("srv", "int32 a\n---\nint32 b\n---\nint32 c\n",
     r"T\.srv:4: a \.srv file needs exactly 1 '---' separator line, found 2 \(lines 2, 4\)"),
    ("srv", "int32 a\n---\nint32 1b\n", r"T\.srv:3: '1b' is not a legal message field name"),
    ("action", "int32 a\n---\nint32 b\n",
     r"T\.action:1: a \.action file needs exactly 2 '---' separator lines, found 1 \(line 2\)"),
    ("action", "---\n---\n---\n", r"T\.action:3: .*needs exactly 2 .*found 3"),
]


@pytest.mark.parametrize(("kind", "text", "match"), MALFORMED)
def test_malformed_definitions(kind: str, text: str, match: str) -> None:
    parsers: dict[str, Callable[..., object]] = {"msg": parse_msg, "srv": parse_srv,
                                                 "action": parse_action}
    parse = parsers[kind]
    with pytest.raises(InvalidMsgSpec, match=match):
        parse(text, "pkg/T", filename=f"T.{kind}")


def test_error_without_filename_names_the_type() -> None:
    with pytest.raises(InvalidMsgSpec, match=r"^pkg/T:1: "):
        parse_msg("int32 1x\n", "pkg/T")
