"""The sandboxed child: the student's nodes in a ddes world of their own, stepped by the grader.

Started by :class:`ddes.grading.sandbox.Sandbox` as ``python -I -B -m ddes.grading.child SEED
N [SCRIPT NARGS ARG...]*`` with its limits already set (rlimits, its own session, a network
namespace, an unprivileged user where the grader is root).  It then

1. keeps the protocol pipes on private descriptors and points fd 0 at ``/dev/null`` and fd 1 at
   standard error (a ``print`` or ``os.write(1, …)`` of the student lands in the captured
   stderr, never in the protocol stream);
2. imports ddes and builds its world;
3. confines itself with Landlock where the kernel has it (files: read only under the Python
   installation, ddes and the submission copy; write only under the submission copy; TCP bind
   and connect refused; no signals to processes outside the sandbox) and installs an audit hook
   that refuses sockets, subprocesses, ``exec``, ``fork`` and every use of ``ctypes`` that
   reaches memory, a library or a foreign function, ``import ctypes`` among them, as an
   ImportError (numpy and scipy import it in ``try``, and work without it); a seccomp filter
   (:func:`seccomp`) makes every new process, exec and socket fail in the kernel, whatever
   path of Python reaches them; once confined, the grader's own modules (exercises, scenarios,
   scoring) can be neither imported nor read;
4. answers STEP frames (see :mod:`ddes.grading.protocol`) until END or end of input, and the
   CALL frames before them by calling the student's service through a bridge ServiceProxy.

Nothing here is trusted by the grader: it decodes and checks every frame this process writes.
"""

from __future__ import annotations

import os
import sys
from typing import Any

__all__ = ["main"]

BRIDGE = "/ddes_grading_bridge"
#: Topics that ROS latches by convention (tf2_ros's static broadcaster): the child's bridge
#: publisher latches them too, so a message the grader forwards before the student's connection
#: is up (the simulator's one /tf_static at the start) still reaches the student's listener.
LATCHED = ("/tf_static",)


def _read_exact(fd: int, n: int) -> bytes:
    chunks = []
    while n:
        chunk = os.read(fd, n)
        if not chunk:
            raise EOFError
        chunks.append(chunk)
        n -= len(chunk)
    return b"".join(chunks)


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        n = os.write(fd, view)
        view = view[n:]


# -- confinement --------------------------------------------------------------------------------

_FS_EXECUTE, _FS_WRITE_FILE, _FS_READ_FILE, _FS_READ_DIR = 1, 2, 4, 8
_FS_WRITES = sum(1 << i for i in range(4, 13))  # remove dir/file, make char/dir/reg/sock/fifo/block/sym
_FS_REFER, _FS_TRUNCATE, _FS_IOCTL_DEV = 1 << 13, 1 << 14, 1 << 15


def landlock(read_paths: list[str], write_paths: list[str]) -> int:
    """Confine this process with Landlock; returns the ABI used (0: the kernel has none)."""
    import ctypes
    import struct

    libc = ctypes.CDLL(None, use_errno=True)
    syscall = libc.syscall
    syscall.restype = ctypes.c_long
    abi = syscall(444, None, 0, 1)  # landlock_create_ruleset(NULL, 0, LANDLOCK_CREATE_RULESET_VERSION)
    if abi <= 0:
        return 0
    fs = _FS_EXECUTE | _FS_WRITE_FILE | _FS_READ_FILE | _FS_READ_DIR | _FS_WRITES
    if abi >= 2:
        fs |= _FS_REFER
    if abi >= 3:
        fs |= _FS_TRUNCATE
    if abi >= 5:
        fs |= _FS_IOCTL_DEV
    net = 3 if abi >= 4 else 0  # bind and connect TCP, with no rule: refused
    scoped = 3 if abi >= 6 else 0  # abstract unix sockets and signals stay inside
    attr = struct.pack("<Q", fs)
    if abi >= 4:
        attr += struct.pack("<Q", net)
    if abi >= 6:
        attr += struct.pack("<Q", scoped)
    buf = ctypes.create_string_buffer(attr, len(attr))
    ruleset = syscall(444, buf, len(attr), 0)
    if ruleset < 0:
        raise OSError(ctypes.get_errno(), "landlock_create_ruleset")
    read = _FS_EXECUTE | _FS_READ_FILE | _FS_READ_DIR
    rules = [(p, read) for p in read_paths] + [(p, fs) for p in write_paths]
    for path, allowed in rules:
        try:
            fd = os.open(path, os.O_PATH | os.O_CLOEXEC)
        except OSError:
            continue
        if not os.path.isdir(path):
            allowed &= _FS_EXECUTE | _FS_WRITE_FILE | _FS_READ_FILE | _FS_TRUNCATE | _FS_IOCTL_DEV
        rule = ctypes.create_string_buffer(struct.pack("<Qi", allowed & fs, fd), 12)
        if syscall(445, ruleset, 1, rule, 0) < 0:  # landlock_add_rule(PATH_BENEATH)
            os.close(fd)
            raise OSError(ctypes.get_errno(), f"landlock_add_rule {path}")
        os.close(fd)
    if libc.prctl(38, 1, 0, 0, 0) != 0:  # PR_SET_NO_NEW_PRIVS
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_NO_NEW_PRIVS)")
    if syscall(446, ruleset, 0) < 0:  # landlock_restrict_self
        raise OSError(ctypes.get_errno(), "landlock_restrict_self")
    os.close(ruleset)
    return int(abi)


