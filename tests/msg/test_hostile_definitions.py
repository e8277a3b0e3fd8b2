"""Hostile message definitions and wire data (issue 13): typed errors, never a crash or a hang."""

from __future__ import annotations

import struct
from pathlib import Path

import pytest

from ddes.errors import DeserializationError, InvalidMsgSpec
from ddes.msg import MessageRegistry, codegen, get_message_class
from ddes.msg.registry import message_class_from_definition, parse_definition
from ddes.msg.wire import deserialize_message, serialize_message

SEP = "=" * 80
EMPTY_DEP = f"\n{SEP}\nMSG: std_msgs/Empty\n"


def _holder() -> type:
    full = "std_msgs/Empty[] items\nint32 tail\nstd_msgs/Empty[2] fixed\n" + EMPTY_DEP
    return message_class_from_definition("hostile/Holder", full)


def test_empty_array_round_trips_like_genpy() -> None:
    # genpy writes the count and nothing per element: bytes and md5 checked against
    # genpy.dynamic.generate_dynamic on ROS Noetic (/usr/bin/python3)
    holder = _holder()
    empty = holder._fields_info[0].cls
    msg = holder(items=[empty(), empty(), empty()], tail=7, fixed=[empty(), empty()])
    data = serialize_message(msg)
    assert data.hex() == "0300000007000000"
    assert holder._md5sum == "3aa50061ae5e0163128cc67011d3795d"
    back = deserialize_message(holder, data)
    assert len(back.items) == 3 and back.tail == 7 and len(back.fixed) == 2
    assert back == msg
    assert serialize_message(holder()) == b"\x00\x00\x00\x00\x00\x00\x00\x00"


def test_empty_array_with_a_huge_count_is_refused_before_allocating() -> None:
    holder = _holder()
    data = struct.pack("<Ii", 4_000_000_000, 1)
    with pytest.raises(DeserializationError, match="MAX_ZERO_SIZE_ELEMENTS"):
        deserialize_message(holder, data)


def test_huge_array_count_on_a_short_buffer_is_refused_before_allocating() -> None:
    scan = get_message_class("sensor_msgs/JointState")
    data = bytes(12) + b"\x00\x00\x00\x00" + struct.pack("<I", 4_000_000_000) + bytes(6)
    with pytest.raises(DeserializationError, match="declares 4000000000 elements"):
        deserialize_message(scan, data)
    multi = get_message_class("std_msgs/Int32MultiArray")
    with pytest.raises(DeserializationError, match="only 6 bytes remain"):
        deserialize_message(multi, struct.pack("<I", 0xFFFFFFF0) + bytes(6))


def test_invalid_utf8_in_a_string_field_is_replaced_as_genpy_does() -> None:
    # genpy decodes with its 'rosmsg' handler: codecs.replace_errors (U+FFFD), logged once
    string = get_message_class("std_msgs/String")
    msg = deserialize_message(string, b"\x03\x00\x00\x00a\xff\xfe")
    assert msg.data == "a\ufffd\ufffd"


def test_non_utf8_msg_file_names_file_line_and_byte(tmp_path: Path) -> None:
    folder = tmp_path / "bad_pkg" / "msg"
    folder.mkdir(parents=True)
    (folder / "Latin.msg").write_bytes(b"int32 x\n# caf\xe9\nint32 y\n")
    registry = MessageRegistry([tmp_path])
    with pytest.raises(InvalidMsgSpec, match=r"Latin\.msg:2: invalid UTF-8 byte b'\\xe9' at "
                                             r"byte offset 13"):
        registry.get_message_class("bad_pkg/Latin")
    (tmp_path / "bad_pkg" / "srv").mkdir()
    (tmp_path / "bad_pkg" / "srv" / "S.srv").write_bytes(b"int32 a\n---\n\xff\n")
    with pytest.raises(InvalidMsgSpec, match=r"S\.srv:3: invalid UTF-8"):
        registry.get_service_class("bad_pkg/S")
    (tmp_path / "bad_pkg" / "action").mkdir()
    (tmp_path / "bad_pkg" / "action" / "A.action").write_bytes(b"\xc3\n---\n---\n")
    with pytest.raises(InvalidMsgSpec, match=r"A\.action:1: invalid UTF-8"):
        registry.get_message_class("bad_pkg/AGoal")


def test_definition_bytes_and_surrogates() -> None:
    cls = message_class_from_definition("hostile/B", b"int32 x # caf\xc3\xa9\n")
    assert cls().x == 0
    with pytest.raises(InvalidMsgSpec, match=r"hostile/B>:2: invalid UTF-8 byte b'\\xff' at byte "
                                             r"offset 8"):
        message_class_from_definition("hostile/B", b"int32 x\n\xff")
    with pytest.raises(InvalidMsgSpec, match="lone surrogate"):
        parse_definition("hostile/B", "int32 x # \udcff\n")
    with pytest.raises(InvalidMsgSpec, match="lone surrogate"):
        message_class_from_definition("hostile/B", "string S=\udcff\n")
    with pytest.raises(InvalidMsgSpec, match="not a legal message type"):
        message_class_from_definition("bad name%s", "int32 x\n")
    with pytest.raises(InvalidMsgSpec, match="not a legal message type"):
        message_class_from_definition("a/B\n", "int32 x\n")
    with pytest.raises(InvalidMsgSpec, match="must be str or bytes"):
        message_class_from_definition("a/B", 12)  # type: ignore[arg-type]
    with pytest.raises(InvalidMsgSpec, match="must be a string"):
        message_class_from_definition(["a/B"], "int32 x\n")  # type: ignore[arg-type]
    with pytest.raises(InvalidMsgSpec, match="not a legal message type"):
        parse_definition("a/B", f"a/C c\n{SEP}\nMSG: a/C%d\nint32 x\n")


