"""teleop_twist_keyboard: upstream's banner and status lines, its key map and parameters; keys
typed on ~keys (std_msgs/String, one key per character) drive the simulated SMB."""

from __future__ import annotations

import os
import pty
import sys
import termios
from typing import Any

import pytest

import ddes
from ddes.msg import get_message_class
from ddes.packages.teleop_twist_keyboard.nodes import MOVE_BINDINGS, SPEED_BINDINGS
from ddes.sim import Simulator

#: ros-teleop/teleop_twist_keyboard's msg (release 1.0.0, Noetic), as it prints it.
UPSTREAM = (
    "\nReading from the keyboard  and Publishing to Twist!\n"
    "---------------------------\n"
    "Moving around:\n"
    "   u    i    o\n"
    "   j    k    l\n"
    "   m    ,    .\n"
    "\n"
    "For Holonomic mode (strafing), hold down the shift key:\n"
    "---------------------------\n"
    "   U    I    O\n"
    "   J    K    L\n"
    "   M    <    >\n"
    "\n"
    "t : up (+z)\n"
    "b : down (-z)\n"
    "\n"
    "anything else : stop\n"
    "\n"
    "q/z : increase/decrease max speeds by 10%\n"
    "w/x : increase/decrease only linear speed by 10%\n"
    "e/c : increase/decrease only angular speed by 10%\n"
    "\n"
    "CTRL-C to quit\n"
)


Twists = list[tuple[float, float, float]]


def start(*params: str) -> tuple[ddes.Console, Simulator, Twists]:
    console = ddes.Console(seed=0)
    console.run("rosrun ddes_sim simulator _world:=empty _noise:=false &")
    node = console.world.master.lookup_node("/simulator")
    assert node is not None
    (sim,) = [e for e in node.entities if isinstance(e, Simulator)]
    twists: list[tuple[float, float, float]] = []
    probe = console.world.create_node("probe")
    probe.subscribe("/cmd_vel", get_message_class("geometry_msgs/Twist"),
                    lambda m: twists.append((m.linear.x, m.linear.y, m.angular.z)))
    typist = console.world.create_node("typist")
    pub = typist.advertise("/teleop_twist_keyboard/keys", get_message_class("std_msgs/String"),
                           queue_size=10)
    TYPISTS[console] = pub
    out = console.run("rosrun teleop_twist_keyboard teleop_twist_keyboard.py "
                      + " ".join(params) + " &")
    assert out.startswith("[")
    return console, sim, twists


TYPISTS: dict[ddes.Console, Any] = {}


def keys(console: ddes.Console, text: str) -> None:
    """Type ``text`` now (each character one key press), as a script would on ~keys."""
    TYPISTS[console].publish(text)


def test_banner_and_status_line_are_upstreams() -> None:
    console, _sim, twists = start()
    out = console.run("sleep 1")
    assert out == UPSTREAM + "\n" + "currently:\tspeed 0.5\tturn 1.0 \n"
    assert twists == [(0.0, 0.0, 0.0)]  # the publish thread's first update
    out = console.run('rostopic pub -1 /teleop_twist_keyboard/keys std_msgs/String "data: q"')
    assert "currently:\tspeed 0.55\tturn 1.1 \n" in out
    assert twists[-1] == (0.0, 0.0, 0.0)  # a speed key publishes the (still zero) twist


def test_key_map_is_upstreams() -> None:
    assert MOVE_BINDINGS["i"] == (1, 0, 0, 0) and MOVE_BINDINGS["j"] == (0, 0, 0, 1)
    assert MOVE_BINDINGS["o"] == (1, 0, 0, -1) and MOVE_BINDINGS["m"] == (-1, 0, 0, -1)
    assert MOVE_BINDINGS["J"] == (0, 1, 0, 0) and MOVE_BINDINGS[">"] == (-1, -1, 0, 0)
    assert sorted(MOVE_BINDINGS) == sorted("uiojlm,.UIOJLM<>tb")
    assert SPEED_BINDINGS == {"q": (1.1, 1.1), "z": (0.9, 0.9), "w": (1.1, 1), "x": (0.9, 1),
                              "e": (1, 1.1), "c": (1, 0.9)}


