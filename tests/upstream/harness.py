"""Running upstream ROS 1 launch files and scripts on ddes and under real roslaunch.

``run_on_ddes`` runs a launch file with ddes's launch API (``load_launch`` and a
``LaunchRunner`` in a ``World``), shuts it down as Ctrl+C does after ``until`` simulated seconds
and lets the world run on, so the nodes' shutdown output (code after ``rospy.spin()``,
``on_shutdown`` hooks) is printed as in ROS.  ``REAL_LAUNCH`` is a script for the ``ros_python``
fixture (tests/conftest.py) that runs the same file with Noetic's ``roslaunch`` on a private
master: it copies the packages into a scratch workspace (git's symlinks restored, scripts made
executable, ``python`` meaning the system Python, as ``catkin_install_python`` arranges), has
genpy generate the packages' messages (Debian lacks rospy_tutorials'), waits until the output
shows what the test needs (at most ``limit`` wall seconds), runs the probe scripts, then sends
SIGINT and collects everything.  The node processes' output is line buffered (a
``sitecustomize`` on their ``PYTHONPATH``) so that lines of different processes do not cut into
each other; roslaunch's own threads still may, and :func:`lines_of` splits those.
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import shutil
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ddes.compat.scripts import run_script
from ddes.launch import load_launch, resolve_launch_args
from ddes.launch.runtime import LaunchRunner, LogRouter
from ddes.rospack import RosPack
from ddes.world import World

UPSTREAM = Path(__file__).resolve().parents[3] / "shared" / "upstream"
ROSPY_TUTORIALS = UPSTREAM / "ros_tutorials" / "rospy_tutorials"
ACTIONLIB_TUTORIALS = UPSTREAM / "common_tutorials" / "actionlib_tutorials"
#: DDES_PACKAGE_PATH of issue 39: the upstream packages shadow ddes's bundled ones.
PATH = [UPSTREAM / "ros_tutorials", UPSTREAM / "actionlib", UPSTREAM / "common_tutorials"]

#: Files of rospy_tutorials that git stores as symbolic links: the upstream copy holds them as
#: small text files naming their target (not executable), as a checkout without symlinks does.
SYMLINKS = {"001_talker_listener/talker": "talker.py",
            "001_talker_listener/listener": "listener.py"}


def checkout(packages: Iterable[Path], dest: Path, *, symlinks: bool = True) -> Path:
    """Copy ``packages`` into ``dest/src`` as git checks them out (symlinks restored, scripts
    executable, files writable, ``X.py.upstream`` named ``X.py``); returns ``dest/src``.

    With ``symlinks=False`` the symlinks stay as the upstream copy holds them (text files)."""
    src = dest / "src"
    for package in packages:
        target = src / package.name
        shutil.copytree(package, target, symlinks=True)
        for folder, _dirs, files in os.walk(target):
            os.chmod(folder, 0o755)
            for name in files:
                path = Path(folder) / name
                if name.endswith(".upstream"):  # an upstream script kept from the linter
                    path = path.rename(path.with_suffix(""))
                if not path.is_symlink():
                    os.chmod(path, 0o755 if _is_script(path) else 0o644)
        if package.name == "rospy_tutorials" and symlinks:
            for rel, link in SYMLINKS.items():
                stub = target / rel
                if stub.is_file() and not stub.is_symlink():
                    assert stub.read_text().strip() == link, stub
                    stub.unlink()
                    stub.symlink_to(link)
    return src


def _is_script(path: Path) -> bool:
    with open(path, "rb") as f:
        return f.read(2) == b"#!"


# -- ddes ------------------------------------------------------------------------------------------

@dataclass
class DdesRun:
    """What a launch printed on ddes: roslaunch's lines and the nodes' lines, in order."""

    out: list[str]
    world: World
    probes: dict[str, list[str]] = field(default_factory=dict)


def run_on_ddes(words: Sequence[str], until: float, *, path: Sequence[Path] = PATH,
                seed: int = 0, after: float = 2.0,
                probes: Sequence[tuple[float, Path]] = (),
                setup: Callable[[World], None] | None = None) -> DdesRun:
    """``roslaunch words`` (``PKG FILE.launch`` or ``PATH``, then ``arg:=value``) with the
    packages of ``path`` for ``until`` simulated seconds, shut down (Ctrl+C), then ``after``
    seconds more.

    ``probes`` are rospy scripts started at the given simulated times; their printed lines are
    in ``probes[script name]``, not in ``out``.  ``setup(world)`` runs before the launch starts.
    """
    rospack = RosPack(list(path))
    world = World(seed=seed, package_path=[str(p) for p in path])
    file, args = resolve_launch_args(list(words), rospack)
    plan = load_launch(file, args, rospack, anon_seed=world.rng_for("roslaunch"))
    out: list[str] = []
    run = DdesRun(out, world)

    def emit(text: str) -> None:
        out.extend(text.split("\n"))

    router = LogRouter(world, emit).install()
    runner = LaunchRunner(world, plan, rospack=rospack, out=emit, router=router)
    if setup is not None:
        setup(world)
    for at, script in probes:
        lines = run.probes.setdefault(script.name, [])

        def start(_ev: Any, script: Path = script, lines: list[str] = lines) -> None:
            run_script(world, script, print_line=lambda text, _err: lines.append(text))

        world.timeout(at).callbacks.append(start)
    runner.start()
    world.run(until=until)
    if not runner.done:
        runner.shutdown()
    world.run(until=until + after)
    return run


# -- real ROS --------------------------------------------------------------------------------------

def master_script() -> str:
    """tests/graph/rosmaster_script.py's MASTER: a private rosmaster for a ``ros_python`` script
    (which then finds ``start_process(args)``)."""
    path = Path(__file__).resolve().parents[1] / "graph" / "rosmaster_script.py"
    spec = importlib.util.spec_from_file_location("_ddes_rosmaster_script", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return str(module.MASTER)


#: The ``ros_python`` script: JSON on stdin (see :func:`real_payload`), JSON on stdout.
REAL_LAUNCH = r'''
import json, os, re, signal, socket, subprocess, sys, tempfile, threading, time
data = json.load(sys.stdin)
work = data["work"]
gen = os.path.join(work, "gen")
os.makedirs(gen)
with open(os.path.join(gen, "sitecustomize.py"), "w") as f:
    f.write("import sys\nfor s in (sys.stdout, sys.stderr):\n"
            "    try:\n        s.reconfigure(line_buffering=True)\n    except Exception:\n"
            "        pass\n")
from genpy.generator import MsgGenerator, SrvGenerator
for name in data["generate"]:
    pkg = os.path.join(data["src"], name)
    for kind, make in (("msg", MsgGenerator), ("srv", SrvGenerator)):
        if not os.path.isdir(os.path.join(pkg, kind)):
            continue
        out = os.path.join(gen, name, kind)
        os.makedirs(out)
        names = sorted(f[:-4] for f in os.listdir(os.path.join(pkg, kind)))
        make().generate_messages(name, [os.path.join(pkg, kind, n + "." + kind) for n in names],
                                 out, {name: [os.path.join(pkg, "msg")],
                                       "std_msgs": ["/usr/share/std_msgs/msg"],
                                       "geometry_msgs": ["/usr/share/geometry_msgs/msg"]})
        with open(os.path.join(out, "__init__.py"), "w") as f:
            f.write("".join("from ._%s import *\n" % n for n in names))
    open(os.path.join(gen, name, "__init__.py"), "w").close()
bindir = os.path.join(work, "bin")
os.makedirs(bindir)
for n in ("python", "python3"):  # the scripts' "#!/usr/bin/env python": the system Python
    os.symlink(sys.executable, os.path.join(bindir, n))

s = socket.socket()
s.bind(("127.0.0.1", 0))
port = s.getsockname()[1]
s.close()
env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "ROS_"))}
env.update(ROS_PACKAGE_PATH=data["src"], ROS_HOME=os.path.join(work, "home"), PYTHONPATH=gen,
           ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_HOSTNAME="127.0.0.1",
           PATH=bindir + os.pathsep + env.get("PATH", ""))
lines = []
def follow(p, into):
    def read():
        for line in p.stdout:
            into.append(line.rstrip("\n"))
    t = threading.Thread(target=read, daemon=True)
    t.start()
    return t
proc = subprocess.Popen([sys.executable, "-u", "/usr/bin/roslaunch", "-p", str(port)]
                        + data["words"], env=env, stdout=subprocess.PIPE,
                        stderr=subprocess.STDOUT, text=True, start_new_session=True)
reader = follow(proc, lines)
start = time.monotonic()
def met(until):
    return all(sum(bool(re.search(pat, l)) for l in list(lines)) >= n for pat, n in until)
def wait(until):
    while time.monotonic() - start < data["limit"] and proc.poll() is None and not met(until):
        time.sleep(0.02)
    return met(until)
ok = wait(data["until"])
probes = {}
for script in data["probes"]:
    p = subprocess.Popen([sys.executable, "-u", script], env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    probes[os.path.basename(script)] = got = []
    t = follow(p, got)
    try:
        p.wait(timeout=max(1.0, data["limit"] - (time.monotonic() - start)))
    except subprocess.TimeoutExpired:
        p.kill()
    t.join(5)
ok = wait(data["then"]) and ok
time.sleep(data["settle"])
proc.send_signal(signal.SIGINT)
try:
    proc.wait(timeout=40)
except subprocess.TimeoutExpired:
    os.killpg(proc.pid, signal.SIGKILL)
reader.join(10)
# roslaunch starts each process in a session of its own: should one outlive it (roslaunch
# stopped while still starting up), end it; it is ours if its command line names our ROS_HOME
for pid in {int(m) for l in lines for m in re.findall(r"started with pid \[(\d+)\]", l)}:
    try:
        with open("/proc/%d/cmdline" % pid, "rb") as f:
            ours = os.path.join(work, "home").encode() in f.read()
        if ours:
            os.kill(pid, signal.SIGKILL)
    except OSError:
        pass
print(json.dumps({"met": ok, "lines": lines, "probes": probes, "code": proc.returncode,
                  "secs": time.monotonic() - start}))
'''


def real_payload(work: Path, src: Path, words: Sequence[str], *,
                 until: Sequence[tuple[str, int]] = (), then: Sequence[tuple[str, int]] = (),
                 settle: float = 0.3, limit: float = 10.0, probes: Sequence[Path] = (),
                 generate: Sequence[str] = ("rospy_tutorials",)) -> str:
    """The stdin of :data:`REAL_LAUNCH`: ``roslaunch words`` on the packages in ``src``, stopped
    ``settle`` seconds after the output matched every ``(regex, count)`` of ``until`` (then the
    probe scripts ran, and ``then`` was met), or after ``limit`` seconds."""
    work.mkdir(parents=True, exist_ok=True)
    return json.dumps({"work": str(work), "src": str(src), "words": list(words),
                       "until": [list(u) for u in until], "then": [list(u) for u in then],
                       "settle": settle, "limit": limit, "probes": [str(p) for p in probes],
                       "generate": list(generate)})


def run_real(ros_python: Callable[..., Any], work: Path, src: Path, words: Sequence[str],
             **kwargs: Any) -> dict[str, Any]:
    """Run :data:`REAL_LAUNCH` (see :func:`real_payload`); ``lines`` come back split."""
    theirs: dict[str, Any] = ros_python(REAL_LAUNCH, as_json=True, timeout=120,
                                        stdin=real_payload(work, src, words, **kwargs))
    theirs["lines"] = lines_of(theirs["lines"])
    return theirs


# -- comparing -------------------------------------------------------------------------------------

_ESCAPES = re.compile(r"\x1b\[[0-9;]*m|\x1b\]2;[^\x07]*\x07")
#: Where a line of roslaunch's may have been cut into by another thread's or process's line.
_CUT = re.compile(r"(?<=\S)(?=\[(?:INFO|WARN|ERROR|DEBUG|FATAL)\] \[\d)"
                  r"|(?<=\S)(?=\[[\w/]+-\d+\] (?:killing on exit|process has))"
                  r"|(?<=\S)(?=process\[[\w/]+(?:-\d+)?\]: started)"
                  r"|(?<=killing on exit)(?=\S)|(?<=finished cleanly)(?=\S)"
                  r"|(?<=started with pid \[\d)(?=\D)")


def lines_of(raw: Iterable[str]) -> list[str]:
    """Real roslaunch output without colours and titles, cut lines split."""
    out: list[str] = []
    for line in raw:
        for part in _CUT.split(_ESCAPES.sub("", line)):
            out.append(part)
    return out


def shape(line: str) -> str:
    """A line with its numbers (times, pids, seq, anonymous suffixes) replaced by N."""
    return re.sub(r"N(_N)+", "N", re.sub(r"\d+(\.\d+)?", "N", line))


#: roslaunch's own lines that differ by machine, run or version, or that ddes does not print
#: (no log files, no XML-RPC server, no terminal title): left out of comparisons.
_NOISE = re.compile(r"^(\.\.\. logging to |Checking log directory|Press Ctrl-C|Done checking log|"
                    r"started roslaunch server|ROS_MASTER_URI=|setting /run_id to |"
                    r"auto-starting new master|started core service|INFO: cannot create a "
                    r"symlink|log file: |\s*$)")
_LAUNCH = re.compile(r"^(process\[[^\]]+\]: started with pid|\[[^\]]+\] (killing on exit|"
                     r"process has|restarting process)|shutting down processing monitor|"
                     r"\.\.\. shutting down processing monitor complete|done$|"
                     r"=+REQUIRED process|No processes to monitor|all processes on machine)")


@dataclass
class Parts:
    """One launch's output, sorted: the SUMMARY block, the processes started (labels, in
    order), the processes killed on exit (labels), errors roslaunch printed, node lines."""

    summary: list[str]
    started: list[str]
    killed: list[str]
    errors: list[str]
    nodes: list[str]


def parts(lines: Sequence[str]) -> Parts:
    """Sort a launch's output (ddes's, or real roslaunch's after :func:`lines_of`)."""
    summary: list[str] = []
    started: list[str] = []
    killed: list[str] = []
    errors: list[str] = []
    nodes: list[str] = []
    in_summary = False
    for line in lines:
        if line == "SUMMARY":
            in_summary = True
        if in_summary:
            if line.startswith("auto-starting") or line.startswith("process[") or \
                    line.startswith("ROS_MASTER_URI"):
                in_summary = False
            else:
                if line.strip():
                    summary.append(re.sub(r"^( \* /rosdistro: | \* /rosversion: ).*", r"\1V",
                                          line))
                continue
        if _NOISE.match(line):
            continue
        m = re.match(r"^process\[([^\]]+)\]: started", line)
        if m:
            started.append(m.group(1))
            continue
        m = re.match(r"^\[([^\]]+)\] killing on exit", line)
        if m:
            killed.append(m.group(1))
            continue
        if line.startswith("ERROR: cannot launch node"):
            errors.append(line)
            continue
        if _LAUNCH.match(line):
            continue
        nodes.append(line)
    return Parts(summary, started, killed, errors, nodes)


def shapes(lines: Iterable[str]) -> set[str]:
    return {shape(line) for line in lines}
