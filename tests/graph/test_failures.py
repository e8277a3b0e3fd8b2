"""A failing node never takes the world down (rospy's rule), unless strict (issue 13, item 5)."""

from __future__ import annotations

import traceback
from collections.abc import Generator
from pathlib import Path, PurePath
from typing import Any

import pytest

import ddes
from ddes.graph.failures import STRICT_DEFAULT, is_library_file, strict_worlds

String = ddes.get_message_class("std_msgs/String")


def _world(strict: bool) -> tuple[ddes.World, Any, list[str]]:
    world = ddes.World(strict=strict)
    lines: list[str] = []
    world.log_output = lambda line, level: lines.append(line)
    talker = world.create_node("talker")
    pub = ddes.Publisher(talker, "t", String, queue_size=10)
    return world, pub, lines


def bad_callback(msg: Any) -> None:
    raise ValueError(f"cannot handle {msg.data}")


def test_a_failing_subscriber_is_logged_as_rospy_does_and_the_world_goes_on() -> None:
    world, pub, lines = _world(strict=False)
    node = world.create_node("listener")
    got: list[str] = []
    ddes.Subscriber(node, "t", String, bad_callback)
    ddes.Subscriber(node, "t", String, lambda m: got.append(m.data))
    for k in range(3):
        world.call_at(10_000_000 * (k + 1), lambda k=k: pub.publish(data=f"m{k}"))
    world.run(until=1)
    assert got == ["m0", "m1", "m2"]  # the world, and the node, went on
    errors = [ln for ln in lines if "bad callback" in ln]
    assert len(errors) == 3
    assert "bad callback: bad_callback" in errors[0]
    assert 'File "test_failures.py"' in errors[0] and "ValueError: cannot handle m0" in errors[0]
    assert "simpy" not in errors[0]
    assert len(world.trace.select(kind="callback.exception")) == 3
    assert len(world.callback_errors) == 3


def test_without_a_log_output_the_traceback_goes_to_stderr(capsys: pytest.CaptureFixture[str]
                                                            ) -> None:
    world = ddes.World(strict=False)
    node = world.create_node("n")
    ddes.Timer(node, 0.1, lambda _e: 1 / 0, oneshot=True)
    world.run(until=1)
    err = capsys.readouterr().err
    # rospy's line, printed by default (ddes.graph.rosout's handler on the ddes.node logger)
    assert "[ERROR] [0.100000]: bad callback: " in err and "ZeroDivisionError" in err


def test_a_failing_main_shuts_its_node_down_and_the_others_go_on() -> None:
    world, pub, lines = _world(strict=False)
    crashing = world.create_node("crashing")
    ticks: list[int] = []
    ddes.Timer(world.create_node("steady"), 0.1, lambda _e: ticks.append(world.now))

    def main() -> Generator[Any, Any, None]:
        yield crashing.sleep(0.25)
        raise RuntimeError("the student's bug")

    crashing.process(main())
    world.run(until=1)
    assert crashing.is_shutdown() and "/crashing" not in world.nodes
    assert len(ticks) == 9
    exit_ev = world.trace.select(kind="node.exit", source="/crashing").first()
    assert exit_ev is not None and exit_ev.details["code"] == 1
    assert "RuntimeError: the student's bug" in exit_ev.details["error"]
    assert any("the student's bug" in ln and "main" in ln for ln in lines)


def test_strict_raises_the_first_error_with_the_user_s_frames_on_top() -> None:
    world, pub, _lines = _world(strict=True)
    node = world.create_node("listener")
    ddes.Subscriber(node, "t", String, bad_callback)
    world.call_at(10_000_000, lambda: pub.publish(data="x"))
    with pytest.raises(ValueError, match="cannot handle x") as err:
        world.run(until=1)
    frames = traceback.extract_tb(err.value.__traceback__)
    assert not any("simpy" in PurePath(f.filename).parts for f in frames)
    assert frames[-1].name == "bad_callback"


