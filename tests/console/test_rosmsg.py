"""``ddes rosmsg`` / ``ddes rossrv``: output layout, bare types, user packages, errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from ddes.cli.main import main


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_show_expands_nested_types(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "rosmsg", "show", "geometry_msgs/PoseStamped")
    assert code == 0
    assert out == (
        "std_msgs/Header header\n"
        "  uint32 seq\n"
        "  time stamp\n"
        "  string frame_id\n"
        "geometry_msgs/Pose pose\n"
        "  geometry_msgs/Point position\n"
        "    float64 x\n"
        "    float64 y\n"
        "    float64 z\n"
        "  geometry_msgs/Quaternion orientation\n"
        "    float64 x\n"
        "    float64 y\n"
        "    float64 z\n"
        "    float64 w\n"
        "\n"
    )


def test_show_constants_first(capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "rosmsg", "info", "sensor_msgs/NavSatStatus")
    assert out.splitlines()[:2] == ["int8 STATUS_NO_FIX=-1", "int8 STATUS_FIX=0"]
    assert out.endswith("int8 status\nuint16 service\n\n")


def test_show_raw_prints_file_text(capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "rosmsg", "show", "-r", "std_msgs/Header")
    assert out.startswith("# Standard metadata for higher-level stamped data types.\n")
    _, out, _ = run(capsys, "rossrv", "show", "--raw", "std_srvs/SetBool")
    assert out == "bool data # e.g. for hardware enabling / disabling\n---\n" \
                  "bool success   # indicate successful run of triggered service\n" \
                  "string message # informational, e.g. for error messages\n\n"


def test_rossrv_show(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "rossrv", "show", "std_srvs/SetBool")
    assert (code, out) == (0, "bool data\n---\nbool success\nstring message\n\n")
    _, out, _ = run(capsys, "rossrv", "show", "roscpp_tutorials/TwoInts.srv")
    assert out == "int64 a\nint64 b\n---\nint64 sum\n\n"


def test_bare_type_prints_each_match(capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "rossrv", "show", "AddTwoInts")
    assert out == "[rospy_tutorials/AddTwoInts]:\nint64 a\nint64 b\n---\nint64 sum\n\n"
    code, _, err = run(capsys, "rosmsg", "show", "NoSuchType")
    assert code == 1 and err == "Could not find msg 'NoSuchType'\n"


def test_md5(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "rosmsg", "md5", "std_msgs/String")[1] == "992ce8a1687cec8c8bd883ec73ca41d1\n"
    assert run(capsys, "rosmsg", "md5", "String")[1] == \
        "[std_msgs/String]: 992ce8a1687cec8c8bd883ec73ca41d1\n"
    assert run(capsys, "rossrv", "md5", "std_srvs/SetBool")[1] == \
        "09fb03525b03e7ea1fd3992bafd87e16\n"
    assert run(capsys, "rosmsg", "md5", "std_msgs/Nope")[2] == "Cannot locate [std_msgs/Nope]\n"
    assert run(capsys, "rosmsg", "md5", "Nope")[2] == "No messages matching the name [Nope]\n"


def test_list_package_packages(capsys: pytest.CaptureFixture[str]) -> None:
    _, out, _ = run(capsys, "rosmsg", "list")
    lines = out.splitlines()
    assert "std_msgs/String" in lines and "actionlib_tutorials/FibonacciActionGoal" in lines
    assert lines == sorted(lines, key=lambda t: tuple(t.split("/")))
    _, out, _ = run(capsys, "rosmsg", "package", "actionlib_msgs")
    assert out == "actionlib_msgs/GoalID\nactionlib_msgs/GoalStatus\nactionlib_msgs/GoalStatusArray\n"
    _, out, _ = run(capsys, "rossrv", "package", "-s", "std_srvs")
    assert out == "std_srvs/Empty std_srvs/SetBool std_srvs/Trigger\n"
    _, out, _ = run(capsys, "rossrv", "packages")
    assert "std_srvs" in out.split() and "std_msgs" not in out.split()
    code, _, err = run(capsys, "rosmsg", "package", "nope_pkg")
    assert code == 64 and err.startswith("Invalid package: package 'nope_pkg' not found")


def test_user_packages_from_env(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "my_pkg" / "msg").mkdir(parents=True)
    (tmp_path / "my_pkg" / "msg" / "Num.msg").write_text("int64 num  # a number\nint8 ONE=1\n")
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(tmp_path))
    assert run(capsys, "rosmsg", "show", "my_pkg/Num")[1] == "int8 ONE=1\nint64 num\n\n"
    assert run(capsys, "rosmsg", "show", "Num")[1] == "[my_pkg/Num]:\nint8 ONE=1\nint64 num\n\n"


def test_errors(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                monkeypatch: pytest.MonkeyPatch) -> None:
    code, _, err = run(capsys, "rosmsg", "show", "std_msgs/Nope")
    assert code == 1 and err.startswith("Unable to load msg [std_msgs/Nope]: Cannot locate")
    code, _, err = run(capsys, "rossrv", "show", "std_srvs/Nope")
    assert code == 1 and err.startswith("Unknown srv type [std_srvs/Nope]: Cannot locate")
    (tmp_path / "bad" / "msg").mkdir(parents=True)
    (tmp_path / "bad" / "msg" / "B.msg").write_text("int32 x\nWhat w\n")
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(tmp_path))
    code, _, err = run(capsys, "rosmsg", "show", "bad/B")
    assert code == 1 and "B.msg:2: unknown type [bad/What]" in err
    with pytest.raises(SystemExit):
        main(["rosmsg", "show", "std_msgs::String"])
    assert "C++-style namespaces" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["rosmsg", "show", "std_msgs.String"])
    assert "invalid message type 'std_msgs.String'" in capsys.readouterr().err


def test_usage_without_command(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "rossrv")
    assert code == 0
    assert out.startswith("rossrv is a command-line tool for displaying information about ROS "
                          "Service types.")


def _diamond(root: Path, depth: int) -> None:
    """``diamond/T0`` .. ``T{depth}``: each type holds the next one twice (``T{depth}`` an int)."""
    (root / "diamond" / "msg").mkdir(parents=True)
    for i in range(depth):
        (root / "diamond" / "msg" / f"T{i}.msg").write_text(f"T{i + 1} a\nT{i + 1} b\n")
    (root / "diamond" / "msg" / f"T{depth}.msg").write_text("int32 x\n")


def test_show_refuses_a_diamond_before_building_its_text(
        capsys: pytest.CaptureFixture[str], tmp_path: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Types holding the next one twice, 40 deep: 3 * 2**40 lines (ddes printed for hours, 3.9 GB in
    the first minute); now refused from sizes memoised per type, before any text is built."""
    import tracemalloc

    from ddes.console.rosmsg import MAX_SHOW_CHARS

    _diamond(tmp_path, 40)
    monkeypatch.setenv("DDES_PACKAGE_PATH", str(tmp_path))
    tracemalloc.start()
    try:
        code, out, err = run(capsys, "rosmsg", "show", "diamond/T0")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert code == 1 and out == ""
    assert err.startswith(f"ERROR: rosmsg show diamond/T0 would print {3 * 2**40 - 2} lines (")
    assert f"more than ddes.console.rosmsg.MAX_SHOW_CHARS ({MAX_SHOW_CHARS})" in err
    assert "'show -r'" in err
    assert peak < 16 * 2**20
    # below the limit the text is the full expansion, exactly as before (and as rosmsg prints)
    code, out, _ = run(capsys, "rosmsg", "show", "diamond/T37")
    assert code == 0
    assert out == ("diamond/T38 a\n  diamond/T39 a\n    diamond/T40 a\n      int32 x\n"
                   "    diamond/T40 b\n      int32 x\n  diamond/T39 b\n    diamond/T40 a\n"
                   "      int32 x\n    diamond/T40 b\n      int32 x\n"
                   "diamond/T38 b\n  diamond/T39 a\n    diamond/T40 a\n      int32 x\n"
                   "    diamond/T40 b\n      int32 x\n  diamond/T39 b\n    diamond/T40 a\n"
                   "      int32 x\n    diamond/T40 b\n      int32 x\n\n")
    assert run(capsys, "rosmsg", "md5", "diamond/T37")[0] == 0


def test_show_size_is_the_length_of_the_text(tmp_path: Path) -> None:
    from ddes.console.rosmsg import show_size, spec_to_str
    from ddes.msg.registry import MessageRegistry

    _diamond(tmp_path, 6)
    registry = MessageRegistry.from_environment({"DDES_PACKAGE_PATH": str(tmp_path)})
    for name in ("diamond/T0", "geometry_msgs/PoseStamped", "sensor_msgs/NavSatStatus",
                 "visualization_msgs/InteractiveMarkerUpdate"):
        registry.md5sum(name)
        text = spec_to_str(registry, registry.get_msg_spec(name))
        assert show_size(registry, registry.get_msg_spec(name)) == (text.count("\n"), len(text))
