"""One registry per world: layering over the bundled registry, isolation, no hidden env reads."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ddes
from ddes.errors import DdesTypeError, DdesValueError, MsgNotFound
from ddes.msg import (
    MessageRegistry,
    default_registry,
    deserialize_message,
    get_message_class,
    get_service_class,
    message_class_from_definition,
    serialize_message,
)
from ddes.msg.parser import parse_msg
from ddes.rospack import BUNDLED_PATH, RosPack

BUNDLED = default_registry()


def _write(root: Path, rel: str, text: str) -> Path:
    path = root / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def _student(root: Path, fields: list[tuple[str, str]]) -> Path:
    """A package ``sub`` whose ``Thing`` has ``fields``, plus types and a service using it."""
    _write(root, "sub/msg/Thing.msg", "".join(f"{t} {n}\n" for t, n in fields))
    _write(root, "sub/msg/Holder.msg", "Header header\nThing[] things\ngeometry_msgs/Point p\n")
    _write(root, "sub/srv/Ask.srv", "Thing t\n---\nbool ok\n")
    return root


# -- isolation, in any order of lookups -------------------------------------------------------

_FIELD_TYPES = ["int32", "float64", "string", "bool", "uint8[]", "geometry_msgs/Point", "time"]
_NAMES = ["a", "b", "c", "d", "e"]

_fields = st.lists(st.tuples(st.sampled_from(_FIELD_TYPES), st.sampled_from(_NAMES)),
                   min_size=1, max_size=4, unique_by=lambda f: f[1])

_LOOKUPS = ["class:sub/Thing", "class:sub/Holder", "srv:sub/Ask", "md5:sub/Thing",
            "md5:sub/Holder", "full:sub/Holder", "spec:sub/Thing", "list:sub",
            "class:std_msgs/Header", "class:geometry_msgs/Point", "srvmd5:sub/Ask"]


def _look(registry: MessageRegistry, op: str) -> object:
    kind, name = op.split(":")
    if kind == "class":
        return registry.get_message_class(name)
    if kind == "srv":
        return registry.get_service_class(name)
    if kind == "md5":
        return registry.md5sum(name)
    if kind == "srvmd5":
        return registry.srv_md5sum(name)
    if kind == "full":
        return registry.full_text(name)
    if kind == "spec":
        return registry.get_msg_spec(name)
    return registry.list_types(name)


@settings(max_examples=40, deadline=None)
@given(fields=st.tuples(_fields, _fields).filter(lambda ab: ab[0] != ab[1]),
       ops=st.lists(st.tuples(st.integers(0, 1), st.sampled_from(_LOOKUPS)), max_size=25))
def test_two_registries_never_interfere(fields: tuple[list[tuple[str, str]], ...],
                                        ops: list[tuple[int, str]]) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        roots = [_student(Path(tmp) / f"w{i}", fields[i]) for i in (0, 1)]
        worlds = [MessageRegistry([root]) for root in roots]
        for i, op in ops:                       # interleaved, in any order
            _look(worlds[i], op)
        for i in (0, 1):
            registry, mine = worlds[i], fields[i]
            alone = MessageRegistry([roots[i]])  # the same path, looked up in one order only
            Thing = registry.get_message_class("sub/Thing")
            assert Thing._slot_types == [t for t, _ in mine]
            assert Thing.__slots__ == tuple(n for _, n in mine)
            assert Thing._md5sum == alone.md5sum("sub/Thing") == registry.md5sum("sub/Thing")
            assert Thing._full_text == alone.full_text("sub/Thing")
            Holder = registry.get_message_class("sub/Holder")
            assert Holder._md5sum == alone.md5sum("sub/Holder")
            assert Holder._full_text == alone.full_text("sub/Holder")
            assert Holder().things == [] and Holder(things=[Thing()]).things[0].__class__ is Thing
            Ask = registry.get_service_class("sub/Ask")
            assert Ask._request_class().t.__class__ is Thing
            assert Ask._md5sum == alone.srv_md5sum("sub/Ask")
            msg = Holder(things=[Thing(), Thing()])
            assert deserialize_message(Holder, serialize_message(msg)) == msg
            # bundled types are the bundled classes, whatever the user package did
            assert registry.get_message_class("std_msgs/Header") is get_message_class("Header")
            assert registry.get_message_class("geometry_msgs/Point") is \
                get_message_class("geometry_msgs/Point")
        one, two = (w.get_message_class("sub/Thing") for w in worlds)
        assert one is not two and one._md5sum != two._md5sum
        assert one() != two()
        with pytest.raises(MsgNotFound):
            BUNDLED.get_message_class("sub/Thing")


@settings(max_examples=30, deadline=None)
@given(st.sampled_from(sorted(BUNDLED.iter_types("msg"))))
def test_bundled_message_classes_are_shared(type_name: str) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        user = MessageRegistry([_student(Path(tmp), [("int32", "x")])])
        nested = MessageRegistry([], parent=user)
        cls = get_message_class(type_name)
        assert user.get_message_class(type_name) is cls
        assert nested.get_message_class(type_name) is cls
        assert MessageRegistry().get_message_class(type_name) is cls
        assert user.md5sum(type_name) == cls._md5sum
        assert user.full_text(type_name) == cls._full_text


def test_bundled_service_classes_are_shared(tmp_path: Path) -> None:
    user = MessageRegistry([_student(tmp_path, [("int32", "x")])])
    for name in BUNDLED.iter_types("srv"):
        assert user.get_service_class(name) is get_service_class(name)
        assert user.srv_md5sum(name) == get_service_class(name)._md5sum


def test_user_types_use_the_bundled_classes(tmp_path: Path) -> None:
    registry = MessageRegistry([_student(tmp_path, [("geometry_msgs/Point", "where")])])
    Thing = registry.get_message_class("sub/Thing")
    assert Thing().where.__class__ is get_message_class("geometry_msgs/Point")
    assert registry.list_types("sub") == ["sub/Holder", "sub/Thing"]
    assert registry.list_types("std_msgs") == BUNDLED.list_types("std_msgs")
    assert "sub" in registry.list_packages() and "std_msgs" in registry.list_packages()
    assert registry.list_packages("srv") == sorted([*BUNDLED.list_packages("srv"), "sub"])
    assert registry.find("String") == ["std_msgs/String"]
    assert registry.find("Thing") == ["sub/Thing"]
    assert set(registry.iter_types()) == {*BUNDLED.iter_types(), "sub/Holder", "sub/Thing"}
    assert registry.parent is BUNDLED and BUNDLED.parent is None
    assert registry.search_path == (tmp_path, BUNDLED_PATH)
    assert repr(registry) == f"MessageRegistry([{str(tmp_path)!r}], parent=default_registry())"


def test_shadowing_a_bundled_package_rebuilds_what_depends_on_it(tmp_path: Path) -> None:
    _write(tmp_path, "std_msgs/msg/Header.msg", "uint32 seq\ntime stamp\nstring frame_id\n"
                                                 "string robot\n")
    registry = MessageRegistry([tmp_path])
    Header = registry.get_message_class("Header")
    assert Header is not get_message_class("Header") and Header().robot == ""
    assert registry.get_message_class("std_msgs/Header") is Header
    # a bundled type that uses the shadowed package is built against it, as a flat path would
    PoseStamped = registry.get_message_class("geometry_msgs/PoseStamped")
    assert PoseStamped is not get_message_class("geometry_msgs/PoseStamped")
    assert PoseStamped().header.__class__ is Header
    assert PoseStamped._md5sum != get_message_class("geometry_msgs/PoseStamped")._md5sum
    assert "string robot" in PoseStamped._full_text
    # ... and what does not use it is still the bundled class
    Pose = registry.get_message_class("geometry_msgs/Pose")
    assert Pose is get_message_class("geometry_msgs/Pose")
    assert PoseStamped().pose.__class__ is Pose
    # std_msgs types not shadowed by the user package are gone (the whole package is shadowed)
    with pytest.raises(MsgNotFound, match=r"Cannot locate message \[String\]"):
        registry.get_message_class("std_msgs/String")
    # the default registry is untouched
    assert get_message_class("Header")().__slots__ == ("seq", "stamp", "frame_id")


def test_a_chain_of_registries(tmp_path: Path) -> None:
    course = _student(tmp_path / "course", [("int32", "x")])
    _write(course, "course_msgs/msg/Grade.msg", "sub/Thing thing\nfloat32 score\n")
    student = _student(tmp_path / "student", [("string", "x")])
    base = MessageRegistry([course])
    top = MessageRegistry([student], parent=base)
    assert top.search_path == (student, course, BUNDLED_PATH)
    assert top.get_message_class("sub/Thing")._slot_types == ["string"]
    assert base.get_message_class("sub/Thing")._slot_types == ["int32"]
    # course_msgs/Grade uses sub/Thing, which the student shadows: rebuilt in `top`
    Grade = top.get_message_class("course_msgs/Grade")
    assert Grade is not base.get_message_class("course_msgs/Grade")
    assert Grade().thing.__class__ is top.get_message_class("sub/Thing")
    _write(course, "course_msgs/msg/Note.msg", "string text\n")
    base.rospack.refresh()
    top.rospack.refresh()
    assert top.get_message_class("course_msgs/Note") is base.get_message_class("course_msgs/Note")


def test_classes_from_definitions_keep_registries_apart(tmp_path: Path) -> None:
    one = MessageRegistry([_student(tmp_path / "one", [("int32", "x")])])
    two = MessageRegistry([_student(tmp_path / "two", [("string", "x")])])
    One, Two = one.get_message_class("sub/Holder"), two.get_message_class("sub/Holder")
    assert message_class_from_definition("sub/Holder", One._full_text, registry=one) is One
    assert message_class_from_definition("sub/Holder", Two._full_text, registry=two) is Two
    # the other world's definition does not become this world's class, nor the reverse
    from_one = message_class_from_definition("sub/Holder", One._full_text, registry=two)
    from_two = message_class_from_definition("sub/Holder", Two._full_text, registry=one)
    assert from_one not in (One, Two) and from_two not in (One, Two)
    assert from_one._md5sum == One._md5sum and from_two._md5sum == Two._md5sum
    # the cache is keyed by (type, text) and the class is a function of that alone
    assert message_class_from_definition("sub/Holder", One._full_text) is from_one
    assert message_class_from_definition("sub/Holder", One._full_text,
                                         registry=BUNDLED) is from_one
    # bundled types in a definition still come back as the shared classes
    Header = get_message_class("Header")
    assert message_class_from_definition("std_msgs/Header", Header._full_text,
                                         registry=one) is Header


# -- the bundled registry is immutable --------------------------------------------------------

def test_the_default_registry_cannot_be_changed() -> None:
    assert default_registry() is BUNDLED and BUNDLED.frozen
    spec = parse_msg("int32 x\n", "sneaky/Thing")
    with pytest.raises(DdesTypeError, match="bundled registry is shared"):
        BUNDLED.add_msg_spec(spec)
    with pytest.raises(TypeError):                 # DdesTypeError is a TypeError too
        BUNDLED.add_msg_spec(parse_msg("int32 data\n", "std_msgs/String"))
    with pytest.raises(MsgNotFound):
        BUNDLED.get_message_class("sneaky/Thing")
    assert get_message_class("std_msgs/String")().data == ""
    assert isinstance(BUNDLED.rospack.paths, tuple)
    assert BUNDLED.rospack.paths == (BUNDLED_PATH,)
    with pytest.raises(AttributeError):
        BUNDLED.rospack = RosPack(["/elsewhere"])  # type: ignore[misc]
    with pytest.raises(AttributeError):
        BUNDLED.parent = MessageRegistry()  # type: ignore[misc]
    assert "bundled" in repr(BUNDLED)
    assert not MessageRegistry().frozen
    user = MessageRegistry()
    user.add_msg_spec(spec)                         # a registry of one's own may be extended
    assert user.get_message_class("sneaky/Thing")().x == 0


def test_constructor_checks() -> None:
    with pytest.raises(DdesValueError, match="either paths/use_env or rospack"):
        MessageRegistry(["/x"], rospack=RosPack())
    with pytest.raises(DdesValueError, match="bundled=False means no parent"):
        MessageRegistry(bundled=False, parent=BUNDLED)
    with pytest.raises(DdesTypeError, match="must be a MessageRegistry"):
        MessageRegistry(parent="std_msgs")  # type: ignore[arg-type]
    assert MessageRegistry(bundled=False).parent is None
    assert MessageRegistry(parent=None).search_path == ()


# -- the environment is read only when asked ----------------------------------------------------

def test_env_var_set_after_import_changes_nothing(tmp_path: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    _student(tmp_path, [("int32", "x")])
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(tmp_path))
    with pytest.raises(MsgNotFound, match=r"unknown package \[sub\]"):
        get_message_class("sub/Thing")
    with pytest.raises(MsgNotFound):
        get_service_class("sub/Ask")
    with pytest.raises(MsgNotFound):
        MessageRegistry().get_message_class("sub/Thing")
    assert "sub" not in BUNDLED.list_packages() and "sub" not in RosPack()
    assert RosPack().paths == (BUNDLED_PATH,)


def test_env_var_set_before_import_changes_nothing(tmp_path: Path) -> None:
    _student(tmp_path, [("int32", "x")])
    code = ("from ddes.errors import MsgNotFound\n"
            "from ddes.msg import get_message_class, default_registry\n"
            "from ddes.rospack import RosPack\n"
            "try:\n    get_message_class('sub/Thing')\nexcept MsgNotFound:\n    pass\n"
            "else:\n    raise SystemExit('the default registry read DDES_PACKAGE_PATH')\n"
            "assert 'sub' not in default_registry().list_packages()\n"
            "assert 'sub' not in RosPack()\n"
            "print('ok')\n")
    root = str(Path(ddes.__file__).resolve().parents[1])
    env = dict(os.environ, DDES_PACKAGE_PATH=str(tmp_path),
               PYTHONPATH=os.pathsep.join([root, os.environ.get("PYTHONPATH", "")]))
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"


def test_from_environment_reads_it_explicitly(tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    first = _student(tmp_path / "first", [("int32", "x")])
    second = _student(tmp_path / "second", [("string", "x")])
    _write(second, "only_second/msg/Extra.msg", "bool flag\n")
    explicit = _student(tmp_path / "explicit", [("float64", "x")])
    environ = {"DDES_PACKAGE_PATH": f"{first}{os.pathsep}{os.pathsep}{second}"}
    registry = MessageRegistry.from_environment(environ)
    assert registry.search_path == (first, second, BUNDLED_PATH)
    assert registry.get_message_class("sub/Thing")._slot_types == ["int32"]   # first one wins
    assert registry.get_message_class("only_second/Extra")().flag is False
    environ["DDES_PACKAGE_PATH"] = ""               # read once, at the call
    assert registry.get_message_class("sub/Thing")._slot_types == ["int32"]
    ahead = MessageRegistry.from_environment({"DDES_PACKAGE_PATH": str(first)}, paths=[explicit])
    assert ahead.get_message_class("sub/Thing")._slot_types == ["float64"]
    assert MessageRegistry.from_environment({}).search_path == (BUNDLED_PATH,)
    assert MessageRegistry.from_environment({}, parent=None).search_path == ()
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(second))
    assert MessageRegistry.from_environment().get_message_class("sub/Thing")._slot_types == [
        "string"]
    # RosPack follows the same rule
    assert RosPack.from_environment(environ={"DDES_PACKAGE_PATH": str(first)}).paths == (
        first, BUNDLED_PATH)
    assert RosPack.from_environment({"DDES_PACKAGE_PATH": str(first)}, paths=[explicit],
                                    bundled=False).paths == (explicit, first)
    assert RosPack.from_environment().paths == (second, BUNDLED_PATH)
    assert RosPack(use_env=True).paths == (second, BUNDLED_PATH)
    assert RosPack([first]).paths == (first, BUNDLED_PATH)


def test_unknown_package_error_names_the_whole_path(tmp_path: Path) -> None:
    registry = MessageRegistry([tmp_path])
    with pytest.raises(MsgNotFound, match=r"unknown package \[nopkg\]") as info:
        registry.get_message_class("nopkg/Thing")
    text = str(info.value)
    assert str(tmp_path) in text and str(BUNDLED_PATH) in text
    assert "from_environment" in text and "World(package_path=" in text
    with pytest.raises(MsgNotFound, match=r"unknown package \[nopkg\]") as info:
        registry.get_service_class("nopkg/Srv")
    assert str(tmp_path) in str(info.value) and str(BUNDLED_PATH) in str(info.value)
    with pytest.raises(MsgNotFound, match=r"unknown package \[nopkg\]"):
        registry.get_action_spec("nopkg/Act")
    with pytest.raises(MsgNotFound, match=r"^package 'nopkg' not found; searched: ") as info:
        registry.list_types("nopkg")
    assert str(tmp_path) in str(info.value) and str(BUNDLED_PATH) in str(info.value)