def test_strict_raises_a_generator_callback_s_error_itself() -> None:
    world, pub, _lines = _world(strict=True)
    node = world.create_node("listener")

    def slow_bad(msg: Any) -> Generator[Any, Any, None]:
        yield node.sleep(0.1)
        raise KeyError("late")

    ddes.Subscriber(node, "t", String, slow_bad)
    world.call_at(10_000_000, lambda: pub.publish(data="x"))
    with pytest.raises(KeyError, match="late") as err:
        world.run(until=1)
    assert traceback.extract_tb(err.value.__traceback__)[-1].name == "slow_bad"


def test_strict_raises_a_failing_main() -> None:
    world = ddes.World(strict=True)
    node = world.create_node("n")

    def main() -> Generator[Any, Any, None]:
        yield node.sleep(0.1)
        raise RuntimeError("boom")

    node.process(main())
    with pytest.raises(RuntimeError, match="boom"):
        world.run(until=1)


def test_strictness_defaults_from_the_context() -> None:
    token = STRICT_DEFAULT.set(False)
    try:
        assert not ddes.World().strict
        with strict_worlds():
            assert ddes.World().strict and not ddes.World(strict=False).strict
        assert not ddes.World().strict
    finally:
        STRICT_DEFAULT.reset(token)
    world = ddes.World(strict=False)
    world.raise_callback_errors = True  # the older name
    assert world.strict


def test_library_files_are_told_from_user_files(tmp_path: Path) -> None:
    """By where ddes and SimPy are installed, not by folder names."""
    import simpy

    here = Path(ddes.__file__).resolve().parent
    assert is_library_file(str(here / "graph" / "node.py"))
    assert is_library_file(str(Path(simpy.__file__).parent / "core.py"))
    assert not is_library_file("/home/me/ddes_homework/talker.py")
    assert not is_library_file(str(here / "packages" / "rospy_tutorials" / "nodes.py"))
    # a clone (or a homework folder) called ddes, with a simpy folder inside: the user's
    assert not is_library_file("/home/me/ddes/talker.py")
    assert not is_library_file("/home/me/ddes/exercises/ex1/scripts/talker.py")
    assert not is_library_file("/home/me/simpy/sim.py")


def test_a_script_in_a_folder_called_ddes_keeps_its_traceback(tmp_path: Path) -> None:
    from ddes.compat.scripts import run_script

    folder = tmp_path / "ddes" / "scripts"
    folder.mkdir(parents=True)
    script = folder / "crash.py"
    script.write_text("import rospy\nrospy.init_node('crash')\nraise ValueError('boom')\n")
    world = ddes.World(strict=False)
    lines: list[str] = []
    world.log_output = lambda line, _level: lines.append(line)
    printed: list[str] = []
    run_script(world, script, print_line=lambda t, _e: printed.append(t))
    world.run(until=0.1)
    text = "\n".join(lines + printed)
    assert 'File "crash.py", line 3, in <module>' in text, text


def test_a_failing_run_has_the_same_digest_on_every_path() -> None:
    digests = set()
    for _ in range(2):
        world, pub, _lines = _world(strict=False)
        ddes.Subscriber(world.create_node("l"), "t", String, bad_callback)
        world.call_at(10_000_000, lambda p=pub: p.publish(data="x"))
        world.run(until=1)
        digests.add(world.digest())
    assert len(digests) == 1


@pytest.mark.parametrize("strict", [False, True])
def test_a_process_yielding_a_non_event_is_a_typed_error(strict: bool) -> None:
    world = ddes.World(strict=strict)
    lines: list[str] = []
    world.log_output = lambda line, level: lines.append(line)
    node = world.create_node("n")

    def main() -> Generator[Any, Any, None]:
        yield node.sleep(0.1)
        yield 5  # type: ignore[misc]

    node.process(main())
    if strict:
        with pytest.raises(ddes.errors.BadYieldError, match="yielded 5, which is not an event"):
            world.run(until=1)
        return
    world.run(until=1)
    assert node.is_shutdown()
    assert any("BadYieldError" in ln and "yielded 5" in ln for ln in lines)
