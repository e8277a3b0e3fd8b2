"""A script's environment beyond rospy: its own folder on ``sys.path`` and NumPy's global
generator pinned to the world (ddes.compat.scriptdir, ddes.compat.pinned_numpy), so code with
helper modules and draws runs unchanged and two runs of one seed give one digest."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

import ddes
from ddes.compat.scripts import run_script

UPSTREAM = Path(__file__).resolve().parents[3] / "shared" / "upstream"
GEN_NUMBERS = UPSTREAM / "common_tutorials" / "actionlib_tutorials" / "scripts" / "gen_numbers.py"


def _run(path: Path, seed: int = 3, until: float = 2.0, *args: str) -> tuple[list[str], str]:
    printed: list[str] = []
    world = ddes.World(seed=seed)
    world.log_output = False
    run_script(world, path, args, print_line=lambda text, _err: printed.append(text))
    world.run(until=until)
    return printed, world.digest()


@pytest.mark.skipif(not GEN_NUMBERS.is_file(), reason="no ../shared/upstream here")
def test_gen_numbers_gives_one_digest_per_seed() -> None:
    first, second, other = (_run(GEN_NUMBERS, seed)[1] for seed in (1, 1, 2))
    assert first == second != other


NUMPY = """
    import json
    import numpy as np
    import numpy.random as npr
    from numpy import random as nr
    from numpy.random import rand, RandomState
    import rospy

    rospy.init_node("drawer")
    a = [float(np.random.rand()), float(rand()), float(npr.randn()), int(nr.randint(0, 10**6))]
    np.random.seed()
    b = float(np.random.random())
    np.random.seed(4)
    seeded = float(np.random.rand())
    c = [float(RandomState().rand()), float(np.random.default_rng().random()),
         isinstance(np.random.RandomState(1), np.random.RandomState),
         isinstance(np.random.mtrand.RandomState(1), RandomState)]
    print(json.dumps({"a": a, "b": b, "seeded": seeded, "c": c}))
"""


def test_numpy_draws_are_the_worlds(tmp_path: Path) -> None:
    path = tmp_path / "drawer.py"
    path.write_text(textwrap.dedent(NUMPY))
    (first,), (second,) = _run(path)[0], _run(path)[0]
    assert first == second
    got = json.loads(first)
    assert got["seeded"] == float(np.random.RandomState(4).rand())  # a seed given is the seed
    assert got["c"][2:] == [True, True]
    other = tmp_path / "other.py"
    other.write_text(textwrap.dedent(NUMPY))
    assert json.loads(_run(other)[0][0])["a"] != got["a"]  # each script draws its own
    assert json.loads(_run(path, 4)[0][0])["a"] != got["a"]


def test_a_scripts_folder_and_its_path_hold_its_modules(tmp_path: Path) -> None:
    for folder, word in (("one", "first"), ("two", "second")):
        d = tmp_path / folder
        (d / "pkg").mkdir(parents=True)
        (d / "lib").mkdir()
        (d / "helper.py").write_text(f"import rospy\nWORD = {word!r}\n"
                                     "def name():\n    return rospy.get_name()\n")
        (d / "pkg" / "__init__.py").write_text("from .inner import VALUE\n")
        (d / "pkg" / "inner.py").write_text(f"VALUE = {word!r} + '-inner'\n")
        (d / "lib" / "extra.py").write_text("EXTRA = 'extra'\n")
        (d / "main.py").write_text(textwrap.dedent("""
            import os
            import sys

            import rospy

            import helper
            import pkg.inner
            from pkg import VALUE

            sys.path.append(os.path.join(os.path.dirname(__file__), "lib"))
            import extra

            rospy.init_node("user")
            print(helper.WORD, helper.name(), VALUE, pkg.inner.VALUE, extra.EXTRA,
                  "helper" in sys.modules, sys.path[0] == os.path.dirname(__file__))
        """))
    world = ddes.World()
    printed: list[str] = []
    for folder in ("one", "two"):
        run_script(world, tmp_path / folder / "main.py", [f"__name:={folder}"],
                   print_line=lambda text, _err: printed.append(text))
    world.run(until=1.0)
    assert printed == ["first /one first-inner first-inner extra False True",
                       "second /two second-inner second-inner extra False True"]
    import sys

    assert str(tmp_path / "one" / "lib") not in sys.path  # the script's path is its own


def _python_package(root: Path, name: str, cmake: str, setup_dir: str = "src") -> None:
    (root / "scripts").mkdir(parents=True)
    (root / "package.xml").write_text(f"<package format='2'><name>{name}</name>"
                                      "<version>0.0.0</version><description>d</description>"
                                      "<maintainer email='a@b.c'>a</maintainer>"
                                      "<license>BSD</license></package>\n")
    (root / "CMakeLists.txt").write_text(f"cmake_minimum_required(VERSION 3.0.2)\n"
                                         f"project({name})\nfind_package(catkin REQUIRED)\n"
                                         f"{cmake}\ncatkin_package()\n")
    (root / "setup.py").write_text(textwrap.dedent(f"""
        from distutils.core import setup
        from catkin_pkg.python_setup import generate_distutils_setup

        setup(**generate_distutils_setup(packages=[{name!r}], package_dir={{'': {setup_dir!r}}}))
    """))
    module = root / setup_dir / name
    module.mkdir(parents=True)
    (module / "__init__.py").write_text("")
    (module / "controller.py").write_text(textwrap.dedent("""
        import rospy
        from std_msgs.msg import String


        class Controller:
            def __init__(self):
                self.pub = rospy.Publisher("out", String, queue_size=1)
                self.where = rospy.get_name()
    """))


def test_a_catkin_python_package_imports_by_name_with_ddes_rospy(tmp_path: Path) -> None:
    """catkin_python_setup() puts a package's src/ modules on every node's path (devel's
    dist-packages): a class there that imports rospy gets ddes's rospy, with no sys.path line."""
    src = tmp_path / "ws" / "src"
    _python_package(src / "pkg_a", "pkg_a", "catkin_python_setup()")
    _python_package(src / "pkg_b", "pkg_b", "catkin_python_setup()", setup_dir="python")
    _python_package(src / "pkg_c", "pkg_c", "# catkin_python_setup()")  # not installed
    script = src / "pkg_a" / "scripts" / "node.py"
    script.write_text(textwrap.dedent("""
        import rospy
        from pkg_a.controller import Controller
        import pkg_b.controller as other

        rospy.init_node("user")
        c = Controller()
        print(c.where, type(c.pub).__module__.startswith("ddes"), other.Controller().where)
        try:
            import pkg_c.controller
        except ImportError as e:
            print("ImportError", e.name)
    """))
    world = ddes.World(package_path=[src])
    printed: list[str] = []
    run_script(world, script, [], print_line=lambda text, _err: printed.append(text))
    world.run(until=1.0)
    assert printed == ["/user True /user", "ImportError pkg_c"]
    assert world.rospack.python_folders() == (src / "pkg_a" / "src", src / "pkg_b" / "python")
