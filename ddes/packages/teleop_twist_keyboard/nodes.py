"""``teleop_twist_keyboard``: keys in, geometry_msgs/Twist on ``cmd_vel`` out (the Noetic node).

``rosrun teleop_twist_keyboard teleop_twist_keyboard.py`` behaves as ros-teleop's script
(release 1.0.0, the one Noetic ships): it waits for a subscriber on ``cmd_vel`` (saying
``Waiting for subscriber to connect to /cmd_vel`` every 2.5 s), publishes a zero twist, prints
its banner and ``currently:\\tspeed 0.5\\tturn 1.0 ``, then turns each key into a twist with
upstream's key map: ``u i o / j k l / m , .`` drive and turn, the shifted keys strafe, ``t``/``b``
move along z, ``q z w x e c`` scale the speeds by 10 % (printing the ``currently`` line, and the
banner again every 15th time), anything else stops, Ctrl+C (``\\x03``) quits.  Parameters:
``~speed`` (0.5), ``~turn`` (1.0), ``~repeat_rate`` (0: publish only on a key; r > 0: also
every 1/r s), ``~key_timeout`` (0: none; t > 0: stop when no key came for t s).  On exit it
publishes a zero twist, as the script's publish thread does (after Ctrl+C on ``~keys`` it
arrives; when the node is killed, its connections close at that instant and it is lost).

Where the keys come from:

* ``~keys`` (std_msgs/String): each character is one key press, in order, when the message is
  delivered — how scripts, notebooks and tests type (``rostopic pub -1
  /teleop_twist_keyboard/keys std_msgs/String iiik``).
* the console's terminal: when standard input is a terminal (or ``_stdin:=true``), the node
  reads the keys typed there while the world runs (cbreak mode, restored when the node ends)
  and publishes them on ``~keys`` itself, so a recording of ``~keys`` replays the session.
  Run it in the foreground; Ctrl+C stops it.  ``_stdin:=false`` never reads the terminal.

Deviations: upstream's publish thread may merge updates that come faster than it wakes; here
each key publishes at once, so the same keys give the same twists on every run.
"""

from __future__ import annotations

import atexit
import os
import sys
from typing import TYPE_CHECKING, Any

from ddes.errors import DdesValueError
from ddes.kernel.events import post
from ddes.msg import get_message_class
from ddes.nodes import NodeType, print_line

if TYPE_CHECKING:
    from simpy.events import ProcessGenerator

    from ddes.graph.node import Node
    from ddes.graph.timer import Timer
    from ddes.graph.topics import Publisher

__all__ = ["BANNER", "MOVE_BINDINGS", "NODES", "SPEED_BINDINGS", "vels"]

#: Upstream's ``msg`` (printed with ``print(msg)``).
BANNER = """
Reading from the keyboard  and Publishing to Twist!
---------------------------
Moving around:
   u    i    o
   j    k    l
   m    ,    .

For Holonomic mode (strafing), hold down the shift key:
---------------------------
   U    I    O
   J    K    L
   M    <    >

t : up (+z)
b : down (-z)

anything else : stop

q/z : increase/decrease max speeds by 10%
w/x : increase/decrease only linear speed by 10%
e/c : increase/decrease only angular speed by 10%

CTRL-C to quit
"""

#: key -> (x, y, z, th), upstream's ``moveBindings``.
MOVE_BINDINGS: dict[str, tuple[int, int, int, int]] = {
    "i": (1, 0, 0, 0), "o": (1, 0, 0, -1), "j": (0, 0, 0, 1), "l": (0, 0, 0, -1),
    "u": (1, 0, 0, 1), ",": (-1, 0, 0, 0), ".": (-1, 0, 0, 1), "m": (-1, 0, 0, -1),
    "O": (1, -1, 0, 0), "I": (1, 0, 0, 0), "J": (0, 1, 0, 0), "L": (0, -1, 0, 0),
    "U": (1, 1, 0, 0), "<": (-1, 0, 0, 0), ">": (-1, -1, 0, 0), "M": (-1, 1, 0, 0),
    "t": (0, 0, 1, 0), "b": (0, 0, -1, 0),
}