def test_keys_drive_the_robot_with_repeat_rate() -> None:
    console, sim, twists = start("_repeat_rate:=10")
    console.run("sleep 1")
    keys(console, "i")              # forward at 0.5 m/s, repeated at 10 Hz
    console.run("sleep 2")
    truth = sim.truth
    assert truth.v == 0.5 and 0.7 < truth.x < 1.0 and truth.y == 0.0
    assert twists[-1] == (0.5, 0.0, 0.0) and len(twists) >= 20
    keys(console, "j")              # turn left on the spot at 1 rad/s
    console.run("sleep 1")
    assert sim.truth.v == 0.0 and sim.truth.w == 1.0 and sim.truth.yaw > 0.5
    keys(console, "k")              # anything else: stop
    console.run("sleep 1")
    assert sim.truth.v == 0.0 and sim.truth.w == 0.0 and twists[-1] == (0.0, 0.0, 0.0)


def test_one_key_without_repeat_moves_briefly_as_the_cmd_vel_timeout_says() -> None:
    console, sim, twists = start()
    console.run("sleep 1")
    keys(console, "i")
    console.run("sleep 2")
    assert twists[-1] == (0.5, 0.0, 0.0)  # published once
    assert sim.truth.v == 0.0 and 0.05 < sim.truth.x < 0.2  # 0.25 s of command, then brakes


def test_speed_keys_scale_and_the_banner_returns_every_15th_time() -> None:
    console, _sim, twists = start("_speed:=1.0", "_turn:=2.0")
    console.run("sleep 1")
    keys(console, "w" * 14)
    out = console.run("sleep 0.1")
    assert out.count("currently:") == 14 and "Reading from the keyboard" not in out
    keys(console, "x")
    out = console.run("sleep 0.1")
    assert out.startswith("currently:\tspeed ") and UPSTREAM in out
    keys(console, "u")
    console.run("sleep 0.1")
    speed = 1.0
    for f in [1.1] * 14 + [0.9]:
        speed *= f
    assert twists[-1] == (speed, 0.0, 2.0)


def test_key_timeout_stops_and_ctrl_c_quits_with_a_stop() -> None:
    console, sim, twists = start("_repeat_rate:=20", "_key_timeout:=0.5")
    console.run("sleep 1")
    keys(console, "u")
    console.run("sleep 0.3")
    assert twists[-1] == (0.5, 0.0, 1.0)
    console.run("sleep 1")
    assert twists[-1] == (0.0, 0.0, 0.0) and sim.truth.v == 0.0
    console.run("sleep 0.05")
    n = len(twists)
    keys(console, "i\x03")          # a key, then Ctrl-C
    console.run("sleep 0.5")
    assert twists[-2:] == [(0.5, 0.0, 0.0), (0.0, 0.0, 0.0)]  # the key, then the exit's stop
    assert len(twists) == n + 2
    assert "/teleop_twist_keyboard" not in console.run("rosnode list")


def test_waits_for_a_subscriber_as_upstream_says() -> None:
    console = ddes.Console(seed=0)
    console.run("rosrun teleop_twist_keyboard teleop_twist_keyboard.py &")
    out = console.run("sleep 5")
    assert out == "Waiting for subscriber to connect to /cmd_vel\n" * 2  # at 2.0 s and 4.5 s
    console.world.create_node("listener").subscribe("/cmd_vel",
                                                    get_message_class("geometry_msgs/Twist"))
    out = console.run("sleep 1")
    assert out.endswith("currently:\tspeed 0.5\tturn 1.0 \n")


def test_keys_typed_on_a_terminal_go_out_on_keys(monkeypatch: pytest.MonkeyPatch) -> None:
    master, slave = pty.openpty()
    with os.fdopen(slave, "r") as tty_in:
        monkeypatch.setattr(sys, "stdin", tty_in)
        console, sim, twists = start("_stdin:=true", "_repeat_rate:=10")
        console.run("sleep 1")
        os.write(master, b"i")
        console.run("sleep 1")
        typed = console.world.trace.select(kind="topic.publish", source="/teleop_twist_keyboard",
                                           topic="/teleop_twist_keyboard/keys")
        assert len(typed) == 1           # the key, recorded for a replay
        assert twists[-1] == (0.5, 0.0, 0.0) and sim.truth.v == 0.5
        cbreak = termios.tcgetattr(slave)
        assert not cbreak[3] & termios.ICANON  # keys, not lines, while it runs
        console.run("rosnode kill /teleop_twist_keyboard")
        assert termios.tcgetattr(slave)[3] & termios.ICANON  # the terminal restored
    os.close(master)