# -- seccomp: no new process, no socket, whatever Python's audit events miss ----------------------

#: Per architecture (``uname -m``): the AUDIT_ARCH value, the system calls refused with EPERM
#: (socket, socketpair, fork, vfork, execve, execveat, ptrace, process_vm_readv/writev, unshare,
#: setns, mount, bpf, userfaultfd, perf_event_open, io_uring_setup, keyctl, add_key,
#: request_key), clone (refused unless it makes a thread: CLONE_THREAD) and clone3 (ENOSYS, so
#: that the C library falls back to clone for its threads).
_SECCOMP_ARCH: dict[str, tuple[int, tuple[int, ...], int, int]] = {
    "x86_64": (0xC000003E, (41, 53, 57, 58, 59, 322, 101, 310, 311, 272, 308, 165, 321, 323,
                            298, 425, 250, 248, 249), 56, 435),
    "aarch64": (0xC00000B7, (198, 199, 221, 281, 117, 270, 271, 97, 268, 40, 280, 282, 241,
                             425, 219, 217, 218), 220, 435),
}
_CLONE_THREAD = 0x00010000


def seccomp_program(machine: str) -> list[tuple[int, int, int, int]] | None:
    """The classic-BPF filter (code, jt, jf, k) for ``machine``, or None when unknown."""
    spec = _SECCOMP_ARCH.get(machine)
    if spec is None:
        return None
    arch, denied, clone, clone3 = spec
    ld_w_abs, jeq, jge, jset, ret = 0x20, 0x15, 0x35, 0x45, 0x06
    allow, eperm, enosys = 0x7FFF0000, 0x00050000 | 1, 0x00050000 | 38
    prog: list[tuple[int, int, int, int]] = [
        (ld_w_abs, 0, 0, 4),            # seccomp_data.arch
        (jeq, 1, 0, arch),
        (ret, 0, 0, eperm),             # another ABI (x32, ia32): refused
        (ld_w_abs, 0, 0, 0),            # seccomp_data.nr
        (jge, 0, 1, 0x40000000),        # the x32 range
        (ret, 0, 0, eperm),
    ]
    n = len(denied)
    for i, nr in enumerate(denied):      # jump to the EPERM at the end of the list
        prog.append((jeq, n - i + 6, 0, nr))
    prog += [
        (jeq, 0, 3, clone),              # clone: a thread or nothing
        (ld_w_abs, 0, 0, 16),            # the low word of args[0], the flags
        (jset, 3, 0, _CLONE_THREAD),
        (ret, 0, 0, eperm),
        (jeq, 0, 1, clone3),
        (ret, 0, 0, enosys),
        (ret, 0, 0, allow),
    ]
    # the denied list jumps past these to here
    prog.append((ret, 0, 0, eperm))
    return prog


