"""Student code in a separate, resource-limited process: the trusted side of the pipe.

:class:`Sandbox` starts ``python -s -P -B -m ddes.grading.child`` (:mod:`ddes.grading.child`)
on a temporary copy of the submission and talks to it only in the frames of
:mod:`ddes.grading.protocol`.  What is enforced on the child (each also listed in
:attr:`Sandbox.enforced`, which the report carries):

* **rlimits**: address space (:attr:`Limits.memory_bytes`), CPU seconds, the size of any file
  it writes (its captured stderr included), open files, processes (``RLIMIT_NPROC``), no core
  files;
* **its own session and process group** (``setsid``): the grader kills the whole group;
* **no network**: a fresh network namespace (``unshare(CLONE_NEWNET)``, or with a user namespace
  when the grader is not root); where neither can be made, Landlock's TCP rules and the audit
  hook remain, and :attr:`Sandbox.enforced` says so;
* **an unprivileged user of its own**: when the grader runs as root the child runs as a user no
  account has, one per sandbox (``0x5DD00000`` and up, claimed with a lock in
  ``/tmp/ddes-grading-uids``, the lowest free one), so the processes rlimit counts only this
  child's threads and concurrent grades (a batch's workers) never share it;
* **no new process, no socket** (seccomp, installed by the child itself) and **no leftover**:
  whatever the child started that survived the group kill (found in ``/proc`` by the token in
  its environment) is killed and named in :attr:`SandboxOutcome.leftovers`;
* **budgets of the whole run**: the grade's wall time (:attr:`Limits.grade_wall_s`, shared by
  every child of a grade through ``grade_deadline``), the bytes of messages a child publishes
  and what it keeps on disk (:attr:`Limits.message_bytes`, :attr:`Limits.disk_bytes`);
* **files**: Landlock (when the kernel has it) limits reading to the Python installation, ddes
  and the submission copy, and writing to the submission copy;
* **a scrubbed environment** (``PATH``, ``HOME`` and ``TMPDIR`` in the copy, ``PYTHONHASHSEED=0``,
  one BLAS thread) and the copy as working directory; ``-s -P`` keep the user's site
  packages and the working directory off ``sys.path``;
* **captured output with a cap**: stdout and stderr of the student go to one file whose size the
  file-size rlimit bounds; the report keeps its last :attr:`Limits.output_keep` bytes;
* **wall budgets**: a child not ready within :attr:`Limits.startup_wall_s` (interpreter,
  ``import ddes``, confinement), or a step not answered within :attr:`Limits.step_wall_s`, is
  ended; the grade goes on without it.

The trusted side never imports, unpickles or evaluates anything from the child: a reply is
decoded by :func:`ddes.grading.protocol.decode_frame` and validated by the caller
(:mod:`ddes.grading.bridge`); anything malformed ends the child (fail closed).
"""

from __future__ import annotations

import fcntl
import json
import os
import resource
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ddes.errors import GradingError, ProtocolError
from ddes.grading import protocol
from ddes.grading.determinism import aslr_off

__all__ = ["Limits", "RunBudget", "Sandbox", "SandboxOutcome", "StepReply"]

#: The first of the users a sandbox child runs as (when the grader is root), and how many.
UID_BASE = 0x5DD0_0000
UID_SLOTS = 4096
_CLONE_NEWUSER = 0x10000000
_CLONE_NEWNET = 0x40000000


@dataclass(frozen=True)
class Limits:
    """Resource limits of the child."""

    memory_bytes: int = 768 * 1024 * 1024
    cpu_seconds: int = 60
    file_bytes: int = 16 * 1024 * 1024
    open_files: int = 64
    processes: int = 16
    #: Wall seconds one step may take (the student's code between two exchanges).
    step_wall_s: float = 5.0
    #: Wall seconds for the child to start: the interpreter, ``import ddes``, the confinement.
    startup_wall_s: float = 30.0
    output_keep: int = 16 * 1024
    #: Most bytes of frames one step may return before it counts as flooding.
    step_bytes: int = 64 * 1024 * 1024
    #: Wall seconds one whole grade may take, all its scenarios and children together (a step
    #: just under :attr:`step_wall_s`, every step, would otherwise take hours).
    grade_wall_s: float = 120.0
    #: Most bytes of messages one child may publish in one run (what the grader keeps of them
    #: grows with it).
    message_bytes: int = 256 * 1024 * 1024
    #: Most bytes, and files, the child may keep in its folder (the copy of the submission and
    #: what it writes there); :attr:`file_bytes` bounds each file.
    disk_bytes: int = 64 * 1024 * 1024
    disk_files: int = 2000


