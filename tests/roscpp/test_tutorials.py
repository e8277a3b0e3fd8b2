"""roscpp_tutorials' C++ nodes, unchanged (../shared/upstream), built with ``ddes catkin_make``
and run in ddes worlds in lockstep; where Noetic's roscpp is installed, the same sources built
with real catkin_make print the same lines (timestamps aside) on a real roscore."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import ddes
from ddes.roscpp.host import ExternalNode

UPSTREAM = Path(__file__).resolve().parents[3] / "shared" / "upstream"
TUTORIALS = UPSTREAM / "ros_tutorials" / "roscpp_tutorials"
TARGETS = ["talker", "listener", "add_two_ints_server", "add_two_ints_client"]

pytestmark = [
    pytest.mark.skipif(not TUTORIALS.is_dir(), reason="no ../shared/upstream here"),
    pytest.mark.skipif(shutil.which("g++") is None or shutil.which("cmake") is None,
                       reason="needs g++ and cmake (.ci/run installs them)"),
]


@pytest.fixture(scope="module")
def devel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """roscpp_tutorials' four lecture-4 nodes built with ``ddes catkin_make TARGETS``."""
    ws = tmp_path_factory.mktemp("ws")
    shutil.copytree(TUTORIALS, ws / "src" / "roscpp_tutorials")
    proc = subprocess.run([sys.executable, "-m", "ddes", "catkin_make", "-j2", *TARGETS],
                          cwd=ws, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return ws / "devel"


def _exe(devel: Path, name: str) -> str:
    return str(devel / "lib" / "roscpp_tutorials" / name)


def _run(devel: Path, commands: list[list[str]], until: float, seed: int = 0
         ) -> tuple[list[str], str, list[ExternalNode]]:
    world = ddes.World(seed=seed)
    lines: list[str] = []
    world.log_output = lambda line, _level: lines.append(line)
    hosts = []
    for cmd in commands:
        host = ExternalNode(world, [_exe(devel, cmd[0]), *cmd[1:]])
        host.start()
        hosts.append(host)
    world.run(until=until)
    digest = world.digest()
    for host in hosts:
        host.close()
    return lines, digest, hosts


def test_the_talker_and_listener_talk(devel: Path) -> None:
    lines, _, _ = _run(devel, [["listener"], ["talker"]], 0.35)
    assert lines == [
        "[ INFO] [0.000000000]: hello world 0",
        "[ INFO] [0.100000000]: hello world 1", "[ INFO] [0.100000000]: I heard: [hello world 1]",
        "[ INFO] [0.200000000]: hello world 2", "[ INFO] [0.200000000]: I heard: [hello world 2]",
        "[ INFO] [0.300000000]: hello world 3", "[ INFO] [0.300000000]: I heard: [hello world 3]"]


def test_the_add_two_ints_server_and_client(devel: Path) -> None:
    lines, _, hosts = _run(devel, [["add_two_ints_server"], ["add_two_ints_client", "3", "4"]],
                           1.0)
    assert [line.split("]: ", 1)[1] for line in lines] == [
        "request: x=3, y=4", "  sending back response: [7]", "Sum: 7"]
    assert hosts[1].exit_code == 0
    lines, _, hosts = _run(devel, [["add_two_ints_client"]], 1.0)
    assert [line.split("]: ", 1)[1] for line in lines] == ["usage: add_two_ints_client X Y"]
    assert hosts[0].exit_code == 1


def test_the_same_seed_gives_the_same_digest_and_seeds_agree(devel: Path) -> None:
    runs = [_run(devel, [["listener"], ["talker"]], 0.55, seed=s)[1] for s in (0, 0, 7)]
    assert runs[0] == runs[1]
    assert runs[0] == runs[2]  # nothing here draws from the seed: the trace is the same


def test_a_cpp_node_and_a_python_node_share_a_world(devel: Path) -> None:
    world = ddes.World()
    world.log_output = False
    heard: list[str] = []
    py = world.create_node("py_listener")
    py.subscribe("chatter", world.messages.get_message_class("std_msgs/String"),
                 lambda m: heard.append(m.data), queue_size=10)
    talker = ExternalNode(world, [_exe(devel, "talker")])
    talker.start()
    pub = world.create_node("py_talker").advertise(
        "chatter", world.messages.get_message_class("std_msgs/String"), queue_size=10)
    listener = ExternalNode(world, [_exe(devel, "listener")])
    listener.start()
    got: list[str] = []
    world.log_output = lambda line, _level: got.append(line)
    world.run(until=0.25)
    pub.publish(data="from python")
    world.run(until=0.3)
    assert heard[:2] == ["hello world 1", "hello world 2"]
    assert "[ INFO] [0.250000000]: I heard: [from python]" in got
    for host in (talker, listener):
        host.close()


def test_rosrun_finds_the_built_nodes_in_the_workspace(devel: Path) -> None:
    """In the console started in the workspace: no variable to set (source devel/setup.bash)."""
    script = devel.parent / "session.txt"
    script.write_text("rosrun roscpp_tutorials add_two_ints_server &\n"
                      "rosrun roscpp_tutorials add_two_ints_client 3 4\n"
                      "rosnode list\n")
    proc = subprocess.run([sys.executable, "-m", "ddes", "console", "--script", str(script)],
                          cwd=devel.parent, capture_output=True, text=True, timeout=300,
                          env={k: v for k, v in os.environ.items()
                               if k != "DDES_PACKAGE_PATH"})
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "[ INFO] [0.000400000]: Sum: 7" in proc.stdout
    assert "/add_two_ints_server" in proc.stdout.split("$ rosnode list", 1)[1]


def test_ddes_run_runs_compiled_nodes_with_scripts_in_one_world(devel: Path) -> None:
    """``ddes run EXE [args] EXE ...``: compiled nodes (and scripts) in one world, the same
    lines and digest on every run."""
    listener = UPSTREAM / "ros_tutorials" / "rospy_tutorials" / "001_talker_listener" / "listener.py"
    cmd = [sys.executable, "-m", "ddes", "run", _exe(devel, "talker"), _exe(devel, "listener"),
           *([str(listener)] if listener.is_file() else []), "--until", "0.25"]
    runs = [subprocess.run(cmd, cwd=devel.parent, capture_output=True, text=True, timeout=300)
            for _ in range(2)]
    for proc in runs:
        assert proc.returncode == 0, proc.stdout + proc.stderr
    out = runs[0].stdout.splitlines()
    assert "[ INFO] [0.100000000]: hello world 1" in out
    assert "[ INFO] [0.100000000]: I heard: [hello world 1]" in out
    if listener.is_file():
        assert any(line.endswith("I heard hello world 1") for line in out), out
    assert out[-1].startswith("trace digest: ") and runs[0].stdout == runs[1].stdout
    bad = subprocess.run([sys.executable, "-m", "ddes", "run", "nope", _exe(devel, "talker")],
                         capture_output=True, text=True, timeout=60)
    assert bad.returncode != 0 and "Traceback" not in bad.stderr


def _shape(line: str) -> str:
    return re.sub(r"\x1b\[[0-9;]*m", "", re.sub(r"\[\d+\.\d+\]", "[T]", line)).strip()


@pytest.mark.ros
def test_the_nodes_print_what_real_roscpp_prints(devel: Path, tmp_path: Path) -> None:
    sys.path.insert(0, str(Path(__file__).parent))
    import real_roscpp

    if not real_roscpp.available():
        pytest.skip("Noetic's roscpp, catkin and roscore are not installed")
    real = real_roscpp.build([TUTORIALS], tmp_path / "real", TARGETS)
    listener, talker = real_roscpp.run(real, "roscpp_tutorials", [["listener"], ["talker"]],
                                       seconds=1.5)
    ours, _, _ = _run(devel, [["listener"], ["talker"]], 1.55)
    said = [_shape(x) for x in talker if "hello world" in x]
    heard = [_shape(x) for x in listener if "I heard" in x]
    assert said[:5] == [f"[ INFO] [T]: hello world {i}" for i in range(5)]
    mine_said = [_shape(x) for x in ours if "]: hello world" in x]
    assert mine_said[:len(said)] == said[:len(mine_said)]
    # each side hears a run of consecutive messages, the first ones lost while connecting
    for got in (heard, [_shape(x) for x in ours if "I heard" in x]):
        numbers = [int(x.rsplit(" ", 1)[1].rstrip("]")) for x in got]
        assert numbers and numbers == list(range(numbers[0], numbers[0] + len(numbers)))
        assert set(got) <= {f"[ INFO] [T]: I heard: [hello world {i}]" for i in range(100)}
    server, client = real_roscpp.run(real, "roscpp_tutorials",
                                     [["add_two_ints_server"], ["add_two_ints_client", "3", "4"]],
                                     seconds=5)
    mine, _, _ = _run(devel, [["add_two_ints_server"], ["add_two_ints_client", "3", "4"]], 1.0)
    assert [_shape(x) for x in server + client] == [_shape(x) for x in mine]


def test_the_python_snippet_of_docs_roscpp_runs(devel: Path, monkeypatch: pytest.MonkeyPatch,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    text = (Path(__file__).resolve().parents[2] / "docs" / "roscpp.md").read_text()
    block = text.split("In Python:\n\n```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(devel.parent)
    scope: dict[str, object] = {}
    exec(compile(block, "<docs/roscpp.md, In Python>", "exec"), scope)  # noqa: S102
    assert capsys.readouterr().out.strip().endswith("0")
    for name in ("server", "client"):
        scope[name].close()  # type: ignore[attr-defined]
