"""No memory address reaches a digest: the same run digested in two processes gives one digest,
though its nodes log and raise with object reprs (``<X object at 0x7f…>``) and a callback is an
object whose repr holds its address."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from ddes.kernel.trace import scrub_addresses

SCENARIO = r'''
import functools, sys, weakref

import greenlet

from ddes.graph.world import World


class Thing:
    pass


class Tick:
    """A callable object as a timer's callback: its name in the log is its repr."""

    def __init__(self, forms):
        self.forms = forms

    def __call__(self, _event):
        raise ValueError(f"bad {self.forms}")


def forms():
    t = Thing()
    return {"default": repr(t), "weakref": repr(weakref.ref(t)),
            "cell": repr((lambda: t).__closure__[0]), "code": repr(forms.__code__),
            "greenlet": repr(greenlet.getcurrent()), "bound": repr(Thing().__init__),
            "partial": repr(functools.partial(forms)), "set": repr({Thing(), Thing()})}


world = World(7, wall_budget=None)
world.log_output = False
node = world.create_node("/n")
seen = forms()
for key, text in seen.items():
    node.loginfo("%s: %s", key, text)
node.create_timer(0.1, Tick(seen))
world.run(until=0.35)
logged = [ev.details["msg"] for ev in world.trace.select(kind="log")]
print(world.digest())
print(all("0x" not in text or "0x…" in text for text in logged))
'''


def _digest(hash_seed: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", SCENARIO], capture_output=True, text=True,
                         check=True, env=dict(os.environ, PYTHONHASHSEED=hash_seed))
    return out.stdout.split()


def test_the_same_run_in_two_processes_has_one_digest() -> None:
    first, second = _digest("1"), _digest("2")
    assert first == second
    assert first[1] == "True"  # every address in the logged text shown as 0x…


@pytest.mark.parametrize(("text", "shown"), [
    ("<__main__.Thing object at 0x7f1005ba5a10>", "<__main__.Thing object at 0x…>"),
    ("<weakref at 0x7f1005f26c50; to 'Thing' at 0x7f1005ba5a10>",
     "<weakref at 0x…; to 'Thing' at 0x…>"),
    ("<cell at 0x7f1005b8b610: Thing object at 0x7f1005ba5a10>",
     "<cell at 0x…: Thing object at 0x…>"),
    ('<code object f at 0x55a4247c1010, file "x.py", line 8>',
     '<code object f at 0x…, file "x.py", line 8>'),
    ("<greenlet.greenlet object at 0x7f1005bb54c0 (otid=0x55a4249d90c0) current active>",
     "<greenlet.greenlet object at 0x… (otid=0x…) current active>"),
    ("<bound method A.f of <A object at 0x7f00>>", "<bound method A.f of <A object at 0x…>>"),
    ("what 0x7f at 0xZZ", "what 0x7f at 0xZZ"),  # neither an address of a repr
    ("that 0x10", "that 0x10"),
    ("no address", "no address"),
])
def test_scrub_addresses_shows_every_repr_address_as_0x(text: str, shown: str) -> None:
    assert scrub_addresses(text) == shown


def test_a_logged_address_is_shown_as_0x_in_the_trace_rosout_and_the_line() -> None:
    from ddes.graph.world import World

    lines: list[str] = []
    world = World(0, wall_budget=None)
    world.log_output = lambda line, _level: lines.append(line)
    node = world.create_node("/n")
    got = []
    node.subscribe("/rosout", world.messages.get_message_class("rosgraph_msgs/Log"),
                   lambda m: got.append(m.msg))
    world.run(until=0.01)
    node.loginfo("made %r", object())
    world.run(until=0.02)
    assert lines == ["[INFO] [0.010000]: made <object object at 0x…>"]
    assert got == ["made <object object at 0x…>"]
    assert world.trace.select(kind="log")[0].details["msg"] == "made <object object at 0x…>"