def seccomp() -> str:
    """Install :func:`seccomp_program` on every thread of this process (no_new_privs is set
    first); returns what is enforced, or "" where the kernel or the machine has no seccomp."""
    import ctypes
    import platform
    import struct

    prog = seccomp_program(platform.machine())
    if prog is None:
        return ""
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(38, 1, 0, 0, 0) != 0:  # PR_SET_NO_NEW_PRIVS
        return ""
    code = b"".join(struct.pack("<HBBI", c, jt, jf, k) for c, jt, jf, k in prog)
    filt = ctypes.create_string_buffer(code, len(code))
    fprog = struct.pack("<HxxxxxxQ", len(prog), ctypes.addressof(filt))
    fbuf = ctypes.create_string_buffer(fprog, len(fprog))
    libc.syscall.restype = ctypes.c_long
    nr = {"x86_64": 317, "aarch64": 277}[platform.machine()]
    if libc.syscall(nr, 1, 1, fbuf) != 0:  # seccomp(SET_MODE_FILTER, FLAG_TSYNC, &prog)
        return ""
    return "seccomp"


#: What the audit hook refuses: whatever reaches past Python into the process or the system.
_REFUSED_EVENTS = frozenset({
    "socket.__new__", "socket.connect", "socket.bind", "socket.sendto", "socket.getaddrinfo",
    "subprocess.Popen", "os.system", "os.exec", "os.posix_spawn", "os.spawn", "os.fork",
    "os.forkpty", "pty.spawn", "ctypes.dlopen", "ctypes.dlsym", "ctypes.dlsym/handle",
    "ctypes.cdata", "ctypes.cdata/buffer", "ctypes.call_function", "ctypes.addressof",
    "ctypes.string_at", "ctypes.wstring_at", "ctypes.PyObj_FromPtr",
    "os.kill", "os.killpg", "signal.pthread_kill", "sys.addaudithook",
})


class SandboxImportRefused(ImportError):
    """``import ctypes`` in the sandbox.  ctypes reaches memory without an audit event
    (``ctypes.memmove`` to any address, ``cast`` of any address to an object: Python 3.11
    raises none for them), so it is what escapes, and the sandbox is a Python without it.  The
    refusal is an ImportError, as on a Python built without ctypes: numpy (and scipy) import
    ctypes in ``try: ... except ImportError`` and work without it (only ``ndarray.ctypes`` and
    ``numpy.ctypeslib`` are then missing, as there)."""


#: The grader's own package: once the child is confined, nothing more of it is imported or read
#: (the child has the protocol and its stand-ins; exercises, scenarios and scoring stay out).
_GRADING_DIR = os.path.dirname(os.path.abspath(__file__))
#: Events one simulated instant may hold in the child before it ends as a zero-time livelock
#: (the kernel's default, 10 million, takes half a minute to reach; this, a few seconds).
INSTANT_BUDGET = 300_000


def _audit(event: str, args: tuple[Any, ...]) -> None:
    if event in _REFUSED_EVENTS:
        raise PermissionError(f"the grading sandbox refuses {event}")
    if event == "import" and args and str(args[0]).startswith("ddes.grading") \
            and str(args[0]) not in sys.modules:
        raise ImportError(f"the grading sandbox refuses to import the grader's {args[0]}: a "
                          "node does not need it", name=str(args[0]))
    if event == "open" and args and isinstance(args[0], str) \
            and os.path.abspath(args[0]).startswith(_GRADING_DIR + os.sep):
        raise PermissionError(f"the grading sandbox refuses to read the grader's {args[0]}")
    if event == "import" and args and str(args[0]).split(".")[0] in ("ctypes", "_ctypes"):
        raise SandboxImportRefused(
            "the grading sandbox refuses ctypes (it reaches memory and libraries outside "
            "Python); numpy and every module that can do without ctypes import as usual",
            name=str(args[0]))


# -- the bridge ---------------------------------------------------------------------------------

