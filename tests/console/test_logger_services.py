"""roscpp's ``~get_loggers`` and ``~set_logger_level`` on the console's roscpp nodes (issue 42,
item 3.4).

The expected texts are what real Noetic printed for ``rosservice list``, ``rosnode info`` and
``rosservice call`` against Debian's roscore and a real roscpp_tutorials talker and listener
(built with real catkin_make): the same loggers, levels and layout.  Real rospy nodes have the
two services as well; ddes's rospy nodes do not (a documented deviation).
"""

from __future__ import annotations

from typing import Any

import pytest

from ddes.console.shell import Console
from ddes.graph.world import World
from ddes.services.loggers import advertise_logger_services

ROSCPP = ["ros", "ros.roscpp", "ros.roscpp.roscpp_internal",
          "ros.roscpp.roscpp_internal.connections", "ros.roscpp.superdebug"]


def loggers_text(*rows: tuple[str, str]) -> str:
    """``rosservice call NODE/get_loggers`` as rosservice prints it."""
    return "loggers: \n" + "".join(f'  - \n    name: "{n}"\n    level: "{lv}"\n' for n, lv in rows)


def base(package: str | None = None, level: str = "info") -> list[tuple[str, str]]:
    rows = [(n, "warn" if n.endswith("superdebug") else "info") for n in ROSCPP]
    if package is not None:
        rows.append((f"ros.{package}", level))
    return rows


def test_rosservice_list_and_rosnode_info_show_them(console: Console) -> None:
    # the console is a roscore: rosout is a roscpp node
    assert console.run("rosservice list") == "/rosout/get_loggers\n/rosout/set_logger_level\n"
    console.run("rosrun --quiet roscpp_tutorials talker &")
    console.run("rosrun --quiet rospy_tutorials talker __name:=pytalker chatter:=/c2 &")
    assert console.run("rosservice list") == (
        "/rosout/get_loggers\n/rosout/set_logger_level\n"
        "/talker/get_loggers\n/talker/set_logger_level\n")  # not the rospy node's: a deviation
    assert console.run("rosservice list -n /talker") == (
        "/talker/get_loggers /talker\n/talker/set_logger_level /talker\n")
    info = console.run("rosnode info /talker")
    assert ("Subscriptions: None\n\nServices: \n * /talker/get_loggers\n"
            " * /talker/set_logger_level\n\n\ncontacting node") in info
    assert "Services: None" in console.run("rosnode info /pytalker")
    assert console.run("rosservice type /talker/get_loggers") == "roscpp/GetLoggers\n"
    assert console.run("rosservice args /talker/set_logger_level") == "logger level\n"
    assert console.run("rossrv show roscpp/SetLoggerLevel") == "string logger\nstring level\n---\n\n"


def test_get_loggers_and_set_logger_level_answer_as_roscpp(console: Console) -> None:
    console.run("rosrun --quiet roscpp_tutorials talker &")
    console.run("rosrun roscpp_tutorials listener __name:=lst chatter:=/nothing &")
    assert console.run("rosservice call /talker/get_loggers") == \
        loggers_text(*base("roscpp_tutorials"))
    # a listener that has heard nothing has logged nothing: no package logger yet
    assert console.run("rosservice call /lst/get_loggers") == loggers_text(*base())
    assert console.run("rosservice call /rosout/get_loggers") == loggers_text(*base("rosout"))

    assert console.run("rosservice call /talker/set_logger_level ros.roscpp_tutorials debug") \
        == "\n"  # the empty response
    assert console.world.lookup_node("/talker").log.level == 1  # DEBUG: the node's own level
    assert console.run("rosservice call /talker/get_loggers") == \
        loggers_text(*base("roscpp_tutorials", "debug"))
    # the level in any case; a new logger is made, as log4cxx makes it
    assert console.run("rosservice call /talker/set_logger_level ros.nope Warn") == "\n"
    rows = base("roscpp_tutorials", "debug")
    rows.insert(1, ("ros.nope", "warn"))
    assert console.run("rosservice call /talker/get_loggers") == loggers_text(*rows)


def test_an_unknown_level_fails_the_call_as_roscpp_does(console: Console) -> None:
    console.run("rosrun --quiet roscpp_tutorials talker &")
    result = console.execute("rosservice call /talker/set_logger_level ros.roscpp_tutorials loud")
    assert result.code == 2
    # roscpp logs it (ROS_ERROR) and returns false: an empty error text
    assert "]: Unknown logger level [LOUD]\n" in result.out
    assert result.err == "ERROR: service [/talker/set_logger_level] responded with an error: \n"


def test_a_level_set_on_ros_reaches_the_package_logger(console: Console) -> None:
    console.run("rosrun --quiet roscpp_tutorials talker &")
    console.run("rosservice call /talker/set_logger_level ros error")
    talker = console.world.lookup_node("/talker")
    assert talker.log.level == 8  # ERROR: ros.roscpp_tutorials has no level of its own
    text = console.run("rosservice call /talker/get_loggers")
    assert 'name: "ros.roscpp_tutorials"\n    level: "error"' in text
    assert 'name: "ros.roscpp.superdebug"\n    level: "warn"' in text  # its own level stays


def test_they_are_not_traced_and_a_nodes_own_service_takes_the_name() -> None:
    world = World(seed=0)
    node = world.create_node("n", log_style="roscpp")
    before = world.digest()
    advertise_logger_services(node)
    assert world.digest() == before  # no trace rows: digests do not depend on them
    assert sorted(world.master.services) == ["/n/get_loggers", "/n/set_logger_level"]
    Empty = world.messages.get_service_class("std_srvs/Empty")
    from ddes.services import Service

    own = Service(node, "~get_loggers", Empty, lambda _req: None)  # the node's own code wins
    assert world.master.lookup_service("/n/get_loggers").server is own


def test_only_the_consoles_worlds_have_them() -> None:
    world = World(seed=0)
    world.create_node("t", log_style="roscpp")
    assert world.master.services == {}  # a plain world, as before
    Console(world, out=lambda _line: None)  # the console gives the existing nodes theirs too
    assert "/t/get_loggers" in world.master.services


@pytest.mark.ros
def test_the_types_are_roscpps(ros_python: Any, console: Console) -> None:
    real = ros_python(
        "import json, roscpp.srv as s, roscpp.msg as m\n"
        "print(json.dumps({c._type: [c._md5sum] for c in (s.GetLoggers, s.SetLoggerLevel, s.Empty)}"
        " | {'roscpp/Logger': [m.Logger._md5sum, m.Logger._full_text]}))", as_json=True)
    messages = console.world.messages
    ours = {t: [messages.get_service_class(t)._md5sum]
            for t in ("roscpp/GetLoggers", "roscpp/SetLoggerLevel", "roscpp/Empty")}
    logger = messages.get_message_class("roscpp/Logger")
    ours["roscpp/Logger"] = [logger._md5sum, logger._full_text]
    assert ours == real