@dataclass
class RunBudget:
    """What the children of one run (a scenario) share: the bytes of messages they published,
    against :attr:`Limits.message_bytes` (a child per node must not multiply the budget)."""

    message_bytes: int = 0


@dataclass
class StepReply:
    """What the child answered to one STEP (frames still to be validated by the bridge)."""

    frames: list[protocol.Adv | protocol.Sub | protocol.Msg | protocol.Gone | protocol.Srv
                 | protocol.Resp | protocol.Died | protocol.Read | protocol.Ask] = field(
                     default_factory=list)
    next_ns: int = -1


@dataclass
class SandboxOutcome:
    """How the child ended, for the report."""

    #: "running", "finished", "exited" (it ended by itself), "killed" (a budget or a bad frame).
    state: str = "running"
    reason: str = ""
    returncode: int | None = None
    output_tail: str = ""
    enforced: list[str] = field(default_factory=list)
    #: Processes of the child's that were still running after it ended (each ``pid cmdline``):
    #: the grader killed them.
    leftovers: list[str] = field(default_factory=list)


def _uid_in_use(uid: int) -> bool:
    """True when a live process runs as ``uid`` (a real, effective or saved user id)."""
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/status", encoding="ascii", errors="replace") as f:
                for line in f:
                    if line.startswith("Uid:"):
                        if str(uid) in line.split()[1:4]:
                            return True
                        break
        except OSError:
            continue
    return False


