"""An external node (a C++ process built against ddes's roscpp) joined to a world in lockstep.

:class:`ExternalNode` starts the process with the two pipes of docs/external-nodes.md and
serves its frames.  The process is a coroutine of the world: the world's thread sends it a
frame and then reads until the process blocks (a blocking request) or ends a callback
(``CB_DONE``); every request is carried out on an ordinary ddes :class:`~ddes.graph.node.Node`
of roscpp style, so the graph, the trace and the digest are those of a Python node.

Conversations nest as the process's stack does: the main conversation (``ros::init`` to the
process's exit), and above it the callbacks the node's spinner hands it.  A blocking request
whose event has fired is answered only when its conversation is on top again (the process is
one thread of execution).  roscpp's spinning is the node's callback queue: ``manual`` (callbacks
wait for ``ros::spinOnce``), running them as they come while ``ros::spin()`` or an
``AsyncSpinner`` runs (one at a time: documented in docs/roscpp.md).
"""

from __future__ import annotations

import os
import select
import signal
import subprocess
import sys
import time
import weakref
from collections.abc import Callable, Generator, Sequence
from typing import TYPE_CHECKING, Any

import simpy

from ddes.errors import DdesError, ProtocolError, ROSException
from ddes.graph.names import NameResolver, parse_node_args
from ddes.roscpp import protocol as P

if TYPE_CHECKING:
    from ddes.graph.node import Node
    from ddes.graph.world import World

__all__ = ["DEFAULT_STEP_WALL_S", "ExternalNode", "ExternalNodeError", "close_all"]

#: Wall-clock seconds a process may hold the floor before the watchdog stops it.
DEFAULT_STEP_WALL_S = 10.0
#: Wall-clock seconds from starting the process to its HELLO (loading a program takes longer
#: on a loaded machine than any step should).
DEFAULT_STARTUP_WALL_S = 60.0
_KEY = "ddes.roscpp.external_nodes"

_LOG_LEVELS = (1, 2, 4, 8, 16)  # rosgraph_msgs/Log DEBUG INFO WARN ERROR FATAL, by the frame's 0..4
_BLOCKING = {P.CALL, P.WAIT_FOR_SERVICE, P.SLEEP_UNTIL, P.SPIN, P.SPIN_ONCE, P.WAIT_FOR_MESSAGE}


class ExternalNodeError(DdesError):
    """An external node broke the protocol, or could not be started."""


def _registry(world: World) -> list[ExternalNode]:
    return world.extension(_KEY, lambda _w: [])


def close_all(world: World) -> None:
    """Stop every external node process of ``world`` (its run is over)."""
    for host in list(_registry(world)):
        host.close()


def _kill(proc: subprocess.Popen[bytes]) -> None:
    if proc.poll() is None:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            proc.kill()
        proc.wait()


class _Conversation:
    """One frame of the process's stack: the main, or a callback."""

    __slots__ = ("id", "turn", "waiter")

    def __init__(self, cid: int) -> None:
        self.id = cid
        #: Fired when this conversation is on top again (set while it waits for its turn).
        self.turn: simpy.Event | None = None
        #: What its blocking request waits on (set while it waits).
        self.waiter: simpy.Event | None = None