#: key -> (speed factor, turn factor), upstream's ``speedBindings``.
SPEED_BINDINGS: dict[str, tuple[float, float]] = {
    "q": (1.1, 1.1), "z": (0.9, 0.9), "w": (1.1, 1), "x": (0.9, 1), "e": (1, 1.1), "c": (1, 0.9),
}

_TTY_POLL_NS = 20_000_000  # how often (kernel time) the terminal is read while the world runs


def vels(speed: Any, turn: Any) -> str:
    """Upstream's status line (with its trailing space)."""
    return "currently:\tspeed %s\tturn %s " % (speed, turn)  # noqa: UP031 - upstream's format


def _number(node: Node, name: str, default: float) -> Any:
    value: Any = node.get_param("~" + name, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DdesValueError(f"{node.name}: parameter ~{name} must be a number, got {value!r}")
    return value


class _Teleop:
    """The script's state and its publish thread, driven by key presses and timers."""

    def __init__(self, node: Node, pub: Publisher[Any], speed: Any, turn: Any, repeat: float,
                 key_timeout: float | None) -> None:
        self.node = node
        self.pub = pub
        self.twist = get_message_class("geometry_msgs/Twist")
        self.speed, self.turn = speed, turn
        self.x = self.y = self.z = self.th = 0
        self.status = 0
        self.period = 1.0 / repeat if repeat else None
        self.key_timeout = key_timeout
        self.ready = False
        self._stopped = False
        self.pending: list[str] = []
        self._repeat_timer: Timer | None = None
        self._key_timer: Timer | None = None
        self._tty: Any = None  # the terminal's saved attributes while in cbreak mode
        self._fd = -1

    # -- the publish thread ---------------------------------------------------------------
    def publish(self, x: Any, y: Any, z: Any, th: Any) -> None:
        t = self.twist()
        t.linear.x = x * self.speed
        t.linear.y = y * self.speed
        t.linear.z = z * self.speed
        t.angular.z = th * self.turn
        self.pub.publish(t)

    def update(self) -> None:
        """``pub_thread.update(...)``: publish now, then every repeat period until the next."""
        self.publish(self.x, self.y, self.z, self.th)
        if self.period is not None:
            if self._repeat_timer is not None:
                self._repeat_timer.shutdown()
            self._repeat_timer = self.node.create_timer(self.period, self._repeat)

    def _repeat(self, _event: object) -> None:
        self.publish(self.x, self.y, self.z, self.th)

    # -- the main loop --------------------------------------------------------------------
    def start(self) -> None:
        self.ready = True
        self.update()
        print_line(self.node, BANNER)
        print_line(self.node, vels(self.speed, self.turn))
        keys, self.pending = self.pending, []
        for key in keys:
            self.key(key)
        self._arm_key_timeout()

    def on_keys(self, msg: Any) -> None:
        for key in str(msg.data):
            if self.node.is_shutdown() or self._stopped:
                return
            if self.ready:
                self.key(key)
            else:
                self.pending.append(key)
        if self.ready and not self._stopped:
            self._arm_key_timeout()

    def _arm_key_timeout(self) -> None:
        if self.key_timeout is None or self.node.is_shutdown():
            return
        if self._key_timer is not None:
            self._key_timer.shutdown()
        self._key_timer = self.node.create_timer(self.key_timeout, self._no_key, oneshot=True)

    def _no_key(self, _event: object) -> None:
        self._key_timer = None
        self.key("")  # getKey timed out; a stopped robot stays as it is, without a publish

    def key(self, key: str) -> None:
        """One pass of the script's ``while`` loop with ``key`` read."""
        if key in MOVE_BINDINGS:
            self.x, self.y, self.z, self.th = MOVE_BINDINGS[key]
        elif key in SPEED_BINDINGS:
            fs, ft = SPEED_BINDINGS[key]
            self.speed = self.speed * fs
            self.turn = self.turn * ft
            print_line(self.node, vels(self.speed, self.turn))
            if self.status == 14:
                print_line(self.node, BANNER)
            self.status = (self.status + 1) % 15
        else:
            if key == "" and self.x == 0 and self.y == 0 and self.z == 0 and self.th == 0:
                return
            self.x = self.y = self.z = self.th = 0
            if key == "\x03":  # break; finally: pub_thread.stop() publishes the stop twist
                self.stop()
                return
        self.update()

    # -- the terminal ---------------------------------------------------------------------
    def read_terminal(self, keys_pub: Publisher[Any]) -> None:
        """Poll standard input while the world runs; what was typed goes out on ``~keys``."""
        import select
        import termios
        import tty

        fd = self._fd = sys.stdin.fileno()
        try:
            self._tty = termios.tcgetattr(fd)
            tty.setcbreak(fd)
        except termios.error:
            self._tty = None
        else:
            atexit.register(self._restore_terminal)  # a process that ends with the node alive
        string = get_message_class("std_msgs/String")
        env = self.node.world.env

        def poll(_ev: object) -> None:
            if self.node.is_shutdown():
                return
            if select.select([fd], [], [], 0)[0]:
                text = os.read(fd, 256).decode("utf-8", "replace")
                if text:
                    keys_pub.publish(string(data=text))
            post(env, _TTY_POLL_NS, None, poll)

        post(env, _TTY_POLL_NS, None, poll)

    def stop(self) -> None:
        """Ctrl-C: the stop twist, then the script ends (once that twist is on its way: the
        node's connections close when it ends, and what they still carry is lost)."""
        self.ready = False
        self._stopped = True
        if self._repeat_timer is not None:
            self._repeat_timer.shutdown()
        if self._key_timer is not None:
            self._key_timer.shutdown()
        self.publish(0, 0, 0, 0)
        node = self.node
        post(node.world.env, 0, None, lambda _ev: node.signal_shutdown("Ctrl-C"))

    def _restore_terminal(self) -> None:
        if self._tty is not None:
            import termios

            saved, self._tty = self._tty, None
            atexit.unregister(self._restore_terminal)
            try:
                termios.tcsetattr(self._fd, termios.TCSADRAIN, saved)
            except (termios.error, ValueError, OSError):
                pass  # standard input closed or replaced meanwhile

    def shutdown(self) -> None:
        """An entity of the node: on exit, the publish thread's stop twist; the terminal back."""
        self._restore_terminal()
        if self.ready:
            self.ready = False
            self.publish(0, 0, 0, 0)


def teleop_twist_keyboard(node: Node) -> ProcessGenerator:
    """The script's main: parameters, wait for a subscriber, banner, then keys until Ctrl-C."""
    speed = _number(node, "speed", 0.5)
    turn = _number(node, "turn", 1.0)
    repeat = float(_number(node, "repeat_rate", 0.0))
    key_timeout = float(_number(node, "key_timeout", 0.0)) or None
    if repeat < 0 or (key_timeout is not None and key_timeout < 0):
        raise DdesValueError(f"{node.name}: ~repeat_rate and ~key_timeout must be >= 0 (0: off)")
    stdin: Any = node.get_param("~stdin", "auto")
    if stdin == "auto":
        stdin = sys.stdin is not None and sys.stdin.isatty()
    pub = node.advertise("cmd_vel", get_message_class("geometry_msgs/Twist"), queue_size=1)
    state = _Teleop(node, pub, speed, turn, repeat, key_timeout)
    string = get_message_class("std_msgs/String")
    node.subscribe("~keys", string, state.on_keys, queue_size=100)
    node.add_entity(state)  # after the publisher: it shuts down first, so the stop goes out
    if stdin is True or str(stdin).lower() in ("true", "1"):
        state.read_terminal(node.advertise("~keys", string, queue_size=100))
    i = 0
    while not node.is_shutdown() and pub.get_num_connections() == 0:
        if i == 4:
            print_line(node, f"Waiting for subscriber to connect to {pub.resolved_name}")
        yield node.sleep(0.5)
        i = (i + 1) % 5
    if node.is_shutdown():
        return 0
    state.start()
    yield node.spin()
    return 0


NODES = {
    "teleop_twist_keyboard.py": NodeType(
        teleop_twist_keyboard, name="teleop_twist_keyboard",
        doc="keys (terminal or ~keys, std_msgs/String) -> geometry_msgs/Twist on cmd_vel"),
}