class _Bridge:
    """The child's end: bridge endpoints on every topic the student's nodes use."""

    def __init__(self, world: Any, out_fd: int) -> None:
        self.world = world
        self.out = out_fd
        self.node = world.create_node(BRIDGE, disable_rosout=True)
        self.frames: list[bytes] = []
        self.pubs: dict[str, Any] = {}   # topic -> bridge publisher (grader -> student)
        self.subs: dict[str, Any] = {}   # topic -> bridge subscriber (student -> grader)
        self.seen_pub: set[tuple[str, str]] = set()
        self.seen_sub: set[tuple[str, str]] = set()
        self.seen_srv: set[tuple[str, str]] = set()
        self.clients: dict[str, Any] = {}  # service -> the bridge's ServiceProxy
        self.live: dict[str, None] = {}
        self.reads: set[tuple[str, str, bool]] = set()
        world.param_observer = self.read
        self.failed: set[tuple[str, str]] = set()
        self.errors_seen = 0
        self.stand_ins: dict[str, Any] = {}     # service -> its stand-in (OFFER)
        self.asks: dict[int, tuple[Any, Any, Any]] = {}  # id -> (stand-in, conn, call)
        self.next_ask = 0

    def offer(self, offers: list[Any]) -> None:
        """Serve a stand-in for each service served outside this child (OFFER): its calls
        cross as ASK frames, its answers come back as ANSWER."""
        from ddes.grading.bridge import ForwardingService

        for o in offers:
            if o.service in self.stand_ins or self.world.master.lookup_service(o.service):
                continue
            try:
                cls = self.world.messages.get_service_class(o.type)
                if cls._md5sum != o.md5:
                    continue
                self.stand_ins[o.service] = ForwardingService(self.node, o.service, cls, self.ask)
            except Exception:  # noqa: BLE001 - a name or type this world cannot serve: none
                continue

    def ask(self, service: Any, conn: Any, call: Any) -> None:
        from ddes.grading import protocol

        self.next_ask += 1
        self.asks[self.next_ask] = (service, conn, call)
        self.frames.append(protocol.encode_ask(self.next_ask, conn.proxy.node.name,
                                               service.resolved_name, call.data))

    def answer(self, answers: list[Any]) -> None:
        for a in answers:
            found = self.asks.pop(a.id, None)
            if found is not None:
                service, conn, call = found
                service._send(conn, call, a.ok, a.data if a.ok else
                              a.data.decode("utf-8", "replace"))

    def read(self, node: str, key: str, found: bool) -> None:
        """A student node read a parameter: told once per (node, key, found)."""
        from ddes.grading import protocol

        if node != BRIDGE and (node, key, found) not in self.reads and len(self.reads) < 4096:
            self.reads.add((node, key, found))
            self.frames.append(protocol.encode_read(node, key, found))

    def watch(self, path: str, done: Any, context: Any) -> None:
        """Tell the grader when the script ``path``'s main ends with an exception."""
        from ddes.graph.failures import user_traceback

        def ended(ev: Any) -> None:
            if ev.ok or not isinstance(ev.value, BaseException):
                return
            from ddes.grading import protocol

            node = context.node
            who = node.name if node is not None else os.path.basename(path)
            self.frames.append(protocol.encode_died(who, self.world.env.now_ns, True,
                                                    user_traceback(ev.value)))

        done.callbacks.insert(0, ended)

    def callback_errors(self) -> None:
        """Tell the grader of the first failure of each student callback since the last step
        (the node goes on, as rospy's does)."""
        from ddes.grading import protocol
        from ddes.graph.failures import user_traceback

        errors = self.world.callback_errors
        for node, callback, exc, _text in errors[self.errors_seen:]:
            if node != BRIDGE and (node, callback) not in self.failed and len(self.failed) < 64:
                self.failed.add((node, callback))
                self.frames.append(protocol.encode_died(
                    node, self.world.env.now_ns, False,
                    f"in the callback {callback}:\n{user_traceback(exc)}"))
        self.errors_seen = len(errors)

    def capture(self, topic: str) -> Any:
        from ddes.graph.topics import AnyMsg, Subscriber

        def cb(msg: Any) -> None:
            caller = msg._connection_header.get("callerid", "")
            if caller != BRIDGE:
                from ddes.grading import protocol

                self.frames.append(protocol.encode_msg(caller, topic, self.world.now, msg._buff))

        return Subscriber(self.node, topic, AnyMsg, cb, internal=True)

    def inject(self, messages: tuple[tuple[str, str, str, bytes], ...]) -> None:
        for topic, type_, md5, data in messages:
            pub = self.pubs.get(topic)
            if pub is None or pub.type != type_ or pub.md5sum != md5:
                continue
            cls = pub.data_class
            pub.publish(cls.__new__(cls)._deserialize_from(data))

    def call(self, calls: list[Any]) -> None:
        """Call the student's services for the grader's CALL frames; each answer becomes a RESP
        frame when it arrives (now, or later in simulated time)."""
        from ddes.grading import protocol
        from ddes.services.client import ServiceProxy

        for c in calls:
            entry = self.world.master.lookup_service(c.service)
            if entry is None or entry.node.name == BRIDGE:
                self.frames.append(protocol.encode_resp(c.id, False,
                                                        f"service [{c.service}] unavailable"))
                continue
            try:
                proxy = self.clients.get(c.service)
                if proxy is None or proxy.service_class is not entry.server.service_class:
                    proxy = self.clients[c.service] = ServiceProxy(
                        self.node, c.service, entry.server.service_class)
                cls = proxy.request_class
                request = cls.__new__(cls)._deserialize_from(c.data)
                pending = proxy._start((request,), {}, None)
            except Exception as exc:  # noqa: BLE001 - answered as an error, never raised
                self.frames.append(protocol.encode_resp(c.id, False, f"{type(exc).__name__}: {exc}"))
                continue

            def answer_call(ev: Any, call_id: int = c.id, pc: Any = pending) -> None:
                ev.defused = True
                if ev.ok:
                    data = ev.value._serialize_to_bytes()
                    self.frames.append(protocol.encode_resp(call_id, True, data))
                else:
                    text = pc.server_text if pc.server_text is not None else str(ev.value)
                    self.frames.append(protocol.encode_resp(call_id, False, text))

            pending.event.callbacks.append(answer_call)

    def discover(self) -> None:
        from ddes.grading import protocol
        from ddes.graph.topics import Publisher

        for name, entry in list(self.world.master.topics.items()):
            for pub in entry.publishers:
                who = pub.node.name
                if who == BRIDGE or (who, name) in self.seen_pub:
                    continue
                self.seen_pub.add((who, name))
                self.frames.append(protocol.encode_adv(who, name, pub.type, pub.md5sum, pub.latch))
                if name not in self.subs:
                    self.subs[name] = self.capture(name)
            for sub in entry.subscribers:
                who = sub.node.name
                if who == BRIDGE or (who, name) in self.seen_sub or sub.type == "*":
                    continue
                self.seen_sub.add((who, name))
                qs = -1 if sub.queue_size is None else int(sub.queue_size)
                self.frames.append(protocol.encode_sub(who, name, sub.type, sub.md5sum, qs))
                if name not in self.pubs:
                    self.pubs[name] = Publisher(self.node, name, sub.data_class, queue_size=None,
                                               latch=name in LATCHED)
        for name, sentry in list(self.world.master.services.items()):
            who = sentry.node.name
            if who == BRIDGE or (who, name) in self.seen_srv:
                continue
            self.seen_srv.add((who, name))
            self.frames.append(protocol.encode_srv(who, name, sentry.type, sentry.md5sum))
        nodes = self.world.nodes
        for name, node in nodes.items():
            if name != BRIDGE and not node.is_shutdown():
                self.live.setdefault(name, None)
        for name in list(self.live):
            node = nodes.get(name)
            if node is None or node.is_shutdown():
                del self.live[name]
                self.frames.append(protocol.encode_gone(name))

    def flush(self, next_ns: int) -> None:
        from ddes.grading import protocol

        self.frames.append(protocol.encode_done(next_ns))
        _write_all(self.out, b"".join(self.frames))
        self.frames = []