def claim_uid(lock_dir: str | os.PathLike[str] | None = None) -> tuple[int, int]:
    """The lowest free sandbox user (``UID_BASE + slot``) and the descriptor whose ``flock``
    holds it (closing it frees the user; so does the grader's death).  A slot whose user still
    has processes (a crashed grader's) is passed over.  Root only."""
    folder = Path(lock_dir if lock_dir is not None
                  else os.path.join(tempfile.gettempdir(), "ddes-grading-uids"))
    try:
        folder.mkdir(mode=0o700)
    except FileExistsError:
        pass
    st = os.lstat(folder)
    if not os.path.isdir(folder) or os.path.islink(folder) or st.st_uid != os.geteuid() \
            or st.st_mode & 0o022:
        raise GradingError(f"{folder} (the sandbox users' locks) must be a folder of this user "
                           "that no one else can write; remove it and grade again")
    for slot in range(UID_SLOTS):
        fd = os.open(folder / str(slot), os.O_CREAT | os.O_RDWR | os.O_NOFOLLOW, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            continue
        if _uid_in_use(UID_BASE + slot):
            os.close(fd)
            continue
        return UID_BASE + slot, fd
    raise GradingError(f"all {UID_SLOTS} sandbox users are in use: fewer grades at once")


def _others_can_run_python() -> bool:
    """True when a user other than the owner can run this Python and import ddes (every
    directory on the way searchable by others, the files readable by them)."""
    import ddes

    paths = [os.path.realpath(sys.executable), os.path.realpath(ddes.__file__),
             os.path.realpath(os.__file__)]
    for path in paths:
        p = Path(path)
        if not p.exists() or not p.stat().st_mode & 0o004:
            return False
        for parent in p.parents:
            if not parent.stat().st_mode & 0o001:
                return False
    return True


def landlock_abi() -> int:
    """The kernel's Landlock ABI version (0: none)."""
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.syscall.restype = ctypes.c_long
        return max(0, int(libc.syscall(444, None, 0, 1)))
    except (OSError, AttributeError):
        return 0


def seccomp_available() -> bool:
    """True when the child can install its seccomp filter (:func:`ddes.grading.child.seccomp`):
    a machine it has a table for and a kernel with seccomp."""
    import platform

    from ddes.grading.child import seccomp_program

    if seccomp_program(platform.machine()) is None:
        return False
    try:
        with open("/proc/self/status", encoding="ascii", errors="replace") as f:
            return any(line.startswith("Seccomp:") for line in f)
    except OSError:
        return False


def _marked(token: str) -> list[tuple[int, str]]:
    """The processes whose environment holds ``DDES_GRADING_TOKEN=token`` (a child's and all it
    started: the environment is inherited, and the child cannot change what /proc shows of
    it), each ``(pid, command line)``."""
    mark = f"DDES_GRADING_TOKEN={token}".encode()
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/environ", "rb") as f:
                if mark not in f.read().split(b"\0"):
                    continue
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                cmd = f.read(300).replace(b"\0", b" ").decode("utf-8", "replace").strip()
        except OSError:  # gone, or not ours to read
            continue
        found.append((int(entry), cmd))
    return sorted(found)


def _libc_unshare() -> object:
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    return libc.unshare


class Sandbox:
    """One child process running ``scripts`` (paths relative to ``submission``)."""

    def __init__(self, submission: str | os.PathLike[str], scripts: Sequence[tuple[str, Sequence[str]]],
                 *, seed: int = 0, limits: Limits | None = None, network_namespace: bool = True,
                 landlock: bool = True, drop_user: bool = True, seccomp: bool = True,
                 params: Mapping[str, Any] | None = None,
                 grade_deadline: float | None = None,
                 run_budget: RunBudget | None = None) -> None:
        self.limits = limits or Limits()
        self.seed = seed
        #: Global parameters the child sets before the student's nodes start (``/use_sim_time``).
        self.params = dict(params or {})
        self.scripts = [(str(p), [str(a) for a in args]) for p, args in scripts]
        self._root = Path(tempfile.mkdtemp(prefix="ddes-grade-"))
        self.workdir = self._root / "work"
        shutil.copytree(submission, self.workdir, symlinks=False)
        self._output_path = self._root / "output.txt"
        self._as_nobody = drop_user and os.geteuid() == 0 and _others_can_run_python()
        #: The user the child runs as (None: the grader's own) and the lock that holds it.
        self.uid: int | None = None
        self._uid_lock = -1
        if self._as_nobody:
            self.uid, self._uid_lock = claim_uid()
            os.chmod(self._root, 0o711)
            for dirpath, _dirs, files in os.walk(self.workdir):
                os.chown(dirpath, self.uid, self.uid)
                for f in files:
                    os.chown(os.path.join(dirpath, f), self.uid, self.uid)
        self._network_namespace = network_namespace
        self._landlock = landlock
        self._seccomp = seccomp and seccomp_available()
        #: ``time.monotonic()`` by which the whole grade must be done (None: no such budget).
        self.grade_deadline = grade_deadline
        self._run_budget = run_budget if run_budget is not None else RunBudget()
        self._disk_checked = 0.0
        self.outcome = SandboxOutcome()
        self._proc: subprocess.Popen[bytes] | None = None
        self._first = True
        self._buf = b""
        self._deadline = 0.0

    # -- life -----------------------------------------------------------------------------------
    @property
    def alive(self) -> bool:
        return self._proc is not None and self.outcome.state == "running"

    @property
    def enforced(self) -> list[str]:
        return self.outcome.enforced

    def start(self) -> None:
        argv = [str(self.seed), str(len(self.scripts))]
        for path, args in self.scripts:
            argv += [path, str(len(args)), *args]
        env = {"PATH": "/usr/bin:/bin", "HOME": str(self.workdir), "TMPDIR": str(self.workdir),
               "PYTHONHASHSEED": "0", "PYTHONDONTWRITEBYTECODE": "1", "LANG": "C.UTF-8",
               "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
               "DDES_GRADING_LANDLOCK": "1" if self._landlock else "0",
               "DDES_GRADING_SECCOMP": "1" if self._seccomp else "0",
               "DDES_GRADING_TOKEN": self._root.name}
        if self.params:
            env["DDES_GRADING_PARAMS"] = json.dumps(self.params, sort_keys=True)
        cmd = [sys.executable, "-s", "-P", "-B", "-m", "ddes.grading.child", *argv]
        out = open(self._output_path, "wb")  # noqa: SIM115 - handed to the child, closed below
        enforced = ["rlimits (address space, CPU, file size, open files, processes, no core)",
                    "own session and process group", "scrubbed environment",
                    "output captured with a cap"]
        try:
            tries = [True, False] if self._network_namespace else [False]
            for netns in tries:
                try:
                    self._proc = subprocess.Popen(
                        cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=out,
                        cwd=self.workdir, env=env, start_new_session=True, close_fds=True,
                        preexec_fn=self._preexec(netns))
                except subprocess.SubprocessError:
                    if netns:
                        continue
                    raise
                enforced.append("network namespace (no network)" if netns else
                                "NO network namespace: Landlock TCP rules and the audit hook only")
                break
        finally:
            out.close()
        if self._as_nobody:
            enforced.append(f"unprivileged user {self.uid} of its own (no account, no other "
                            "process)")
        elif os.geteuid() == 0:
            enforced.append("NOT a separate user: this Python is not readable by others")
        abi = landlock_abi() if self._landlock else 0
        enforced.append(f"Landlock ABI {abi}: files (read: Python, ddes, the copy; write: the "
                        "copy), TCP and signals confined" if abi else
                        "NO Landlock (kernel without it, or switched off): files not confined")
        enforced.append("seccomp: no new process, no exec, no socket (kernel-enforced)"
                        if self._seccomp else
                        "NO seccomp (kernel or machine without it): processes and sockets are "
                        "refused by the audit hook only; leftovers are still found and killed")
        enforced.append("audit hook: no sockets, subprocesses, exec, fork, ctypes, kill")
        self.outcome.enforced = enforced
        assert self._proc is not None and self._proc.stdout is not None
        os.set_blocking(self._proc.stdout.fileno(), False)
        assert self._proc.stdin is not None
        os.set_blocking(self._proc.stdin.fileno(), False)

    def _preexec(self, netns: bool) -> Callable[[], None]:
        lim = self.limits
        unshare = _libc_unshare() if netns else None
        as_nobody = self._as_nobody
        uid = self.uid
        no_aslr = aslr_off()  # libc looked up before the fork: id() order repeats

        def run() -> None:
            resource.setrlimit(resource.RLIMIT_AS, (lim.memory_bytes, lim.memory_bytes))
            resource.setrlimit(resource.RLIMIT_CPU, (lim.cpu_seconds, lim.cpu_seconds))
            resource.setrlimit(resource.RLIMIT_FSIZE, (lim.file_bytes, lim.file_bytes))
            resource.setrlimit(resource.RLIMIT_NOFILE, (lim.open_files, lim.open_files))
            resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
            resource.setrlimit(resource.RLIMIT_NPROC, (lim.processes, lim.processes))
            no_aslr()
            if unshare is not None:
                flags = _CLONE_NEWNET if os.geteuid() == 0 else _CLONE_NEWUSER | _CLONE_NEWNET
                if unshare(flags) != 0:  # type: ignore[operator]
                    raise OSError("unshare failed")
            if as_nobody and uid is not None:
                os.setgroups([])
                os.setgid(uid)
                os.setuid(uid)

        return run

    # -- steps ----------------------------------------------------------------------------------
    def step(self, t_ns: int, messages: list[tuple[str, str, str, bytes]],
             calls: Sequence[tuple[int, str, bytes]] = (),
             offers: Sequence[tuple[str, str, str]] = (),
             answers: Sequence[tuple[int, bool, bytes | str]] = ()) -> StepReply | None:
        """Send one STEP (after an OFFER per ``(service, type, md5)`` of ``offers``, an ANSWER
        per ``(id, ok, bytes or error text)`` of ``answers`` and a CALL per ``(id, service,
        request bytes)`` of ``calls``) and read its reply; None (and the child ended) when it
        fails.  :meth:`begin` and :meth:`finish` are its two halves (a lockstep of several
        children sends every due child its step before it reads the first reply, so they
        compute in parallel)."""
        if not self.begin(t_ns, messages, calls, offers, answers):
            return None
        return self.finish(t_ns)

    def begin(self, t_ns: int, messages: list[tuple[str, str, str, bytes]],
              calls: Sequence[tuple[int, str, bytes]] = (),
              offers: Sequence[tuple[str, str, str]] = (),
              answers: Sequence[tuple[int, bool, bytes | str]] = ()) -> bool:
        """Send one STEP (see :meth:`step`); False (and the child ended) when it fails."""
        if not self.alive:
            return False
        budget = self.limits.step_wall_s
        try:
            if self._first:
                self._first = False
                self._ready(t_ns)
            self._deadline = self._step_deadline(budget)
            head = b"".join([*(protocol.encode_offer(*o) for o in offers),
                             *(protocol.encode_answer(*a) for a in answers),
                             *(protocol.encode_call(i, name, data) for i, name, data in calls)])
            self._send(head + protocol.encode_step(t_ns, messages), self._deadline)
            return True
        except BaseException as exc:  # noqa: BLE001 - each kind ends the child, as _failed says
            self._failed(t_ns, exc)
        return False

    def finish(self, t_ns: int) -> StepReply | None:
        """Read the reply to the STEP :meth:`begin` sent; None (and the child ended) when it
        fails."""
        if not self.alive:
            return None
        try:
            return self._reply(t_ns, self._deadline)
        except BaseException as exc:  # noqa: BLE001 - each kind ends the child, as _failed says
            self._failed(t_ns, exc)
        return None

    def _step_deadline(self, budget: float) -> float:
        """Now + ``budget``, or the grade's deadline when that comes first."""
        deadline = time.monotonic() + budget
        if self.grade_deadline is not None and self.grade_deadline < deadline:
            return self.grade_deadline
        return deadline

    def _over_grade(self) -> bool:
        return self.grade_deadline is not None and time.monotonic() >= self.grade_deadline

    def _failed(self, t_ns: int, exc: BaseException) -> None:
        budget = self.limits.step_wall_s
        if isinstance(exc, TimeoutError) and self._over_grade():
            self.kill("killed", f"the grade's wall budget of {self.limits.grade_wall_s:g} s ran "
                                f"out (at simulated t={t_ns / 1e9:.3f} s): the whole grade, "
                                "every scenario and node together, gets that long")
        elif isinstance(exc, TimeoutError):
            hint = "" if str(exc) else (": code that never sleeps (rate.sleep(), rospy.sleep()) "
                                        "or waits for ROS time in a loop keeps simulated time "
                                        "still")
            self.kill("killed", f"{str(exc) or f'no answer within the {budget:g} s wall budget of a step'}"
                                f" (at simulated t={t_ns / 1e9:.3f} s){hint}")
        elif isinstance(exc, EOFError):
            self._ended(t_ns)
        elif isinstance(exc, _Budget):
            self.kill("killed", str(exc))
        elif isinstance(exc, ProtocolError):
            self.kill("killed", f"broke the protocol at t={t_ns / 1e9:.3f} s: {exc}")
        elif isinstance(exc, OSError):  # a broken pipe: it has gone
            self._ended(t_ns, str(exc))
        else:
            raise exc

    def _ready(self, t_ns: int) -> None:
        """Wait for READY: the child has imported ddes and confined itself."""
        budget = self.limits.startup_wall_s
        try:
            kind, length = protocol.decode_header(
                self._read(protocol.HEADER.size, self._step_deadline(budget)))
        except TimeoutError:
            if self._over_grade():
                raise
            raise TimeoutError(f"not ready within the {budget:g} s start-up budget") from None
        if kind != protocol.READY or length:
            raise ProtocolError("the child's first frame is not READY")

    def _send(self, data: bytes, deadline: float) -> None:
        assert self._proc is not None and self._proc.stdin is not None
        fd = self._proc.stdin.fileno()
        view = memoryview(data)
        while view:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError
            _, w, _ = select.select([], [fd], [], left)
            if w:
                view = view[os.write(fd, view):]

    def _read(self, n: int, deadline: float) -> bytes:
        assert self._proc is not None and self._proc.stdout is not None
        fd = self._proc.stdout.fileno()
        while len(self._buf) < n:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError
            r, _, _ = select.select([fd], [], [], left)
            if not r:
                continue
            chunk = os.read(fd, max(65536, n - len(self._buf)))
            if not chunk:
                raise EOFError
            self._buf += chunk
        out, self._buf = self._buf[:n], self._buf[n:]
        return out

    def _reply(self, t_ns: int, deadline: float) -> StepReply:
        reply = StepReply()
        total = 0
        while True:
            kind, length = protocol.decode_header(self._read(protocol.HEADER.size, deadline))
            total += length + protocol.HEADER.size
            if total > self.limits.step_bytes:
                raise ProtocolError(f"a step returned more than {self.limits.step_bytes} bytes")
            frame = protocol.decode_frame(kind, self._read(length, deadline))
            if isinstance(frame, protocol.Msg):
                self._run_budget.message_bytes += length
                if self._run_budget.message_bytes > self.limits.message_bytes:
                    raise _Budget(f"your nodes published more than "
                                  f"{_size(self.limits.message_bytes)} of messages in this run "
                                  f"(at simulated t={t_ns / 1e9:.3f} s): a grade keeps what "
                                  "crosses, and allows that much")
            if isinstance(frame, protocol.Done):
                if frame.next_ns != -1 and frame.next_ns < t_ns:
                    raise ProtocolError(f"next event at {frame.next_ns} ns is before the step "
                                        f"({t_ns} ns)")
                reply.next_ns = frame.next_ns
                self._check_disk(t_ns)
                return reply
            if frame is None or isinstance(frame, (protocol.Step, protocol.Call, protocol.Offer,
                                                   protocol.Answer)):
                raise ProtocolError("the child sent a grader-side frame")
            reply.frames.append(frame)

    def _check_disk(self, t_ns: int) -> None:
        """End the child once its folder holds more than :attr:`Limits.disk_bytes` or
        :attr:`Limits.disk_files` (looked at after a step, at most every 0.1 s of wall time,
        and at the end; a step can add at most what its wall budget lets it write)."""
        now = time.monotonic()
        if now - self._disk_checked < 0.1:
            return
        self._disk_checked = now
        used, files = _disk_use(self.workdir, self.limits.disk_files)
        lim = self.limits
        if used > lim.disk_bytes or files > lim.disk_files:
            raise _Budget(f"your node keeps more than {_size(lim.disk_bytes)} or "
                          f"{lim.disk_files} files in its folder (at simulated "
                          f"t={t_ns / 1e9:.3f} s: {used} bytes in {files}"
                          f"{'+' if files > lim.disk_files else ''} files): a grade allows "
                          "that much disk")

    # -- the end --------------------------------------------------------------------------------
    def _ended(self, t_ns: int, detail: str = "") -> None:
        code = self._reap(1.0)
        why = f"exit code {code}" if code is not None and code >= 0 else (
            f"signal {signal.Signals(-code).name}" if code is not None else "unknown")
        if code == -signal.SIGXCPU:
            why += f": it used up its {self.limits.cpu_seconds} s of CPU time"
        self.kill("exited", f"the student's process ended at t={t_ns / 1e9:.3f} s ({why})"
                            + (f": {detail}" if detail else ""))

    def _reap(self, wait_s: float) -> int | None:
        if self._proc is None:
            return None
        try:
            return self._proc.wait(wait_s)
        except subprocess.TimeoutExpired:
            return None

    def kill(self, state: str, reason: str) -> None:
        """End the child's whole process group, and every process it started that left the
        group (found by the token in their environment), and record why."""
        if self._proc is not None:
            try:
                os.killpg(self._proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
            code = self._reap(5.0)
            self._kill_leftovers()
            self.outcome.returncode = code
            for pipe in (self._proc.stdin, self._proc.stdout):
                try:
                    if pipe is not None:
                        pipe.close()
                except OSError:
                    pass
        if self.outcome.state == "running":
            self.outcome.state, self.outcome.reason = state, reason

    def close(self) -> SandboxOutcome:
        """End the child (END, then the kill of its group), read its output tail, remove the copy."""
        if self.alive:
            try:
                self._send(protocol.encode_end(), time.monotonic() + 1.0)
            except (OSError, TimeoutError):
                pass
            self.kill("finished", "")
        elif self._proc is not None:
            self.kill(self.outcome.state, self.outcome.reason)
        try:
            with open(self._output_path, "rb") as f:
                f.seek(0, os.SEEK_END)
                size = f.tell()
                keep = self.limits.output_keep
                f.seek(max(0, size - keep))
                tail = f.read(keep).decode("utf-8", "replace").replace("\x00", "\\0")
                cut = (f"[… {size - keep} bytes of your output before this are not kept: a "
                       f"grade keeps the last {_size(keep)}]\n" if size > keep else "")
                self.outcome.output_tail = cut + tail
        except OSError:
            pass
        shutil.rmtree(self._root, ignore_errors=True)
        if self._uid_lock >= 0:  # the child and its leftovers are dead: the user is free again
            os.close(self._uid_lock)
            self._uid_lock = -1
        return self.outcome

    def _kill_leftovers(self) -> None:
        for _ in range(3):  # a leftover may fork while it is found: look again
            found = [(pid, cmd) for pid, cmd in _marked(self._root.name)
                     if self._proc is None or pid != self._proc.pid]
            if not found:
                return
            for pid, cmd in found:
                try:
                    os.kill(pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    continue
                text = f"{pid} {cmd}"
                if text not in self.outcome.leftovers:
                    self.outcome.leftovers.append(text)
            for pid, _cmd in found:  # gone (or a zombie of its new parent) before the grade goes on
                _wait_dead(pid, 2.0)

    def __del__(self) -> None:
        if getattr(self, "_uid_lock", -1) >= 0:  # never closed: at least free its user
            os.close(self._uid_lock)
            self._uid_lock = -1

    def __enter__(self) -> Sandbox:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _wait_dead(pid: int, wait_s: float) -> None:
    """Wait until ``pid`` has ended (no /proc entry, or a zombie), at most ``wait_s``."""
    end = time.monotonic() + wait_s
    while time.monotonic() < end:
        try:
            with open(f"/proc/{pid}/stat", "rb") as f:
                state = f.read().rpartition(b")")[2].split()[:1]
        except OSError:
            return
        if state in ([b"Z"], [b"X"]):
            return
        time.sleep(0.005)


class _Budget(Exception):
    """A budget of the whole run passed (messages, disk): the child is ended with this text."""


def _disk_use(root: Path, max_files: int) -> tuple[int, int]:
    """Bytes (allocated blocks, at least the sizes) and files below ``root``, counting stops
    past ``max_files``."""
    used = files = 0
    stack = [str(root)]
    while stack and files <= max_files:
        try:
            entries = list(os.scandir(stack.pop()))
        except OSError:
            continue
        for e in entries:
            files += 1
            try:
                st = e.stat(follow_symlinks=False)
            except OSError:
                continue
            if e.is_dir(follow_symlinks=False):
                stack.append(e.path)
            else:
                used += max(st.st_size, st.st_blocks * 512)
    return used, files


def _size(n: int) -> str:
    """``16 MiB``, ``768 MiB``, ``512 KiB``, ``100 B``."""
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n >= size and n % size == 0:
            return f"{n // size} {unit}"
    return f"{n} B"


def check_limits(limits: Limits) -> None:
    """Refuse limits a child cannot start under."""
    if limits.memory_bytes < 128 * 1024 * 1024:
        raise GradingError(f"memory limit {limits.memory_bytes} B is below 128 MiB: ddes alone "
                           "needs about 100 MiB; give --mem 256M or more")
