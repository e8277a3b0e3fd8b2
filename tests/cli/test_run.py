"""``ddes run`` (launch file or Python scenario) and ``ddes roslaunch`` from the shell prompt."""

from __future__ import annotations

from pathlib import Path

import pytest

from ddes.cli.main import main
from ddes.rospack import BUNDLED_PATH

SCENARIO = '''
def scenario(world):
    from ddes.msg import get_message_class
    string = get_message_class("std_msgs/String")
    talker = world.create_node("talker")
    pub = talker.advertise("chatter", string, queue_size=10)
    listener = world.create_node("listener")
    listener.subscribe("chatter", string, lambda m: listener.loginfo("I heard %s", m.data))
    world.set_link("/chatter", latency=lambda rng: rng.uniform(0.001, 0.01), loss=0.2)

    def main():
        rate = talker.create_rate(4)
        while True:
            pub.publish("tick %.2f" % talker.get_time())
            yield rate.sleep()

    talker.process(main())
'''


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_python_scenario_prints_logs_and_digest(tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "chat.py"
    path.write_text(SCENARIO)
    code, out, _ = run(capsys, "run", str(path), "--until", "2", "--seed", "3")
    assert code == 0
    lines = out.splitlines()
    assert all(line.startswith("[INFO] [") and "I heard tick" in line for line in lines[:-2])
    assert lines[-2].startswith("simulated 2.000 s; ")
    assert lines[-1].startswith("trace digest: ")
    assert run(capsys, "run", str(path), "--until", "2", "--seed", "3")[1] == out
    other = run(capsys, "run", str(path), "--until", "2", "--seed", "4")[1]
    assert other.splitlines()[-1] != lines[-1]  # other losses, other digest


def test_launch_file_scenario(capsys: pytest.CaptureFixture[str]) -> None:
    path = BUNDLED_PATH / "rospy_tutorials" / "launch" / "param_talker.launch"
    code, out, _ = run(capsys, "run", str(path), "--until", "1.5", "ns:=bar")
    assert code == 0
    assert "[INFO] [0.000000]: /bar/utterance is Hello World\n" in out
    assert "[ INFO] [1.000000000]: I heard: [Hello World]\n" in out
    assert "done\nsimulated 1.500 s; " in out
    assert run(capsys, "run", str(path), "--until", "1.5", "ns:=bar")[1] == out


def test_roslaunch_from_the_shell(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "roslaunch", "rospy_tutorials", "talker_listener.launch",
                       "--until", "0.2")
    assert code == 0
    assert out.startswith("\nSUMMARY\n========\n\nPARAMETERS\n * /chatter/message_type: "
                          "std_msgs/String\n")
    assert "auto-starting new master\nprocess[master]: started with pid [" in out
    assert "process[talker-2]: started with pid [" in out
    assert ("[INFO] [0.100000]: hello world 0.1\n"
            "[INFO] [0.100000]: /listenerI heard hello world 0.1\n") in out
    assert out.endswith("[listener-3] killing on exit\n[talker-2] killing on exit\n"
                        "shutting down processing monitor...\n"
                        "... shutting down processing monitor complete\ndone\n")
    code, with_digest, _ = run(capsys, "roslaunch", "--digest", "rospy_tutorials",
                               "talker_listener.launch", "--until=0.2")
    assert with_digest.startswith(out) and with_digest.splitlines()[-1].startswith("trace digest")


@pytest.mark.parametrize("argv, text", [
    (["run", "/no/such/scenario.py"], "scenario file not found"),
    (["run", "{empty}"], "must define 'def scenario(world): ...'"),
    (["run", "{empty}", "a:=1"], "arg:=value goes with launch files"),
    (["run", "{empty}", "--until", "soon"], "--until needs a number"),
    (["roslaunch", "rospy_tutorials", "nope.launch"], "[nope.launch] is neither a launch file"),
    (["roslaunch", "rospy_tutorials", "talker_listener.launch", "x:=1"], "unused args [x]"),
    (["roslaunch"], "no launch file given"),
])
def test_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str],
                text: str) -> None:
    empty = tmp_path / "empty.py"
    empty.write_text("X = 1\n")
    code, out, err = run(capsys, *[a.format(empty=empty) for a in argv])
    assert code == 1 and out == ""
    assert err.startswith("ERROR: ") and text in err


def test_node_failure_is_reported(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "bad.py"
    path.write_text("def scenario(world):\n"
                    "    n = world.create_node('n')\n"
                    "    def main():\n"
                    "        yield n.sleep(1)\n"
                    "        raise ValueError('boom')\n"
                    "    n.process(main())\n")
    code, _, err = run(capsys, "run", str(path))
    assert code == 1
    assert err == "ERROR: ValueError raised while the world ran: boom\n"


def test_until_is_seconds_as_world_run_takes_them(tmp_path: Path) -> None:
    """``--until`` goes through ddes.time.units like ``world.run(until=...)`` (truncated to ns)."""
    from ddes.cli.run import run_launch, run_scenario
    from ddes.time.units import to_ns

    path = tmp_path / "chat.py"
    path.write_text(SCENARIO)
    assert run_scenario(path, until=1.2, out=lambda _line: None).now == to_ns(1.2)
    launch = BUNDLED_PATH / "rospy_tutorials" / "launch" / "param_talker.launch"
    assert run_launch([str(launch)], until=1.2, out=lambda _line: None).now == to_ns(1.2)