def _parse_scripts(argv: list[str]) -> tuple[int, list[tuple[str, list[str]]]]:
    seed = int(argv[0])
    n = int(argv[1])
    scripts, i = [], 2
    for _ in range(n):
        path, nargs = argv[i], int(argv[i + 1])
        scripts.append((path, argv[i + 2:i + 2 + nargs]))
        i += 2 + nargs
    return seed, scripts


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    seed, scripts = _parse_scripts(argv)
    inp, out = os.dup(0), os.dup(1)
    # the grader's mark on this child's processes (it finds leftovers by it in /proc): it stays
    # in the process's environment, which what the child starts inherits, and leaves
    # os.environ, which the student's code reads
    os.environ._data.pop(os.environ.encodekey("DDES_GRADING_TOKEN"), None)  # type: ignore[attr-defined]
    devnull = os.open(os.devnull, os.O_RDONLY)
    os.dup2(devnull, 0)
    os.close(devnull)
    os.dup2(2, 1)
    sys.stdout = sys.stderr

    import random

    import ddes
    from ddes.compat.scripts import run_script  # noqa: F401 - imported before the confinement
    from ddes.errors import RunawayError
    from ddes.grading import bridge as _stand_ins  # noqa: F401 - imported before the confinement
    from ddes.grading import protocol
    from ddes.graph.world import World

    world = World(seed, wall_budget=None, instant_budget=INSTANT_BUDGET)
    world.log_output = None
    import json

    # global parameters the grader sets before the student's nodes start (/use_sim_time)
    for key, value in sorted(json.loads(os.environ.get("DDES_GRADING_PARAMS", "{}")).items()):
        world.master.params.set_param(key, value)
    bridge = _Bridge(world, out)
    random.seed(seed)
    cwd = os.getcwd()
    # the submission's copy is shown as /submission in logs, as in the grader's world
    # (ddes.grading.grader.submission_paths): a digest does not depend on the temporary folder
    world.display_paths = {cwd: "/submission", os.path.realpath(cwd): "/submission"}
    reads = sorted({sys.prefix, sys.base_prefix, sys.exec_prefix, ddes.__path__[0],
                    os.path.dirname(os.path.realpath(sys.executable)), "/usr/lib", "/usr/lib64",
                    "/lib", "/lib64", "/usr/share/zoneinfo", "/dev/null"})
    reads += [p for p in sys.path if p and os.path.isdir(p) and "site-packages" in p]
    abi = landlock(reads, [cwd]) if os.environ.get("DDES_GRADING_LANDLOCK", "1") == "1" else 0
    filtered = seccomp() if os.environ.get("DDES_GRADING_SECCOMP", "1") == "1" else ""
    print(f"[ddes grading sandbox] landlock abi {abi}, seccomp {'on' if filtered else 'off'}",
          file=sys.stderr, flush=True)
    for name in [m for m in sys.modules if m.split(".")[0] in ("ctypes", "_ctypes")]:
        del sys.modules[name]
    from ddes.grading import determinism  # clocks and entropy of the child pinned to its world
    determinism.install(world, scripts)
    sys.addaudithook(_audit)
    _write_all(out, protocol.encode_ready())

    def printer(line: str, _err: bool) -> None:
        print(line, file=sys.stderr, flush=True)

    started = False
    calls: list[Any] = []
    offers: list[Any] = []
    answers: list[Any] = []
    while True:
        try:
            header = _read_exact(inp, protocol.HEADER.size)
        except EOFError:
            return 0
        kind, length = protocol.decode_header(header)
        frame = protocol.decode_frame(kind, _read_exact(inp, length))
        if isinstance(frame, protocol.Call):
            calls.append(frame)  # made at the STEP that follows
            continue
        if isinstance(frame, protocol.Offer):
            offers.append(frame)
            continue
        if isinstance(frame, protocol.Answer):
            answers.append(frame)
            continue
        if not isinstance(frame, protocol.Step):
            return 0
        t = frame.t_ns
        try:
            _step(world, bridge, frame, t, scripts, cwd, printer, started, offers, answers,
                  calls)
        except RunawayError as exc:  # a zero-time livelock of the student's nodes: named, ended
            print(f"ddes: {exc}", file=sys.stderr, flush=True)
            return 3
        started = True
        offers, answers, calls = [], [], []


def _step(world: Any, bridge: _Bridge, frame: Any, t: int, scripts: list[tuple[str, list[str]]],
          cwd: str, printer: Any, started: bool, offers: list[Any], answers: list[Any],
          calls: list[Any]) -> None:
    """One STEP: time up to ``t``, what crossed in, the scripts at the first, the instant, the
    reply."""
    from ddes.compat.scripts import run_script

    if world.now < t:
        world.run(until=_ns(t))
    if offers:
        bridge.offer(offers)
    bridge.inject(frame.messages)
    if answers:
        bridge.answer(answers)
    if calls:
        bridge.call(calls)
    if not started:
        for path, args in scripts:
            done, context = run_script(world, os.path.join(cwd, path), args,
                                       print_line=printer)
            bridge.watch(path, done, context)
    world.run_through(t)
    bridge.callback_errors()
    bridge.discover()
    nxt = world.env.peek()
    bridge.flush(-1 if nxt == float("inf") else int(nxt))


def _ns(t: int) -> Any:
    from ddes.time import Time

    return Time._from_ns(t)


if __name__ == "__main__":
    sys.exit(main())