class ExternalNode:
    """One external node process (``argv[0]`` is the executable) in ``world``.

    ``name``/``namespace``/``remappings`` are what rosrun or a launch file give the node
    (``__name:=``, ``ROS_NAMESPACE``/``ns=``, ``<remap>``); the process's own ``ros::init`` name
    and command line apply first, as in roscpp.  ``print_line(text, is_stderr)`` receives the
    process's own standard output and error, line by line (default: this process's).
    """

    def __init__(self, world: World, argv: Sequence[str], *, name: str | None = None,
                 namespace: str = "/", remappings: dict[str, str] | None = None,
                 cwd: str | None = None, env: dict[str, str] | None = None,
                 print_line: Callable[[str, bool], None] | None = None,
                 step_wall_s: float | None = None) -> None:
        if not argv:
            raise ExternalNodeError("an external node needs a command line (the executable first)")
        self.world = world
        self.argv = [str(a) for a in argv]
        self.launch_name = name
        self.namespace = namespace
        self.remappings = dict(remappings or {})
        self.cwd = cwd
        self.env = dict(env) if env is not None else None
        self.print_line = print_line
        if step_wall_s is None:
            step_wall_s = float(os.environ.get("DDES_NODE_STEP_WALL_S", DEFAULT_STEP_WALL_S))
        self.step_wall_s = step_wall_s
        #: The node, once the process called ros::init.
        self.node: Node | None = None
        #: The process's exit code once it ended (negative: the signal that ended it).
        self.exit_code: int | None = None
        #: Why the world stopped the process (watchdog, protocol error), or "".
        self.verdict = ""
        self.pid = 0
        self._proc: subprocess.Popen[bytes] | None = None
        self._rfd = self._wfd = -1
        self._out_fds: dict[int, bool] = {}
        self._partial: dict[int, bytes] = {}
        #: Bytes read from the process and not yet taken as frames.
        self._buf = bytearray()
        self._stack: list[_Conversation] = []
        self._next_cb = 0
        self._pubs: dict[int, Any] = {}
        self._subs: dict[int, Any] = {}
        self._services: dict[int, Any] = {}
        self._timers: dict[int, Any] = {}
        #: Persistent service clients (``serviceClient(name, true)``), by (service, type).
        self._persistent: dict[tuple[str, str, bool], Any] = {}
        #: Connect callbacks' single-subscriber publishers, by (publisher id, caller id).
        self._peers: dict[tuple[int, str], Any] = {}
        self._next_id = 0
        self._finalizer: weakref.finalize | None = None
        self._done = world.env.event()
        self._shutdown_sent = False

    # -- life -------------------------------------------------------------------------------
    @property
    def done(self) -> simpy.Event:
        """Fires with the exit code when the process has ended."""
        return self._done

    def start(self) -> Node | None:
        """Start the process and run it now until it first blocks, as a rospy script starts
        (:func:`ddes.compat.scripts.run_script`): its node once ``ros::init`` made it, or None
        when the process ended (or was stopped) before that.  The rest of its main
        conversation runs as a kernel process; :attr:`done` fires at its end."""
        self._spawn()
        gen = self._main()
        try:
            first = next(gen)
        except StopIteration:
            return self.node
        self.world.env.process(_drive(gen, first))
        return self.node

    def _spawn(self) -> None:
        to_child_r, to_child_w = os.pipe()
        from_child_r, from_child_w = os.pipe()
        env = dict(os.environ if self.env is None else self.env)
        env["DDES_NODE_FDS"] = f"{to_child_r},{from_child_w}"
        env["DDES_PROTOCOL"] = str(P.VERSION)
        try:
            self._proc = subprocess.Popen(
                self.argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                stderr=subprocess.PIPE, pass_fds=(to_child_r, from_child_w), cwd=self.cwd,
                env=env, start_new_session=True)
        except OSError as exc:
            for fd in (to_child_r, to_child_w, from_child_r, from_child_w):
                os.close(fd)
            raise ExternalNodeError(f"cannot start {self.argv[0]}: {exc.strerror or exc}") from None
        os.close(to_child_r)
        os.close(from_child_w)
        self._rfd, self._wfd = from_child_r, to_child_w
        os.set_blocking(self._rfd, False)
        self.pid = self._proc.pid
        assert self._proc.stdout is not None and self._proc.stderr is not None
        for stream, is_err in ((self._proc.stdout, False), (self._proc.stderr, True)):
            fd = stream.fileno()
            os.set_blocking(fd, False)
            self._out_fds[fd] = is_err
            self._partial[fd] = b""
        proc = self._proc
        self._finalizer = weakref.finalize(self, _kill, proc)
        _registry(self.world).append(self)

    def close(self) -> None:
        """Stop the process (if it still runs) and free its pipes."""
        if self._proc is not None:
            _kill(self._proc)
            self._drain_output(final=True)
            if self.exit_code is None:
                self.exit_code = self._proc.returncode
        for fd in (self._rfd, self._wfd):
            if fd >= 0:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self._rfd = self._wfd = -1
        if self._proc is not None:
            for stream in (self._proc.stdout, self._proc.stderr):
                if stream is not None:
                    stream.close()
        reg = _registry(self.world)
        if self in reg:
            reg.remove(self)

    def death_text(self) -> str:
        """roslaunch's line for a process that ended (``process has died [pid …]``)."""
        return (f"process has died [pid {self.pid}, exit code {self.exit_code}, cmd "
                f"{' '.join(self.argv)}]")

    # -- the pipe ---------------------------------------------------------------------------
    def _send(self, data: bytes) -> None:
        view = memoryview(data)
        while view:
            try:
                n = os.write(self._wfd, view)
            except BlockingIOError:  # pragma: no cover - the pipe is blocking
                continue
            except BrokenPipeError:
                raise _ProcessEnded() from None
            view = view[n:]

    def _fill(self, deadline: float) -> None:
        """Read what the process has written (at least one byte), into the buffer.

        ``deadline`` is on the wall clock (``time.monotonic``): the watchdog's budget, which only
        stops a process that never hands back; it decides nothing in the trace."""
        while True:
            try:
                chunk = os.read(self._rfd, 1 << 16)  # non-blocking: what is there already
            except BlockingIOError:
                chunk = None
            if chunk is not None:
                if not chunk:
                    raise _ProcessEnded()
                self._buf += chunk
                return
            left = deadline - time.monotonic()
            if left <= 0:
                raise _Watchdog()
            ready, _, _ = select.select([self._rfd, *self._out_fds], [], [], left)
            for fd in ready:
                if fd in self._out_fds:
                    self._read_output(fd)

    def _read_frame(self, budget: float | None = None) -> tuple[int, bytes]:
        """The next frame: from the buffer, reading more only when it holds no whole frame
        (one read takes every frame the process wrote since)."""
        buf = self._buf
        if len(buf) >= P.HEADER_SIZE:
            kind, size = P.split_header(bytes(buf[:P.HEADER_SIZE]))
            end = P.HEADER_SIZE + size
            if len(buf) >= end:
                payload = bytes(buf[P.HEADER_SIZE:end])
                del buf[:end]
                return kind, payload
        deadline = time.monotonic() + (self.step_wall_s if budget is None else budget)
        while len(buf) < P.HEADER_SIZE:
            self._fill(deadline)
        kind, size = P.split_header(bytes(buf[:P.HEADER_SIZE]))
        end = P.HEADER_SIZE + size
        while len(buf) < end:
            self._fill(deadline)
        payload = bytes(buf[P.HEADER_SIZE:end])
        del buf[:end]
        return kind, payload

    def _read_output(self, fd: int) -> None:
        try:
            data = os.read(fd, 65536)
        except BlockingIOError:
            return
        is_err = self._out_fds.get(fd, True)
        if not data:
            self._out_fds.pop(fd, None)
            rest = self._partial.pop(fd, b"")
            if rest:
                self._emit(rest, is_err)
            return
        buf = self._partial.get(fd, b"") + data
        *lines, rest = buf.split(b"\n")
        self._partial[fd] = rest
        for line in lines:
            self._emit(line, is_err)

    def _drain_output(self, final: bool = False) -> None:
        for fd in list(self._out_fds):
            while fd in self._out_fds:
                try:
                    ready, _, _ = select.select([fd], [], [], 0)
                except (OSError, ValueError):
                    break
                if not ready:
                    break
                self._read_output(fd)
            if final and self._partial.get(fd):
                self._emit(self._partial.pop(fd), self._out_fds.get(fd, True))

    def _emit(self, raw: bytes, is_err: bool) -> None:
        text = raw.decode("utf-8", "replace")
        if self.print_line is not None:
            self.print_line(text, is_err)
        else:
            (sys.stderr if is_err else sys.stdout).write(text + "\n")

    # -- replies ----------------------------------------------------------------------------
    def _times(self) -> tuple[int, int]:
        node = self.node
        wall = self.world.env.now_ns
        return (node.clock.now_ns() if node is not None else wall), wall

    def _reply(self, req: int, payload: bytes = b"") -> None:
        now, wall = self._times()
        self._send(P.frame(P.REPLY, P.Writer().u32(req).i64(now).i64(wall).u8(0).payload()
                           + payload))

    def _reply_error(self, req: int, text: str) -> None:
        now, wall = self._times()
        self._send(P.Writer().u32(req).i64(now).i64(wall).u8(1).string(text).frame(P.REPLY))

    def _new_id(self) -> int:
        self._next_id += 1
        return self._next_id

    # -- the main conversation --------------------------------------------------------------
    def _main(self) -> Generator[simpy.Event, Any, int | None]:
        main = _Conversation(0)
        self._stack.append(main)
        try:
            kind, payload = self._read_frame(max(self.step_wall_s, DEFAULT_STARTUP_WALL_S))
            if kind != P.HELLO:
                raise ProtocolError(f"protocol error: the first frame must be HELLO, got "
                                    f"{P.KINDS[kind]}")
            self._hello(payload)
            yield from self._converse(main, None)
        except _ProcessEnded:
            pass
        except _Watchdog:
            self.verdict = (f"the node did not hand back within {self.step_wall_s:g} s of wall "
                            "time (a loop that never calls ros::spinOnce, a sleep, or another "
                            "blocking call?)")
        except ProtocolError as exc:
            self.verdict = str(exc)
        return self._ended()

    def _ended(self) -> int | None:
        proc = self._proc
        if proc is not None:
            if self.verdict:
                _kill(proc)
            try:
                proc.wait(timeout=self.step_wall_s)
            except subprocess.TimeoutExpired:
                _kill(proc)
            self._drain_output(final=True)
            self.exit_code = proc.returncode
        node = self.node
        if self.verdict:
            self._emit(f"[ddes] {self.verdict}".encode(), True)
        if node is not None and not node.is_shutdown():
            self.world.record("node.exit", node.name, code=self.exit_code)
            node.shutdown("process ended")
        self.close()
        if not self._done.triggered:
            self._done.succeed(self.exit_code)
        return self.exit_code

    def _hello(self, payload: bytes) -> None:
        r = P.Reader(payload, "HELLO")
        version = r.u32("version")
        name = r.string("name")
        options = r.u32("options")
        argv = [r.string("argv") for _ in range(r.u32("argc"))]
        r.end()
        if version != P.VERSION:
            self._reply_error(0, f"protocol version {version} is not spoken by this ddes (it "
                                 f"speaks {P.VERSION})")
            raise ProtocolError(f"protocol error: the node speaks version {version}")
        args = list(argv[1:])
        if self.launch_name is not None and not any(a.startswith("__name:=") for a in args):
            args.append(f"__name:={self.launch_name}")
        node = self.world.create_node(
            name, namespace=self.namespace, argv=args, remappings=self.remappings,
            anonymous=bool(options & 1), spinner="manual", log_style="roscpp",
            disable_rosout=bool(options & 4))
        self.node = node
        rest = [argv[0] if argv else self.argv[0], *parse_node_args(args).args]
        w = P.Writer().string(node.name).string(node.get_namespace()).u8(1 if node.use_sim_time else 0)
        w.u32(len(rest))
        for a in rest:
            w.string(a)
        self._reply(0, w.payload())
        node.spin().callbacks.append(self._on_shutdown)

    def _on_shutdown(self, _ev: simpy.Event) -> None:
        if self._shutdown_sent or self._rfd < 0 or self.exit_code is not None:
            return
        self._shutdown_sent = True
        now, wall = self._times()
        try:
            self._send(P.Writer().i64(now).i64(wall).string("node shut down").frame(
                P.SHUTDOWN_NOTICE))
        except _ProcessEnded:
            pass

    # -- one conversation: frames until its end -----------------------------------------------
    def _converse(self, me: _Conversation, cb: int | None
                  ) -> Generator[simpy.Event, Any, tuple[int, bytes] | None]:
        """Serve frames for ``me`` until the process ends (the main) or sends ``CB_DONE cb``."""
        while True:
            kind, payload = self._read_frame()
            if kind == P.CB_DONE:
                r = P.Reader(payload, "CB_DONE")
                got, ok, data = r.u32("cb"), r.u8("ok"), r.blob("payload")
                r.end()
                if got != cb:
                    raise ProtocolError(f"protocol error: CB_DONE {got} while callback {cb} "
                                        "runs")
                return ok, data
            if kind in _BLOCKING:
                req, event = self._blocking(kind, payload)
                # the wait, which a callback's exception (CB_DONE ok 2) may cut short
                waiter = me.waiter = self.world.env.event()
                event.callbacks.append(_relay(waiter))
                try:
                    value = yield waiter
                except Exception as exc:  # noqa: BLE001 - the request's failure is its answer
                    value = exc
                if isinstance(event, simpy.Event) and not event.triggered:
                    event.defused = True  # nobody waits on it any more
                me.waiter = None
                while self._stack[-1] is not me:  # the process is in a callback above me
                    me.turn = self.world.env.event()
                    yield me.turn
                if value is _INTERRUPTED:
                    if self.node is not None and not self.node.is_shutdown():
                        self.node.callbacks.set_manual(True)  # no more callbacks for it
                    self._reply_error(req, "interrupted by an exception in a callback")
                    continue
                self._answer(kind, req, value)
            else:
                self._immediate(kind, payload)

    # -- immediate requests -------------------------------------------------------------------
    def _immediate(self, kind: int, payload: bytes) -> None:
        node = self._need_node(kind)
        name = P.KINDS[kind]
        r = P.Reader(payload, name)
        if kind == P.PUBLISH:
            pid = r.u32("id")
            data = r.blob("message")
            r.end()
            pub = self._pubs.get(pid)
            if pub is None:
                raise ProtocolError(f"protocol error: PUBLISH on unknown publisher {pid}")
            msg = _decode(pub.data_class, data, "PUBLISH")
            pub.publish(msg)
            return
        if kind == P.PUBLISH_ONE:
            pid, caller, data = r.u32("id"), r.string("subscriber"), r.blob("message")
            r.end()
            pub = self._pubs.get(pid)
            if pub is None:
                raise ProtocolError(f"protocol error: PUBLISH_ONE on unknown publisher {pid}")
            peer = self._peers.get((pid, caller))
            if peer is not None:  # a subscriber gone by now gets nothing
                peer(_decode(pub.data_class, data, "PUBLISH_ONE"))
            return
        if kind == P.LOG:
            level = r.u8("level")
            logger, text = r.string("logger"), r.string("text")
            file, function, line = r.string("file"), r.string("function"), r.u32("line")
            r.end()
            # the process has filtered by its loggers' levels already (roscpp's rosconsole)
            node.log.log_at(_LOG_LEVELS[min(level, 4)], text, file, function, line,
                            logger=logger, filtered=True)
            return
        if kind in (P.UNADVERTISE, P.UNSUBSCRIBE, P.UNADVERTISE_SERVICE):
            eid = r.u32("id")
            r.end()
            table = {P.UNADVERTISE: self._pubs, P.UNSUBSCRIBE: self._subs,
                     P.UNADVERTISE_SERVICE: self._services}[kind]
            entity = table.pop(eid, None)
            if entity is not None:
                entity.unregister()
            return
        if kind == P.TIMER_CONTROL:
            tid, op, period, _reset = r.u32("id"), r.u8("op"), r.i64("period"), r.u8("reset")
            r.end()
            self._timer_control(tid, op, period)
            return
        if kind == P.REQUEST_SHUTDOWN:
            reason = r.string("reason")
            r.end()
            node.signal_shutdown(reason or "requestShutdown")
            return
        req = r.u32("req")
        try:
            out = self._query(kind, r, node)
        except ProtocolError:
            raise
        except DdesError as exc:
            self._reply_error(req, str(exc))
            return
        self._reply(req, out)

    def _query(self, kind: int, r: P.Reader, node: Node) -> bytes:
        w = P.Writer()
        if kind == P.RESOLVE:
            ns, name, remap = r.string("ns"), r.string("name"), r.u8("remap")
            r.end()
            return w.string(self._resolve(ns, name, bool(remap))).payload()
        if kind == P.ADVERTISE:
            ns, topic, type_, md5 = r.string("ns"), r.string("topic"), r.string("type"), r.string("md5")
            _definition, queue, latch, connect = (r.string("definition"), r.u32("queue"),
                                                  r.u8("latch"), r.u8("connect"))
            r.end()
            cls = self._message_class(type_, md5)
            resolved = self._resolve(ns, topic, True)
            pid = self._new_id()
            listener = _PeerListener(self, pid) if connect else None
            pub = node.advertise(resolved, cls, queue_size=queue or None, latch=bool(latch),
                                 subscriber_listener=listener)
            self._pubs[pid] = pub
            return w.u32(pid).string(pub.resolved_name).payload()
        if kind == P.SUBSCRIBE:
            ns, topic, type_, md5, queue = (r.string("ns"), r.string("topic"), r.string("type"),
                                            r.string("md5"), r.u32("queue"))
            r.end()
            cls = self._message_class(type_, md5)
            resolved = self._resolve(ns, topic, True)
            sid = self._new_id()
            sub = node.subscribe(resolved, cls, self._message_callback(sid),
                                 queue_size=queue or None)
            self._subs[sid] = sub
            return w.u32(sid).string(sub.resolved_name).payload()
        if kind == P.ADVERTISE_SERVICE:
            ns, service, type_, md5 = r.string("ns"), r.string("service"), r.string("type"), r.string("md5")
            r.string("request type")
            r.string("response type")
            r.end()
            from ddes.services import Service

            srv = self._service_class(type_, md5)
            resolved = self._resolve(ns, service, True)
            sid = self._new_id()
            server = Service(node, resolved, srv, self._service_handler(sid), style="roscpp")
            self._services[sid] = server
            return w.u32(sid).string(server.resolved_name).payload()
        if kind == P.SERVICE_EXISTS:
            ns, service = r.string("ns"), r.string("service")
            r.end()
            entry = self.world.master.lookup_service(self._resolve(ns, service, True))
            return w.u8(1 if entry is not None else 0).payload()
        if kind in (P.NUM_SUBSCRIBERS, P.NUM_PUBLISHERS):
            eid = r.u32("id")
            r.end()
            table = self._pubs if kind == P.NUM_SUBSCRIBERS else self._subs
            entity = table.get(eid)
            return w.u32(0 if entity is None else entity.get_num_connections()).payload()
        if kind in (P.PARAM_GET, P.PARAM_SET, P.PARAM_HAS, P.PARAM_DELETE, P.PARAM_SEARCH):
            ns, key = r.string("ns"), r.string("key")
            params = self.world.master.params
            if kind == P.PARAM_SET:
                value = r.value("value")
                r.end()
                params.set_param(self._param_key(ns, key), value)
                return b""
            if kind == P.PARAM_GET:
                r.u8("cached")
                r.end()
                full = self._param_key(ns, key)
                observer = self.world.param_observer
                found = params.has_param(full)
                if observer is not None:
                    observer(node.name, full, found)
                if not found:
                    return w.u8(0).payload()
                return w.u8(1).value(params.get_param(full)).payload()
            r.end()
            if kind == P.PARAM_HAS:
                return w.u8(1 if params.has_param(self._param_key(ns, key)) else 0).payload()
            if kind == P.PARAM_DELETE:
                full = self._param_key(ns, key)
                if not params.has_param(full):
                    return w.u8(0).payload()
                params.delete_param(full)
                return w.u8(1).payload()
            found_key = self._search_param(ns, key)
            return (w.u8(0).string("") if found_key is None else w.u8(1).string(found_key)).payload()
        if kind == P.PARAM_NAMES:
            r.end()
            names = self.world.master.params.get_param_names()
            w.u32(len(names))
            for n in names:
                w.string(n)
            return w.payload()
        if kind == P.TIMER_CREATE:
            _clock, period, oneshot, autostart = (r.u8("clock"), r.i64("period"),
                                                  r.u8("oneshot"), r.u8("autostart"))
            r.end()
            tid = self._new_id()
            self._timers[tid] = [period, bool(oneshot), None]
            if autostart:
                self._timer_control(tid, 1, period)
            return w.u32(tid).payload()
        if kind == P.SPINNER:
            op, _threads = r.u8("op"), r.u32("threads")
            r.end()
            node.callbacks.set_manual(op != 0)
            return b""
        if kind == P.LOGGER_LEVEL:
            r.string("logger")
            r.u8("level")
            r.end()  # the process keeps its loggers' levels itself (rosconsole)
            return b""
        if kind == P.SHUTDOWN:
            r.end()
            node.shutdown("ros::shutdown() called")
            return b""
        raise ProtocolError(f"protocol error: {P.KINDS[kind]} is not a request")

    # -- blocking requests ----------------------------------------------------------------------
    def _blocking(self, kind: int, payload: bytes) -> tuple[int, simpy.Event]:
        node = self._need_node(kind)
        r = P.Reader(payload, P.KINDS[kind])
        req = r.u32("req")
        env = self.world.env
        down = node.spin()  # fires when the node shuts down
        if kind == P.SLEEP_UNTIL:
            clock, t_ns = r.u8("clock"), r.i64("t")
            r.end()
            if node.is_shutdown():
                return req, _fired(env, False)
            c = node.clock if clock == 0 else self.world.kernel_clock
            return req, env.any_of([c.wait_until(t_ns), down])
        if kind == P.SPIN:
            r.end()
            node.callbacks.set_manual(False)
            return req, down
        if kind == P.SPIN_ONCE:
            r.end()
            return req, node.spin_once()
        if kind == P.CALL:
            ns, service, type_, md5 = r.string("ns"), r.string("service"), r.string("type"), r.string("md5")
            data, persistent = r.blob("request"), r.u8("persistent")
            r.end()
            return req, self._call(node, ns, service, type_, md5, data, bool(persistent))
        if kind == P.WAIT_FOR_SERVICE:
            ns, service, timeout = r.string("ns"), r.string("service"), r.i64("timeout")
            r.end()
            from ddes.services import wait_for_service

            resolved = self._resolve(ns, service, True)
            ev = wait_for_service(node, resolved, None if timeout < 0 else
                                  max(timeout, 1) / 1e9)
            return req, ev
        if kind == P.WAIT_FOR_MESSAGE:
            ns, topic, type_, md5, timeout = (r.string("ns"), r.string("topic"), r.string("type"),
                                              r.string("md5"), r.i64("timeout"))
            r.end()
            cls = self._message_class(type_, md5)
            resolved = self._resolve(ns, topic, True)
            return req, node.wait_for_message(resolved, cls,
                                              None if timeout < 0 else max(timeout, 1) / 1e9)
        raise ProtocolError(f"protocol error: {P.KINDS[kind]} does not block")

    def _answer(self, kind: int, req: int, value: Any) -> None:
        w = P.Writer()
        if kind == P.SLEEP_UNTIL:
            node = self.node
            ok = not isinstance(value, Exception) and node is not None and not node.is_shutdown()
            self._reply(req, w.u8(1 if ok else 0).payload())
        elif kind in (P.SPIN, P.SPIN_ONCE):
            self._reply(req)
        elif kind == P.CALL:
            if isinstance(value, Exception):
                self._reply(req, w.u8(0).string(str(value)).payload())
            else:
                self._reply(req, w.u8(1).blob(value._serialize_to_bytes()).payload())
        elif kind == P.WAIT_FOR_SERVICE:
            self._reply(req, w.u8(0 if isinstance(value, Exception) else 1).payload())
        elif kind == P.WAIT_FOR_MESSAGE:
            if isinstance(value, Exception) or value is None:
                self._reply(req, w.u8(0).blob(b"").payload())
            else:
                self._reply(req, w.u8(1).blob(value._serialize_to_bytes()).payload())

    def _call(self, node: Node, ns: str, service: str, type_: str, md5: str, data: bytes,
              persistent: bool) -> simpy.Event:
        from ddes.services import ServiceProxy

        srv = self._service_class(type_, md5)
        resolved = self._resolve(ns, service, True)
        key = (resolved, type_, persistent)
        proxy = self._persistent.get(key) if persistent else None
        if proxy is None:
            proxy = ServiceProxy(node, resolved, srv, persistent=persistent)
            if persistent:
                self._persistent[key] = proxy
        request = _decode(srv._request_class, data, "CALL")
        return proxy.call(request)

    # -- callbacks: the world hands the process a callback ---------------------------------------
    def _callback(self, what: int, entity: int, body: bytes
                  ) -> tuple[int, bytes] | Generator[simpy.Event, Any, tuple[int, bytes] | None]:
        """Run one callback in the process: a plain result when it finished without blocking,
        else a generator the node's runner drives (it holds the spinner while it blocks)."""
        self._next_cb += 1
        cb = self._next_cb
        me = _Conversation(cb)
        self._stack.append(me)
        now, wall = self._times()
        gen = self._converse(me, cb)
        try:
            self._send(P.frame(P.CALLBACK, P.Writer().u32(cb).u8(what).u32(entity).i64(now)
                               .i64(wall).payload() + body))
            event = next(gen)
        except StopIteration as stop:
            self._pop(me)
            return stop.value if stop.value is not None else (1, b"")
        except (_ProcessEnded, _Watchdog, ProtocolError) as exc:
            self._pop(me)
            self._broken(exc)
            return (1, b"")
        return self._resume(me, gen, event)

    def _resume(self, me: _Conversation, gen: Generator[simpy.Event, Any, Any],
                event: simpy.Event) -> Generator[simpy.Event, Any, tuple[int, bytes] | None]:
        try:
            while True:
                try:
                    value = yield event
                except Exception as exc:  # noqa: BLE001 - handed on to the conversation
                    event = gen.throw(exc)
                    continue
                event = gen.send(value)
        except StopIteration as stop:
            return stop.value  # type: ignore[no-any-return]
        except (_ProcessEnded, _Watchdog, ProtocolError) as exc:
            self._broken(exc)
            return (1, b"")
        finally:
            self._pop(me)

    def _pop(self, me: _Conversation) -> None:
        if self._stack and self._stack[-1] is me:
            self._stack.pop()
        elif me in self._stack:
            self._stack.remove(me)
        top = self._stack[-1] if self._stack else None
        if top is not None and top.turn is not None and not top.turn.triggered:
            turn, top.turn = top.turn, None
            turn.succeed()

    def _broken(self, exc: BaseException) -> None:
        """The process broke off inside a callback: the main conversation ends it."""
        if isinstance(exc, _Watchdog):
            self.verdict = (f"the node did not hand back within {self.step_wall_s:g} s of wall "
                            "time inside a callback")
        elif isinstance(exc, ProtocolError):
            self.verdict = str(exc)
        if self._proc is not None:
            _kill(self._proc)

    def _message_callback(self, sid: int) -> Callable[[Any], Any]:
        def deliver(msg: Any) -> Any:
            header = getattr(msg, "_connection_header", None) or {}
            body = (P.Writer().string(header.get("callerid", "")).i64(self.world.env.now_ns)
                    .blob(msg._serialize_to_bytes()).payload())
            return self._plain(self._callback(P.CB_MESSAGE, sid, body), "subscriber")
        return deliver

    def _plain(self, result: Any, what: str) -> Any:
        if isinstance(result, tuple):
            self._check_failure(result, what)
            return None
        return self._checked(result, what)

    def _checked(self, gen: Generator[simpy.Event, Any, Any], what: str
                 ) -> Generator[simpy.Event, Any, None]:
        result = yield from gen
        if result is not None:
            self._check_failure(result, what)

    def _check_failure(self, result: tuple[int, bytes], what: str) -> None:
        ok, data = result
        if ok == 2:  # the callback threw: it leaves the blocking call below, as in roscpp
            below = self._stack[-1] if self._stack else None
            if below is not None and below.waiter is not None and not below.waiter.triggered:
                below.waiter.succeed(_INTERRUPTED)
            return
        if not ok and self.node is not None:
            self.node.logerr("Exception thrown while processing %s callback: %s", what,
                             data.decode("utf-8", "replace"))

    def _service_handler(self, sid: int) -> Callable[[Any, Any], Any]:
        def serve(request: Any, response: Any) -> Any:
            header = getattr(request, "_connection_header", None) or {}
            body = (P.Writer().string(header.get("callerid", "")).blob(request._serialize_to_bytes())
                    .payload())
            result = self._callback(P.CB_SERVICE, sid, body)
            if isinstance(result, tuple):
                return _fill(response, result)
            return _fill_later(response, result)
        return serve

    def _timer_control(self, tid: int, op: int, period: int) -> None:
        entry = self._timers.get(tid)
        node = self.node
        if entry is None or node is None:
            return
        if op == 2:
            entry[0] = period
            if entry[2] is None:
                return
            op = 1
            self._stop_timer(entry)
        if op == 0:
            self._stop_timer(entry)
            return
        if entry[2] is not None:
            return

        def fire(event: Any) -> Any:
            body = (P.Writer().i64(_ns(event._le)).i64(_ns(event._lr)).i64(_ns(event._ce))
                    .i64(_ns(event._cr)).i64(int((event.last_duration or 0.0) * 1e9)).payload())
            return self._plain(self._callback(P.CB_TIMER, tid, body), "timer")

        entry[2] = node.create_roscpp_timer(entry[0] / 1e9, fire, oneshot=entry[1])

    @staticmethod
    def _stop_timer(entry: list[Any]) -> None:
        timer = entry[2]
        if timer is not None:
            timer.shutdown()
            entry[2] = None

    # -- names, types ---------------------------------------------------------------------------
    def _need_node(self, kind: int) -> Node:
        if self.node is None:
            raise ProtocolError(f"protocol error: {P.KINDS[kind]} before HELLO")
        return self.node

    def _resolve(self, ns: str, name: str, remap: bool) -> str:
        """roscpp's ``NodeHandle::resolveName``: ``name`` in namespace ``ns``, then remapped."""
        node = self._need_node(P.RESOLVE)
        if name.startswith("~"):
            raise ROSException(
                "Using ~ names with NodeHandle methods is not allowed.  If you want to use "
                "private names with the NodeHandle interface, construct a NodeHandle using a "
                "private name as its namespace.  e.g. ros::NodeHandle nh(\"~\");  "
                f"nh.getParam(\"my_private_name\"); (name = [{name}])")
        resolver = NameResolver("x", ns or "/", node.remappings if remap else {})
        return resolver.resolve(name) if name else (ns or "/")

    def _param_key(self, ns: str, key: str) -> str:
        if key.startswith("~"):
            assert self.node is not None
            return self.node.resolve_name(key)
        return self._resolve(ns, key, True)

    def _search_param(self, ns: str, key: str) -> str | None:
        params = self.world.master.params
        if key.startswith("/"):
            return key if params.has_param(key) else None
        parts = [p for p in (ns or "/").split("/") if p]
        first = key.split("/", 1)[0]
        while True:
            base = "/" + "/".join(parts + [first]) if parts else "/" + first
            if params.has_param(base):
                return base + key[len(first):]
            if not parts:
                return None
            parts.pop()

    def _message_class(self, type_: str, md5: str) -> Any:
        cls = self.world.messages.get_message_class(type_)
        if md5 != "*" and cls._md5sum != md5:
            raise ROSException(f"message type {type_} of this node has md5sum {md5}, the "
                               f"world's has {cls._md5sum}: rebuild the node against this "
                               "world's messages (ddes catkin_make)")
        return cls

    def _service_class(self, type_: str, md5: str) -> Any:
        srv = self.world.messages.get_service_class(type_)
        if md5 != "*" and srv._md5sum != md5:
            raise ROSException(f"service type {type_} of this node has md5sum {md5}, the "
                               f"world's has {srv._md5sum}: rebuild the node against this "
                               "world's services (ddes catkin_make)")
        return srv


