"""dynamic_reconfigure wired to the graph: latched topics, set_parameters, parameters."""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

import pytest

import ddes
from ddes.dynamic_reconfigure.core import ParameterGenerator, bool_t, double_t, int_t
from ddes.dynamic_reconfigure.server import DynamicReconfigureServer, config_to_message
from ddes.errors import DynamicReconfigureCallbackException
from ddes.msg import get_message_class, get_service_class
from ddes.services import ServiceProxy

Config = get_message_class("dynamic_reconfigure/Config")
ConfigDescription = get_message_class("dynamic_reconfigure/ConfigDescription")
Reconfigure = get_service_class("dynamic_reconfigure/Reconfigure")


def _type() -> Any:
    gen = ParameterGenerator()
    gen.add("gain", double_t, 1, "P gain", 1.0, 0.0, 10.0)
    gen.add("speed", int_t, 2, "speed", 5, 0, 100)
    gen.add("enabled", bool_t, 4, "on", True)
    return gen.generate("ctrl", "controller", "Controller")


def test_startup_topics_params_and_service(world: ddes.World) -> None:
    world.connect_delay = 0
    ct = _type()
    world.params.set_param("/controller/speed", 500)  # clamped to max at start-up
    node = world.create_node("controller")
    calls: list[tuple[dict[str, Any], int]] = []

    def cb(config: Any, level: int) -> Any:
        calls.append((dict(config), level))
        return config

    server = DynamicReconfigureServer(node, ct, cb)
    assert calls == [({"gain": 1.0, "speed": 100, "enabled": True}, 0xFFFFFFFF)]
    assert world.params.get_param("/controller") == {"gain": 1.0, "speed": 100, "enabled": True}

    watcher = world.create_node("watcher")
    updates: list[Any] = []
    descriptions: list[Any] = []
    watcher.subscribe("/controller/parameter_updates", Config, updates.append)
    watcher.subscribe("/controller/parameter_descriptions", ConfigDescription, descriptions.append)
    out: list[Any] = []

    def main() -> Generator[Any, Any, None]:
        proxy = ServiceProxy(watcher, "/controller/set_parameters", Reconfigure)
        resp = yield proxy.call(config=config_to_message({"gain": 42.0, "enabled": False}, ct))
        out.append(resp.config)

    watcher.process(main())
    world.run(until=1)
    assert calls[-1] == ({"gain": 10.0, "speed": 100, "enabled": False}, 1 | 4)
    assert [(p.name, p.value) for p in out[0].doubles] == [("gain", 10.0)]
    assert [p.name for p in descriptions[0].groups[0].parameters] == ["gain", "speed", "enabled"]
    assert [(p.name, p.value) for p in updates[-1].bools] == [("enabled", False)]
    assert server.config["gain"] == 10.0
    assert "/controller/set_parameters" in world.master.services


def test_update_from_code_and_none_return(world: ddes.World) -> None:
    node = world.create_node("controller")
    results: list[int] = []

    def cb(config: Any, level: int) -> Any:
        results.append(level)
        return None if config["speed"] == 13 else config

    with pytest.raises(DynamicReconfigureCallbackException):
        DynamicReconfigureServer(world.create_node("bad"), _type(), lambda c, lv: None)
    server = DynamicReconfigureServer(node, _type(), cb)
    assert server.update_configuration({"speed": 7})["speed"] == 7
    with pytest.raises(DynamicReconfigureCallbackException):
        server.update_configuration({"speed": 13})
    assert server.config["speed"] == 7 and results[1:] == [2, 2]
    node.shutdown()
    assert "/controller/set_parameters" not in world.master.services
