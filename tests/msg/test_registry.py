"""Looking types up on a package path: user packages, actions, errors, definitions."""

from __future__ import annotations

from pathlib import Path

import pytest

from ddes import Duration, Time
from ddes.errors import InvalidMsgSpec, MsgNotFound
from ddes.msg import (
    MessageRegistry,
    default_registry,
    deserialize_message,
    get_message_class,
    get_service_class,
    message_class_from_definition,
    parse_definition,
    serialize_message,
)
from ddes.msg.parser import AUTOGEN


def _write(root: Path, rel: str, text: str) -> Path:
    path = root / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def user_path(tmp_path: Path) -> Path:
    _write(tmp_path, "my_pkg/msg/Bar.msg", "int32 x\n")
    _write(tmp_path, "my_pkg/msg/Foo.msg",
           "Header header\nBar[] bars\ngeometry_msgs/Point p\nuint8 MODE=2\n")
    _write(tmp_path, "my_pkg/srv/DoIt.srv", "Bar bar\n---\nbool ok\n")
    _write(tmp_path, "my_pkg/action/Go.action", "float64 dist\n---\nbool done\n---\nfloat64 left\n")
    _write(tmp_path, "broken/msg/Unknown.msg", "int32 a\nNope b\n")
    _write(tmp_path, "broken/msg/OtherPkg.msg", "nopkg/Thing t\n")
    _write(tmp_path, "broken/msg/A.msg", "B b\n")
    _write(tmp_path, "broken/msg/B.msg", "A a\n")
    _write(tmp_path, "broken/msg/Self.msg", "int32 x\nSelf s\n")
    _write(tmp_path, "broken/msg/Bad.msg", "int32 x\nint32 x\n")
    return tmp_path


@pytest.fixture
def registry(user_path: Path) -> MessageRegistry:
    return MessageRegistry([user_path])


def test_user_package_message(registry: MessageRegistry, user_path: Path) -> None:
    Foo = registry.get_message_class("my_pkg/Foo")
    assert Foo._type == "my_pkg/Foo"
    assert Foo.__slots__ == ("header", "bars", "p")
    assert Foo._slot_types == ["std_msgs/Header", "my_pkg/Bar[]", "geometry_msgs/Point"]
    assert Foo._has_header
    assert Foo.MODE == 2
    assert Foo._full_text.startswith(
        "Header header\nBar[] bars\ngeometry_msgs/Point p\nuint8 MODE=2\n\n" + "=" * 80
        + "\nMSG: std_msgs/Header\n")
    assert "MSG: my_pkg/Bar\nint32 x\n" in Foo._full_text
    Bar = registry.get_message_class("my_pkg/Bar")
    msg = Foo(bars=[Bar(1), Bar(2)])
    assert deserialize_message(Foo, serialize_message(msg)) == msg
    assert registry.get_message_class("my_pkg/Foo") is Foo


def test_service_and_action(registry: MessageRegistry) -> None:
    DoIt = registry.get_service_class("my_pkg/DoIt")
    assert DoIt._type == "my_pkg/DoIt"
    assert DoIt._request_class._type == "my_pkg/DoItRequest"
    assert DoIt._response_class().ok is False
    GoGoal = registry.get_message_class("my_pkg/GoGoal")
    assert GoGoal._full_text == AUTOGEN + "float64 dist\n"
    ActionGoal = registry.get_message_class("my_pkg/GoActionGoal")
    assert ActionGoal.__slots__ == ("header", "goal_id", "goal")
    assert isinstance(ActionGoal().goal, GoGoal)
    assert registry.get_message_class("my_pkg/GoAction").__slots__ == (
        "action_goal", "action_result", "action_feedback")


def test_listing(registry: MessageRegistry) -> None:
    assert registry.list_types("my_pkg") == [
        "my_pkg/Bar", "my_pkg/Foo", "my_pkg/GoAction", "my_pkg/GoActionFeedback",
        "my_pkg/GoActionGoal", "my_pkg/GoActionResult", "my_pkg/GoFeedback", "my_pkg/GoGoal",
        "my_pkg/GoResult"]
    assert registry.list_types("my_pkg", "srv") == ["my_pkg/DoIt"]
    assert registry.list_types("my_pkg", "action") == ["my_pkg/Go"]
    assert registry.find("Foo") == ["my_pkg/Foo"]
    assert registry.find("String") == ["std_msgs/String"]
    assert "my_pkg" in registry.list_packages("srv")
    assert "std_msgs" not in registry.list_packages("srv")
    with pytest.raises(ValueError, match="kind must be"):
        registry.list_types("my_pkg", "bag")
    with pytest.raises(MsgNotFound, match="nope"):
        registry.list_types("nope")


def test_unknown_package_says_where_it_looked(registry: MessageRegistry, user_path: Path) -> None:
    with pytest.raises(MsgNotFound, match=r"unknown package \[nopkg\]") as info:
        registry.get_message_class("nopkg/Thing")
    assert str(user_path) in str(info.value)
    assert "DDES_PACKAGE_PATH" in str(info.value)