class _PeerListener:
    """rospy's SubscribeListener for a C++ publisher's connect/disconnect callbacks."""

    def __init__(self, host: ExternalNode, pid: int) -> None:
        self.host = host
        self.pid = pid

    def peer_subscribe(self, topic_name: str, topic_publish: Any, peer_publish: Any) -> Any:
        caller = str(getattr(peer_publish, "subscriber", ""))
        self.host._peers[(self.pid, caller)] = peer_publish
        return self.host._plain(self.host._callback(
            P.CB_PEER_SUBSCRIBED, self.pid, P.Writer().string(caller).payload()), "connect")

    def peer_unsubscribe(self, topic_name: str, num_peers: int) -> Any:
        return self.host._plain(self.host._callback(
            P.CB_PEER_UNSUBSCRIBED, self.pid, P.Writer().string("").payload()), "disconnect")


def _relay(waiter: simpy.Event) -> Callable[[simpy.Event], None]:
    """A callback handing an event's outcome on to ``waiter`` (unless that was cut short)."""
    def relay(ev: simpy.Event) -> None:
        if not waiter.triggered:
            if ev._ok:
                waiter.succeed(ev._value)
            else:
                ev.defused = True
                waiter.fail(ev._value)
    return relay


#: The value a blocking request's wait gets when a callback's exception cuts it short.
_INTERRUPTED = object()