def test_recursive_and_deep_definitions() -> None:
    with pytest.raises(InvalidMsgSpec, match="circular message dependency a/A -> a/A"):
        message_class_from_definition("a/A", "a/A[] children\n")
    mutual = f"a/B b\n{SEP}\nMSG: a/B\na/A a\n"
    with pytest.raises(InvalidMsgSpec, match="circular message dependency"):
        message_class_from_definition("a/A", mutual)
    depth = 1000
    chain = "a/T0 x\n" + "".join(
        f"{SEP}\nMSG: a/T{i}\n" + (f"a/T{i + 1}[] x\n" if i < depth else "int32 y\n")
        for i in range(depth + 1))
    with pytest.raises(InvalidMsgSpec, match="MAX_NESTING_DEPTH"):
        message_class_from_definition("a/Top", chain)
    ok = "a/T0 x\n" + "".join(
        f"{SEP}\nMSG: a/T{i}\n" + (f"a/T{i + 1} x\n" if i < 50 else "int32[] y\n")
        for i in range(51))
    cls = message_class_from_definition("a/Top", ok)  # 50 deep, inlined
    assert deserialize_message(cls, serialize_message(cls())) == cls()
    # arrays nest Python for-loops: genpy's code stops compiling at 20 (SyntaxError);
    # ddes reports it as InvalidMsgSpec naming the type
    loops = "a/T0[] x\n" + "".join(
        f"{SEP}\nMSG: a/T{i}\n" + (f"a/T{i + 1}[] x\n" if i < 30 else "int32 y\n")
        for i in range(31))
    with pytest.raises(InvalidMsgSpec, match="too many statically nested blocks"):
        message_class_from_definition("a/Top", loops)


def test_exponential_fan_out_and_huge_fixed_arrays() -> None:
    levels = 30
    text = "".join(f"a/L1 f{j}\n" for j in range(10)) + "".join(
        f"{SEP}\nMSG: a/L{i}\n" + ("".join(f"a/L{i + 1} f{j}\n" for j in range(10))
                                    if i < levels else "int32 y\n")
        for i in range(1, levels + 1))
    with pytest.raises(InvalidMsgSpec, match="MAX_FLAT_FIELDS"):
        message_class_from_definition("a/Bomb", text)
    with pytest.raises(InvalidMsgSpec, match="MAX_DEFAULT_ELEMENTS"):
        message_class_from_definition("a/Big", "int32[4000000000] x\n")
    with pytest.raises(InvalidMsgSpec, match="MAX_DEFAULT_ELEMENTS"):
        message_class_from_definition("a/Big", f"a/C[100000] c\n{SEP}\nMSG: a/C\nint8[1000] x\n")
    with pytest.raises(InvalidMsgSpec, match="array size"):
        message_class_from_definition("a/Big", "int32[\u0663] x\n")  # an Arabic-Indic digit


def test_codegen_turns_a_syntax_error_into_invalid_msg_spec(monkeypatch: pytest.MonkeyPatch) -> None:
    from ddes.msg.message import FieldInfo

    real = codegen.field_infos

    def hostile(spec, resolve):  # type: ignore[no-untyped-def]
        infos = real(spec, resolve)
        return tuple(FieldInfo(*(("x y",) + tuple(i)[1:])) for i in infos)

    monkeypatch.setattr(codegen, "field_infos", hostile)
    with pytest.raises(InvalidMsgSpec, match="cannot generate a class for 'hostile/Syn'"):
        message_class_from_definition("hostile/Syn", "int32 x\n")


def test_a_huge_msg_file_is_refused_before_it_is_read(tmp_path: Path) -> None:
    import tracemalloc

    from ddes.errors import ResourceLimitError
    from ddes.msg.registry import MAX_DEFINITION_BYTES

    folder = tmp_path / "big_pkg" / "msg"
    folder.mkdir(parents=True)
    with open(folder / "Big.msg", "wb") as f:  # sparse: 4 GiB of nothing on disk
        f.truncate(4 << 30)
    (folder / "Fine.msg").write_text("int32 x\n" + "#" * (MAX_DEFINITION_BYTES - 20) + "\n")
    registry = MessageRegistry([tmp_path])
    tracemalloc.start()
    try:
        with pytest.raises(ResourceLimitError, match=rf"Big\.msg: the definition is larger than "
                                                     rf"{MAX_DEFINITION_BYTES} bytes"):
            registry.get_msg_spec("big_pkg/Big")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1 << 20
    assert registry.get_message_class("big_pkg/Fine")().x == 0