def test_unknown_type_in_known_package(registry: MessageRegistry, user_path: Path) -> None:
    with pytest.raises(MsgNotFound, match=r"Cannot locate message \[Nope\] in package \[my_pkg\]") \
            as info:
        registry.get_message_class("my_pkg/Nope")
    assert str(user_path / "my_pkg" / "msg" / "Nope.msg") in str(info.value)
    with pytest.raises(MsgNotFound, match=r"Cannot locate service \[Nope\]"):
        registry.get_service_class("my_pkg/Nope")
    with pytest.raises(MsgNotFound, match="missing package name"):
        registry.get_message_class("String")
    with pytest.raises(MsgNotFound, match="invalid message type name"):
        registry.get_message_class("a/b/c")


def test_field_of_unknown_type_names_file_and_line(registry: MessageRegistry,
                                                   user_path: Path) -> None:
    path = user_path / "broken" / "msg" / "Unknown.msg"
    with pytest.raises(InvalidMsgSpec, match=rf"{path}:2: unknown type \[broken/Nope\] of field "
                                             r"'b': Cannot locate message \[Nope\]"):
        registry.get_message_class("broken/Unknown")
    with pytest.raises(InvalidMsgSpec, match=r"OtherPkg\.msg:1: .*unknown package \[nopkg\]"):
        registry.md5sum("broken/OtherPkg")


def test_circular_types_are_rejected(registry: MessageRegistry) -> None:
    with pytest.raises(InvalidMsgSpec, match=r"circular message dependency "
                                             r"broken/A -> broken/B -> broken/A"):
        registry.get_message_class("broken/A")
    with pytest.raises(InvalidMsgSpec, match=r"Self\.msg:2: circular .*broken/Self -> broken/Self"):
        registry.get_message_class("broken/Self")


def test_malformed_file_names_path(registry: MessageRegistry, user_path: Path) -> None:
    with pytest.raises(InvalidMsgSpec, match=rf"{user_path / 'broken/msg/Bad.msg'}:2: duplicate"):
        registry.get_message_class("broken/Bad")


def test_first_package_on_path_wins(tmp_path: Path) -> None:
    _write(tmp_path, "std_msgs/msg/String.msg", "int32 data\n")
    shadowed = MessageRegistry([tmp_path])
    assert shadowed.get_message_class("std_msgs/String")().data == 0
    assert get_message_class("std_msgs/String")().data == ""


def test_env_path_only_when_asked_and_no_bundled(user_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(user_path))
    with pytest.raises(MsgNotFound, match=r"unknown package \[my_pkg\]"):
        MessageRegistry().get_message_class("my_pkg/Bar")
    assert MessageRegistry(use_env=True).get_message_class("my_pkg/Bar")._type == "my_pkg/Bar"
    assert MessageRegistry.from_environment().get_message_class("my_pkg/Bar")._type == "my_pkg/Bar"
    bare = MessageRegistry(use_env=False, bundled=False)
    with pytest.raises(MsgNotFound, match=r"\(empty path\)"):
        bare.get_message_class("std_msgs/String")


def test_default_registry_and_aliases() -> None:
    assert default_registry() is default_registry()
    assert get_message_class("Header") is get_message_class("std_msgs/Header")
    assert get_message_class("time") is Time
    assert get_message_class("duration") is Duration
    assert get_service_class("std_srvs/SetBool")._md5sum == "09fb03525b03e7ea1fd3992bafd87e16"


def test_class_from_definition_prefers_registry_class() -> None:
    Odom = get_message_class("nav_msgs/Odometry")
    assert message_class_from_definition("nav_msgs/Odometry", Odom._full_text,
                                         registry=default_registry()) is Odom
    other = message_class_from_definition("nav_msgs/Odometry", Odom._full_text)
    assert other is not Odom and other._md5sum == Odom._md5sum
    assert other._full_text == Odom._full_text
    assert other() == Odom()
    assert message_class_from_definition("nav_msgs/Odometry", Odom._full_text) is other


def test_class_from_definition_of_unknown_type() -> None:
    text = ("Header header\nfloat32 v\n" + "=" * 80 + "\nMSG: std_msgs/Header\n"
            + get_message_class("std_msgs/Header")._full_text)
    cls = message_class_from_definition("gone_pkg/Reading", text, registry=default_registry())
    assert cls._type == "gone_pkg/Reading"
    assert cls._full_text == text
    assert cls(v=1.5).v == 1.5
    assert [s.full_name for s in parse_definition("gone_pkg/Reading", text)] == [
        "gone_pkg/Reading", "std_msgs/Header"]


def test_class_from_definition_with_md5_mismatch_keeps_its_own_class() -> None:
    cls = message_class_from_definition("std_msgs/String", "int32 data",
                                        registry=default_registry())
    assert cls is not get_message_class("std_msgs/String")
    assert cls().data == 0


def test_bad_definitions() -> None:
    with pytest.raises(InvalidMsgSpec, match=r"must start with 'MSG: pkg/Type'"):
        message_class_from_definition("p/T", "int32 x\n" + "=" * 80 + "\nnot a header\n")
    with pytest.raises(InvalidMsgSpec, match=r"unknown type \[p/Missing\]"):
        message_class_from_definition("p/T", "Missing m")
