"""ddes.compat.dynamic_reconfigure: a plain rospy server script with a package's cfg/*.cfg.

A catkin package on the package path holds ``cfg/Tutorials.cfg`` and ``scripts/server.py``
(``from dynamic_reconfigure.server import Server``, ``from my_robot.cfg import
TutorialsConfig``); a client script calls ``~set_parameters``.  The ``ros`` test runs the same
``.cfg`` and callback under the real dynamic_reconfigure ``Server`` (rospy's publishers,
service and parameters patched out: no master) and compares every callback argument, the
parameters written back and the bytes of the published description, of each update and of the
service response.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import ddes
from ddes.compat.scripts import run_script
from ddes.errors import DdesValueError
from ddes.msg import get_message_class

PACKAGE_XML = """<?xml version="1.0"?>
<package format="2">
  <name>my_robot</name>
  <version>0.1.0</version>
  <description>dynamic_reconfigure in a rospy script</description>
  <maintainer email="me@example.com">me</maintainer>
  <license>BSD</license>
  <buildtool_depend>catkin</buildtool_depend>
  <depend>dynamic_reconfigure</depend>
</package>
"""

CFG = '''#!/usr/bin/env python
PACKAGE = "my_robot"

from dynamic_reconfigure.parameter_generator_catkin import *

gen = ParameterGenerator()

gen.add("int_param", int_t, 1, "An Integer parameter", 50, 0, 100)
gen.add("double_param", double_t, 2, "A double parameter", .5, 0, 1)
gen.add("str_param", str_t, 4, "A string parameter", "Hello World")
gen.add("bool_param", bool_t, 8, "A Boolean parameter", True)

size_enum = gen.enum([gen.const("Small", int_t, 0, "A small constant"),
                      gen.const("Medium", int_t, 1, "A medium constant"),
                      gen.const("Large", int_t, 2, "A large constant")],
                     "An enum to set size")
gen.add("size", int_t, 16, "A size parameter which is edited via an enum", 1, 0, 2,
        edit_method=size_enum)

exit(gen.generate(PACKAGE, "my_robot", "Tutorials"))
'''

SERVER = '''#!/usr/bin/env python3
import rospy
from dynamic_reconfigure.server import Server
from my_robot.cfg import TutorialsConfig


def callback(config, level):
    rospy.loginfo("Reconfigure Request: {int_param}, {double_param}, {str_param}, "
                  "{bool_param}, {size} (level {level})".format(level=level, **config))
    if config["int_param"] == 13:
        config["str_param"] = "unlucky"
    return config


if __name__ == "__main__":
    rospy.init_node("my_robot", anonymous=False)
    srv = Server(TutorialsConfig, callback)
    rospy.sleep(1.0)
    srv.update_configuration({"bool_param": False, "size": 2})
    rospy.spin()
'''

CLIENT = '''#!/usr/bin/env python3
import rospy
from dynamic_reconfigure.msg import Config, DoubleParameter, IntParameter, StrParameter
from dynamic_reconfigure.srv import Reconfigure

rospy.init_node("client")
rospy.wait_for_service("/my_robot/set_parameters")
set_parameters = rospy.ServiceProxy("/my_robot/set_parameters", Reconfigure)
resp = set_parameters(Config(ints=[IntParameter(name="int_param", value=13)],
                             doubles=[DoubleParameter(name="double_param", value=2.0)],
                             strs=[StrParameter(name="str_param", value="hi")]))
print("now", sorted((p.name, p.value) for p in resp.config.ints + resp.config.doubles))
'''


def _package(root: Path) -> Path:
    pkg = root / "my_robot"
    (pkg / "cfg").mkdir(parents=True)
    (pkg / "scripts").mkdir()
    (pkg / "package.xml").write_text(PACKAGE_XML, encoding="utf-8")
    (pkg / "cfg" / "Tutorials.cfg").write_text(CFG, encoding="utf-8")
    (pkg / "scripts" / "server.py").write_text(SERVER, encoding="utf-8")
    (root / "client.py").write_text(CLIENT, encoding="utf-8")
    return pkg


def _run_ddes(root: Path) -> dict[str, Any]:
    """The server and the client as script nodes; what a watcher saw."""
    pkg = _package(root)
    world = ddes.World(package_path=[root])
    world.connect_delay = 0
    logs: list[str] = []
    printed: list[str] = []
    world.log_output = lambda line, _level: logs.append(line)
    watcher = world.create_node("watcher")
    seen: dict[str, list[bytes]] = {"descriptions": [], "updates": []}
    watcher.subscribe("/my_robot/parameter_descriptions",
                      get_message_class("dynamic_reconfigure/ConfigDescription"),
                      lambda m: seen["descriptions"].append(m._serialize_to_bytes()))
    watcher.subscribe("/my_robot/parameter_updates",
                      get_message_class("dynamic_reconfigure/Config"),
                      lambda m: seen["updates"].append(m._serialize_to_bytes()))
    run_script(world, pkg / "scripts" / "server.py")
    world.run(until=0.5)
    done, _ = run_script(world, root / "client.py", print_line=lambda t, _e: printed.append(t))
    world.run(until=2.0)
    assert done.processed and done.ok
    return {"logs": logs, "printed": printed, "seen": seen,
            "params": world.params.get_param("/my_robot")}


def test_a_script_server_with_the_packages_cfg(tmp_path: Path) -> None:
    out = _run_ddes(tmp_path)
    assert out["logs"] == [
        "[INFO] [0.000000]: Reconfigure Request: 50, 0.5, Hello World, True, 1 (level -1)",
        "[INFO] [0.500300]: Reconfigure Request: 13, 1.0, hi, True, 1 (level 7)",
        "[INFO] [1.000000]: Reconfigure Request: 13, 1.0, unlucky, False, 2 (level 24)",
    ]
    assert out["printed"] == ["now [('double_param', 1.0), ('int_param', 13), ('size', 1)]"]
    assert out["params"] == {"int_param": 13, "double_param": 1.0, "str_param": "unlucky",
                             "bool_param": False, "size": 2}
    assert len(out["seen"]["descriptions"]) == 1
    assert len(out["seen"]["updates"]) == 3


def test_parameters_already_on_the_server_override_the_defaults_clamped(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    world = ddes.World(package_path=[tmp_path])
    logs: list[str] = []
    world.log_output = lambda line, _level: logs.append(line)
    world.params.set_param("/my_robot/int_param", 500)  # clamped to max, as dynamic_reconfigure
    world.params.set_param("/my_robot/str_param", "from the server")
    run_script(world, pkg / "scripts" / "server.py")
    world.run(until=0.1)
    assert logs == ["[INFO] [0.000000]: Reconfigure Request: 100, 0.5, from the server, True, 1 "
                    "(level -1)"]


def test_cfg_errors_name_the_file_and_the_type(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    script = tmp_path / "other.py"
    script.write_text("from my_robot.cfg import OtherConfig\n", encoding="utf-8")
    world = ddes.World(package_path=[tmp_path], strict=False)
    errors: list[str] = []
    done, _ = run_script(world, script, print_line=lambda t, _e: errors.append(t))
    world.run(until=0.1)
    assert not done.ok
    assert "generate TutorialsConfig" in errors[-1], errors
    (pkg / "cfg" / "Bad.cfg").write_text("gen = 1 / 0\n", encoding="utf-8")
    world = ddes.World(package_path=[tmp_path])
    from ddes.compat.dynamic_reconfigure import cfg_module

    module = cfg_module(world, "my_robot")
    assert module is not None
    with pytest.raises(DdesValueError, match=r"Bad\.cfg: the \.cfg file failed: ZeroDivision"):
        module.TutorialsConfig  # noqa: B018


REAL = r'''
import json, sys, types
import rospy
sys.argv = ["cfg", "-", "-", "-", "-"]  # the catkin generator wants its four directories
from dynamic_reconfigure import parameter_generator_catkin as pgc
from dynamic_reconfigure.encoding import extract_params
captured = []
pgc.ParameterGenerator.generate = lambda self, *a: captured.append(self) or 0
try:
    exec(compile(open(CFG).read(), CFG, "exec"), {"__name__": "__main__"})
except SystemExit:
    pass
gen = captured[0]
T = types.SimpleNamespace(config_description=gen.group.to_dict(), min={}, max={},
                          defaults={}, level={}, type={}, all_level=0)
for p in extract_params(T.config_description):
    for k in ("min", "max", "level", "type"):
        getattr(T, k)[p["name"]] = p[k]
    T.defaults[p["name"]] = p["default"]
    T.all_level |= p["level"]

published = {"descriptions": [], "updates": []}
class Pub:
    def __init__(self, name, cls, **k):
        self.key = "descriptions" if name.endswith("descriptions") else "updates"
    def publish(self, msg):
        from io import BytesIO
        b = BytesIO(); msg.serialize(b); published[self.key].append(b.getvalue().hex())
handlers = []
params = {}
def get_param(name):
    if name in params:
        return params[name]
    raise KeyError(name)
rospy.Publisher = Pub
rospy.Service = lambda name, cls, handler: handlers.append(handler)
rospy.get_param = get_param
rospy.set_param = params.__setitem__
logs = []
rospy.loginfo = lambda text: logs.append(text)
sys.modules["my_robot"] = types.ModuleType("my_robot")
sys.modules["my_robot.cfg"] = cfg = types.ModuleType("my_robot.cfg")
cfg.TutorialsConfig = T
scope = {"__name__": "server"}
exec(compile(open(SERVER).read(), SERVER, "exec"), scope)
srv = scope["Server"](T, scope["callback"])
from dynamic_reconfigure.msg import Config, DoubleParameter, IntParameter, StrParameter
from dynamic_reconfigure.srv import ReconfigureRequest
from io import BytesIO
resp = handlers[0](ReconfigureRequest(Config(ints=[IntParameter("int_param", 13)],
                                             doubles=[DoubleParameter("double_param", 2.0)],
                                             strs=[StrParameter("str_param", "hi")])))
srv.update_configuration({"bool_param": False, "size": 2})
now = "now " + str(sorted((p.name, p.value) for p in resp.ints + resp.doubles))  # the Config
print(json.dumps({"logs": logs, "published": published, "now": now,
                  "params": {k[1:]: v for k, v in params.items()}}))
'''


@pytest.mark.ros
def test_agrees_with_the_real_server(ros_python: Callable[..., Any], tmp_path: Path) -> None:
    ours = _run_ddes(tmp_path)
    pkg = tmp_path / "my_robot"
    theirs = ros_python(f"CFG = {str(pkg / 'cfg' / 'Tutorials.cfg')!r}\n"
                        f"SERVER = {str(pkg / 'scripts' / 'server.py')!r}\n" + REAL,
                        as_json=True)
    assert [line.split("]: ", 1)[1] for line in ours["logs"]] == theirs["logs"]
    assert ours["params"] == theirs["params"]
    assert [b.hex() for b in ours["seen"]["descriptions"]] == theirs["published"]["descriptions"]
    assert [b.hex() for b in ours["seen"]["updates"]] == theirs["published"]["updates"]
    assert ours["printed"] == [theirs["now"]]


def test_the_package_in_docs_rospy_md_runs_as_described(tmp_path: Path) -> None:
    import re

    doc = (Path(__file__).resolve().parents[2] / "docs" / "rospy.md").read_text(encoding="utf-8")
    section = doc.split("\n## dynamic_reconfigure\n", 1)[1].split("\n## ", 1)[0]
    cfg, server = re.findall(r"```python\n(.*?)```", section, re.S)
    pkg = tmp_path / "dynamic_tutorials"
    (pkg / "cfg").mkdir(parents=True)
    (pkg / "scripts").mkdir()
    (pkg / "package.xml").write_text(PACKAGE_XML.replace("my_robot", "dynamic_tutorials"),
                                     encoding="utf-8")
    (pkg / "cfg" / "Tutorials.cfg").write_text(cfg, encoding="utf-8")
    (pkg / "scripts" / "server.py").write_text(server, encoding="utf-8")
    (tmp_path / "client.py").write_text(CLIENT.replace("my_robot", "dynamic_tutorials"),
                                        encoding="utf-8")
    world = ddes.World(package_path=[tmp_path])
    logs: list[str] = []
    world.log_output = lambda line, _level: logs.append(line)
    run_script(world, pkg / "scripts" / "server.py")
    run_script(world, tmp_path / "client.py")
    world.run(until=1.0)
    assert [line.split("]: ", 1)[1] for line in logs] == [
        "Reconfigure Request: 50, 0.5, Hello World, True, 1",
        "Reconfigure Request: 13, 1.0, hi, True, 1"]
    assert world.params.get_param("/dynamic_tutorials/int_param") == 13