class _ProcessEnded(Exception):
    """The process closed its end of the pipe (it exited)."""


class _Watchdog(Exception):
    """The process held the floor past the wall budget."""


def _drive(gen: Generator[simpy.Event, Any, Any], event: simpy.Event
           ) -> Generator[simpy.Event, Any, Any]:
    """Go on with ``gen`` from the event it yielded first (its first steps ran already)."""
    try:
        while True:
            try:
                value = yield event
            except Exception as exc:  # noqa: BLE001 - handed on to the conversation
                event = gen.throw(exc)
                continue
            event = gen.send(value)
    except StopIteration as stop:
        return stop.value


def _decode(cls: Any, data: bytes, what: str) -> Any:
    """A message of ``cls`` from the process's bytes; bytes that are none end the process as a
    protocol error (docs/external-nodes.md: anything malformed is its death)."""
    try:
        return cls.__new__(cls)._deserialize_from(data)
    except DdesError as exc:
        raise ProtocolError(f"protocol error: {what} of {cls._type}: {exc}") from None


def _fired(env: simpy.Environment, value: object) -> simpy.Event:
    ev = env.event()
    ev.succeed(value)
    return ev


def _ns(v: int | None) -> int:
    return -1 if v is None else int(v)


def _fill(response: Any, result: tuple[int, bytes] | None) -> bool:
    """A service handler's answer: the response's bytes filled in, True; or False."""
    if result is None:
        return False
    ok, data = result
    if ok != 1:  # 0: the handler failed; 2: it threw (the process logged it)
        return False
    try:
        response._deserialize_from(data)
    except DdesError:  # bytes that are no response of this service: the call fails
        return False
    return True


def _fill_later(response: Any, gen: Generator[simpy.Event, Any, Any]
                ) -> Generator[simpy.Event, Any, bool]:
    result = yield from gen
    return _fill(response, result)
