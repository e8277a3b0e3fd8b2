"""``ddes catkin_make`` (and ``catkin build``): workspaces configured with the system's CMake on
ddes's catkin, built with make into devel/ (docs/roscpp.md, "Building with catkin").

Most builds here use packages whose nodes need only message headers and ddes's runtime headers,
or a stand-in for ddes's roscpp library (``-DDDES_ROSCPP_SOURCE_DIR``): they test the build
machinery whether or not the library is complete.  The builds of roscpp_tutorials' unchanged
sources need the library (ddes/roscpp/cpp/CMakeLists.txt) and skip without it.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

import ddes
from ddes.roscpp import catkin
from ddes.roscpp.catkin import (
    CatkinError,
    bounded_make_args,
    catkin_make,
    catkin_tool,
    find_packages,
    topological_order,
)

UPSTREAM = Path(__file__).resolve().parents[3] / "shared" / "upstream"
ROSCPP_TUTORIALS = UPSTREAM / "ros_tutorials" / "roscpp_tutorials"
LIBRARY = catkin.LIBRARY_SOURCE_DIR

needs_tools = pytest.mark.skipif(
    not (shutil.which("cmake") and shutil.which("make") and shutil.which("c++")),
    reason="needs cmake, make and a C++ compiler")
needs_library = pytest.mark.skipif(
    not (LIBRARY / "CMakeLists.txt").is_file(),
    reason="ddes's roscpp library (ddes/roscpp/cpp/CMakeLists.txt) is not there yet")
needs_tutorials = pytest.mark.skipif(not ROSCPP_TUTORIALS.is_dir(),
                                     reason="upstream roscpp_tutorials not available")


@pytest.fixture(autouse=True)
def _library_cache(tmp_path_factory: pytest.TempPathFactory,
                   monkeypatch: pytest.MonkeyPatch) -> None:
    """ddes's roscpp is built once for the whole test run (both xdist workers share it), not
    into the user's ~/.cache."""
    base = tmp_path_factory.getbasetemp()
    if base.name.startswith("popen-gw"):
        base = base.parent
    monkeypatch.setenv("DDES_CACHE_DIR", str(base / "ddes-cache"))


# -- workspaces ------------------------------------------------------------------------------------
def _package_xml(name: str, depends: list[str]) -> str:
    deps = "".join(f"  <depend>{d}</depend>\n" for d in depends)
    return (f'<?xml version="1.0"?>\n<package format="2">\n  <name>{name}</name>\n'
            "  <version>0.0.1</version>\n  <description>test</description>\n"
            '  <maintainer email="t@example.org">t</maintainer>\n  <license>BSD</license>\n'
            f"  <buildtool_depend>catkin</buildtool_depend>\n{deps}</package>\n")


def _write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


#: A package with its own message and service, used from its node (no library needed).
CHATTER_CMAKE = """\
cmake_minimum_required(VERSION 3.0.2)
project(chatter)
add_compile_options(-std=c++11)
find_package(catkin REQUIRED COMPONENTS std_msgs geometry_msgs message_generation)
add_message_files(FILES Num.msg)
add_service_files(FILES AddTwoInts.srv)
generate_messages(DEPENDENCIES std_msgs geometry_msgs)
catkin_package(CATKIN_DEPENDS message_runtime std_msgs)
include_directories(${catkin_INCLUDE_DIRS})
add_executable(use_msgs src/use_msgs.cpp)
add_dependencies(use_msgs ${${PROJECT_NAME}_EXPORTED_TARGETS} ${catkin_EXPORTED_TARGETS})
target_link_libraries(use_msgs ${catkin_LIBRARIES})
add_executable(old_std src/old_std.cpp)
install(TARGETS use_msgs RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
"""

USE_MSGS = """\
#include <chatter/Num.h>
#include <chatter/AddTwoInts.h>
#include <std_msgs/String.h>
#include <cstdio>

int main() {
  chatter::Num n;
  n.num = 42;
  n.where.x = 1.5;
  chatter::AddTwoInts srv;
  srv.request.a = 1;
  srv.request.b = 2;
  std_msgs::String s;
  s.data = "hi";
  std::printf("%s num=%lld len=%u sum_md5=%s %s\\n", ROS_PACKAGE_NAME, (long long)n.num,
              (unsigned)ros::serialization::serializationLength(n),
              ros::service_traits::md5sum(srv), s.data.c_str());
  return 0;
}
"""

OLD_STD = """\
#include <cstdio>
int main() { std::printf("%ld\\n", (long)__cplusplus); return 0; }
"""


def chatter_workspace(root: Path) -> Path:
    pkg = root / "src" / "chatter"
    _write(pkg / "package.xml", _package_xml("chatter", ["std_msgs", "geometry_msgs",
                                                         "message_generation",
                                                         "message_runtime"]))
    _write(pkg / "CMakeLists.txt", CHATTER_CMAKE)
    _write(pkg / "msg" / "Num.msg", "Header header\nint64 num\ngeometry_msgs/Point where\n")
    _write(pkg / "srv" / "AddTwoInts.srv", "int64 a\nint64 b\n---\nint64 sum\n")
    _write(pkg / "src" / "use_msgs.cpp", USE_MSGS)
    _write(pkg / "src" / "old_std.cpp", OLD_STD)
    return root


#: A stand-in for ddes's roscpp library (its CMakeLists builds static library ddes_roscpp).
STUB_CMAKE = """\
cmake_minimum_required(VERSION 3.16)
project(ddes_roscpp_stub CXX)
add_library(ddes_roscpp STATIC src/stub.cpp)
target_include_directories(ddes_roscpp PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}/include")
"""


def stub_library(root: Path) -> Path:
    _write(root / "CMakeLists.txt", STUB_CMAKE)
    _write(root / "include" / "ddes_stub.h",
           "#pragma once\nnamespace ddes_stub { const char* hello(); }\n")
    _write(root / "src" / "stub.cpp",
           '#include "ddes_stub.h"\nconst char* ddes_stub::hello() { return "stub"; }\n')
    # ddes's runtime headers, as the real library's include/ holds them
    shutil.copytree(LIBRARY / "include", root / "include", dirs_exist_ok=True)
    return root


def talker_package(src: Path, name: str = "stub_talker") -> Path:
    pkg = src / name
    _write(pkg / "package.xml", _package_xml(name, ["roscpp", "std_msgs"]))
    _write(pkg / "CMakeLists.txt", f"""\
cmake_minimum_required(VERSION 3.0.2)
project({name})
find_package(catkin REQUIRED COMPONENTS roscpp std_msgs)
catkin_package()
include_directories(${{catkin_INCLUDE_DIRS}})
add_executable({name}_talker src/talker.cpp)
target_link_libraries({name}_talker ${{catkin_LIBRARIES}})
""")
    _write(pkg / "src" / "talker.cpp", """\
#include <ddes_stub.h>
#include <std_msgs/String.h>
#include <cstdio>
int main() {
  std_msgs::String msg;
  msg.data = ddes_stub::hello();
  std::printf("%s says %s\\n", ROS_PACKAGE_NAME, msg.data.c_str());
  return 0;
}
""")
    return pkg


class Run:
    """One catkin_make run: exit code, the lines it printed (stdout, stderr) and its time."""

    def __init__(self, ws: Path, *args: str, tool: str = "catkin_make",
                 environ: dict[str, str] | None = None) -> None:
        self.out: list[str] = []
        self.err: list[str] = []
        start = time.monotonic()
        fn = catkin_make if tool == "catkin_make" else catkin_tool
        self.code = fn(list(args), cwd=ws, out=self.out.append, err=self.err.append,
                       environ=environ)
        self.seconds = time.monotonic() - start
        self.text = "\n".join(self.out + self.err)

    def __repr__(self) -> str:
        return f"<Run code={self.code} {self.seconds:.1f}s>\n{self.text[-6000:]}"


def _later(path: Path, ws: Path) -> None:
    """Make ``path`` newer than everything else in ``ws`` without sleeping.

    Every file of the workspace is moved ten seconds into the past and ``path`` stamped now, so
    whatever the next build writes is newer than ``path`` (a stamp in the future would make the
    build's own outputs look older than their source and rebuild them again on the run after)."""
    for root, _dirs, files in os.walk(ws):
        for name in files:
            f = Path(root) / name
            if not f.is_symlink():
                st = f.stat()
                os.utime(f, ns=(st.st_atime_ns - 10**10, st.st_mtime_ns - 10**10))
    os.utime(path)


# -- pure Python: packages, order, arguments -------------------------------------------------------
def test_packages_are_found_by_package_xml_and_ordered_by_dependencies(tmp_path: Path) -> None:
    src = tmp_path / "src"
    _write(src / "zeta" / "package.xml", _package_xml("zeta", ["roscpp"]))
    _write(src / "group" / "b_pkg" / "package.xml", _package_xml("b_pkg", ["zeta"]))
    _write(src / "a_pkg" / "package.xml", _package_xml("a_pkg", ["b_pkg"]))
    _write(src / "ignored" / "CATKIN_IGNORE", "")
    _write(src / "ignored" / "x" / "package.xml", _package_xml("x", []))
    _write(src / "zeta" / "inner" / "package.xml", _package_xml("inner", []))  # inside a package
    found = find_packages(src)
    assert [p.relpath for p in found] == ["a_pkg", "group/b_pkg", "zeta"]
    assert [p.name for p in topological_order(found)] == ["zeta", "b_pkg", "a_pkg"]


def test_a_dependency_cycle_and_duplicate_names_are_refused(tmp_path: Path) -> None:
    src = tmp_path / "src"
    _write(src / "a" / "package.xml", _package_xml("a", ["b"]))
    _write(src / "b" / "package.xml", _package_xml("b", ["a"]))
    with pytest.raises(CatkinError, match=r"circular dependency .*a -> b -> a"):
        topological_order(find_packages(src))
    _write(src / "c" / "package.xml", _package_xml("a", []))
    with pytest.raises(CatkinError, match='Multiple packages found with the same name "a"'):
        find_packages(src)


def test_make_jobs_are_bounded_by_the_cpus() -> None:
    assert bounded_make_args([], 2) == (["-j2", "-l2"], [])
    assert bounded_make_args(["-j1", "install"], 4) == (["install", "-j1"], [])
    args, notes = bounded_make_args(["-j", "64", "-l", "3"], 2)
    assert args == ["-j2", "-l3"] and "bounded to this machine's 2 CPUs" in notes[0]
    args, notes = bounded_make_args(["-j"], 2)  # make's "no limit"
    assert args == ["-j2"] and "no limit" in notes[0]


def test_missing_tools_are_named_with_the_fix(tmp_path: Path) -> None:
    (tmp_path / "src").mkdir()
    run = Run(tmp_path, environ={"PATH": str(tmp_path / "nothing")})
    assert run.code == 1
    if not (Path(sys.executable).parent / "cmake").exists():  # pip's cmake would be found there
        assert run.err == ["cmake not found: install it (pip install cmake, or apt install "
                           "cmake)"]
    cmake = shutil.which("cmake")
    make = shutil.which("make")
    if cmake and make:
        bin_dir = tmp_path / "bin"
        bin_dir.mkdir()
        for tool in (cmake, make):
            (bin_dir / Path(tool).name).symlink_to(tool)
        run = Run(tmp_path, environ={"PATH": str(bin_dir), "CXX": "/no/such/c++"})
        assert run.code == 1
        assert run.err[-1] == "no C++ compiler found: install g++ (apt install g++)"


def test_catkin_make_checks_the_workspace_as_catkin_make_does(tmp_path: Path) -> None:
    run = Run(tmp_path)
    assert run.code == 1
    assert run.out == [f"Base path: {tmp_path}"]
    assert run.err == [f'The specified source space "{tmp_path / "src"}" does not exist']
    _write(tmp_path / "package.xml", _package_xml("oops", []))
    run = Run(tmp_path)
    assert run.code == 1 and "must be invoked in the root of workspace" in run.err[0]


def test_the_ddes_command_and_the_console_offer_catkin_make(tmp_path: Path,
                                                            capsys: pytest.CaptureFixture[str]
                                                            ) -> None:
    from ddes.cli.main import main

    assert main(["catkin_make", "-C", str(tmp_path)]) == 1
    captured = capsys.readouterr()
    assert f"Base path: {tmp_path}" in captured.out
    assert "does not exist" in captured.err
    from ddes.console.tooling import ToolContext, run_command_result

    ctx = ToolContext(ddes.World(seed=0), cwd=str(tmp_path))
    res = run_command_result(ctx, "catkin_make")
    assert res.code == 1 and f"Base path: {tmp_path}" in res.out and "does not exist" in res.err
    res = run_command_result(ctx, "catkin build")
    assert res.code == 1 and "Unable to find a catkin workspace" in res.err


# -- builds ----------------------------------------------------------------------------------------
@needs_tools
def test_a_package_with_its_own_messages_builds_then_rebuilds_incrementally(
        tmp_path: Path) -> None:
    ws = chatter_workspace(tmp_path / "ws")
    clean = Run(ws, "-j2")
    assert clean.code == 0, clean
    for line in (f"Base path: {ws}", f"Source space: {ws / 'src'}",
                 f"Build space: {ws / 'build'}", f"Devel space: {ws / 'devel'}",
                 f"Install space: {ws / 'install'}"):
        assert line in clean.out
    assert any(line.startswith('#### Running command: "cmake ') for line in clean.out)
    assert f'#### Running command: "make -j2" in "{ws / "build"}"' in clean.out
    assert "-- +++ processing catkin package: 'chatter'" in clean.out
    assert not any("building ddes's roscpp" in line for line in clean.out)  # no library needed
    # the layout of catkin's devel space
    exe = ws / "devel" / "lib" / "chatter" / "use_msgs"
    for header in ("Num.h", "AddTwoInts.h", "AddTwoIntsRequest.h", "AddTwoIntsResponse.h"):
        assert (ws / "devel" / "include" / "chatter" / header).is_file()
    assert (ws / "build" / "ddes_gencpp" / "include" / "geometry_msgs" / "Point.h").is_file()
    assert not (ws / "devel" / "include" / "std_msgs").exists()
    shown = subprocess.run([exe], capture_output=True, text=True, check=True).stdout
    md5 = ddes.msg.get_service_class("rospy_tutorials/AddTwoInts")._md5sum
    # Header (seq, stamp, empty frame_id) 16 + int64 8 + Point 24
    assert shown == f"chatter num=42 len=48 sum_md5={md5} hi\n"
    # a package's add_compile_options(-std=c++11) decides for its sources (headers included)
    old = ws / "devel" / "lib" / "chatter" / "old_std"
    assert subprocess.run([old], capture_output=True, text=True).stdout == "201103\n"
    setup = subprocess.run(["bash", "-c", f". {ws}/devel/setup.bash && echo $DDES_PACKAGE_PATH "
                            "$ROS_PACKAGE_PATH"], capture_output=True, text=True,
                           env={"PATH": os.environ["PATH"]})
    assert setup.stdout.split() == [str(ws / "src")] * 2

    again = Run(ws)
    assert again.code == 0, again
    assert not any(line.startswith("#### Running command: \"cmake") for line in again.out)
    assert not any("Building CXX" in line or "Generating" in line or "Linking" in line
                   for line in again.out), again
    assert f'#### Running command: "make -j{catkin._cpu_count()} -l{catkin._cpu_count()}" in ' \
           f'"{ws / "build"}"' in again.out
    print(f"clean build {clean.seconds:.1f} s, nothing changed {again.seconds:.1f} s")
    assert again.seconds < 30

    _later(ws / "src" / "chatter" / "src" / "use_msgs.cpp", ws)
    touched = Run(ws)
    assert touched.code == 0, touched
    compiled = [line for line in touched.out if "Building CXX object" in line]
    assert len(compiled) == 1 and "use_msgs.cpp.o" in compiled[0]
    # an unchanged definition regenerates nothing a compiler sees
    _later(ws / "src" / "chatter" / "msg" / "Num.msg", ws)
    regen = Run(ws)
    assert regen.code == 0 and not any("Building CXX" in line for line in regen.out), regen

    # catkin build: the same build space, package by package
    built = Run(ws, "build", tool="catkin")
    assert built.code == 0, built
    assert "Starting  >>> chatter" in built.out
    assert any(line.startswith("Finished  <<< chatter") for line in built.out)
    assert "[build] Summary: All 1 packages succeeded!" in built.out


@needs_tools
def test_a_compile_error_shows_the_compilers_file_and_line(tmp_path: Path) -> None:
    ws = chatter_workspace(tmp_path / "ws")
    source = ws / "src" / "chatter" / "src" / "use_msgs.cpp"
    source.write_text(USE_MSGS.replace("n.num = 42;", "n.num = 42"), encoding="utf-8")
    run = Run(ws)
    assert run.code == 1
    assert re.search(rf"^{re.escape(str(source))}:8:\d+: error: expected .;. before",
                     "\n".join(run.out), re.M), run
    assert re.fullmatch(r'Invoking "make -j\d+ -l\d+" failed', run.err[-1]), run
    built = Run(ws, "build", tool="catkin")
    assert built.code == 1
    assert "Errors     << chatter:make" in built.out
    assert any(line.startswith("Failed     << chatter:make") for line in built.out)
    assert "[build] Summary: 0 of 1 packages succeeded." in built.out


@needs_tools
def test_an_unknown_component_stops_cmake_naming_it(tmp_path: Path) -> None:
    ws = chatter_workspace(tmp_path / "ws")
    lists = ws / "src" / "chatter" / "CMakeLists.txt"
    lists.write_text(CHATTER_CMAKE.replace("message_generation)", "message_generation nav_msgz)"),
                     encoding="utf-8")
    run = Run(ws)
    assert run.code == 1
    text = " ".join(" ".join(run.out).split())
    assert "unknown component 'nav_msgz'" in text
    assert "remove 'nav_msgz' from the components" in text
    assert run.err == ['Invoking "cmake" failed']


@needs_tools
def test_a_message_using_an_undeclared_package_is_refused(tmp_path: Path) -> None:
    ws = chatter_workspace(tmp_path / "ws")
    lists = ws / "src" / "chatter" / "CMakeLists.txt"
    lists.write_text(CHATTER_CMAKE.replace("DEPENDENCIES std_msgs geometry_msgs",
                                           "DEPENDENCIES std_msgs"), encoding="utf-8")
    run = Run(ws)
    assert run.code == 1
    text = " ".join(" ".join(run.out).split())
    assert "chatter/Num uses geometry_msgs/Point, but 'geometry_msgs' is not in " \
           "generate_messages(DEPENDENCIES std_msgs)" in text


@needs_tools
def test_a_package_uses_the_messages_and_actions_of_another(tmp_path: Path) -> None:
    ws = tmp_path / "ws"
    a = ws / "src" / "a_msgs"
    _write(a / "package.xml", _package_xml("a_msgs", ["std_msgs", "actionlib_msgs",
                                                      "message_generation"]))
    _write(a / "CMakeLists.txt", """\
cmake_minimum_required(VERSION 3.0.2)
project(a_msgs)
find_package(catkin REQUIRED COMPONENTS std_msgs actionlib_msgs message_generation)
add_message_files()
add_action_files(DIRECTORY action FILES Count.action)
generate_messages(DEPENDENCIES std_msgs actionlib_msgs)
catkin_package(CATKIN_DEPENDS std_msgs actionlib_msgs)
""")
    _write(a / "msg" / "Pair.msg", "string name\nint32 value\n")
    _write(a / "action" / "Count.action", "int32 to\n---\nint32 reached\n---\nint32 now\n")
    b = ws / "src" / "b_node"
    _write(b / "package.xml", _package_xml("b_node", ["a_msgs"]))
    _write(b / "CMakeLists.txt", """\
cmake_minimum_required(VERSION 3.0.2)
project(b_node)
find_package(catkin REQUIRED COMPONENTS a_msgs)
catkin_package()
include_directories(${catkin_INCLUDE_DIRS})
add_executable(count src/count.cpp)
add_dependencies(count ${catkin_EXPORTED_TARGETS})
""")
    _write(b / "src" / "count.cpp", """\
#include <a_msgs/Pair.h>
#include <a_msgs/CountAction.h>
#include <cstdio>
int main() {
  a_msgs::Pair p;
  p.name = "x";
  a_msgs::CountGoal goal;
  goal.to = 3;
  a_msgs::CountActionGoal action_goal;
  action_goal.goal = goal;
  std::printf("%s %d %s\\n", p.name.c_str(), (int)action_goal.goal.to,
              ros::message_traits::datatype(action_goal));
  return 0;
}
""")
    run = Run(ws)
    assert run.code == 0, run
    order = [line for line in run.out if line.startswith("-- ~~  - ")]
    assert order == ["-- ~~  - a_msgs", "-- ~~  - b_node"]
    headers = sorted(p.name for p in (ws / "devel" / "include" / "a_msgs").iterdir())
    assert headers == sorted(["Pair.h"] + [f"Count{s}.h" for s in (
        "Action", "ActionGoal", "ActionResult", "ActionFeedback", "Goal", "Result", "Feedback")])
    out = subprocess.run([ws / "devel" / "lib" / "b_node" / "count"], capture_output=True,
                         text=True, check=True).stdout
    assert out == "x 3 a_msgs/CountActionGoal\n"
    # the dependency forgotten in package.xml: b_node would be configured first
    _write(b / "package.xml", _package_xml("b_node", []))
    _write(a / "package.xml", _package_xml("a_msgs", ["std_msgs", "actionlib_msgs",
                                                      "message_generation", "zzz"]))
    _write(ws / "src" / "zzz" / "package.xml", _package_xml("zzz", ["b_node"]))
    _write(ws / "src" / "zzz" / "CMakeLists.txt", "project(zzz)\n")
    run = Run(ws)
    assert run.code == 1
    text = " ".join(" ".join(run.out).split())
    assert "asks for 'a_msgs', a package of this workspace that is configured after it: add " \
           "<depend>a_msgs</depend> to the package.xml of 'b_node'" in text, run


@needs_tools
def test_the_library_is_built_once_and_linked_through_catkin_libraries(tmp_path: Path) -> None:
    stub = stub_library(tmp_path / "stub")
    ws = tmp_path / "ws"
    talker_package(ws / "src", "talker_a")
    talker_package(ws / "src", "talker_b")
    run = Run(ws, f"-DDDES_ROSCPP_SOURCE_DIR={stub}")
    assert run.code == 0, run
    assert sum("Linking CXX static library libddes_roscpp.a" in line for line in run.out) == 1
    for name in ("talker_a", "talker_b"):
        exe = ws / "devel" / "lib" / name / f"{name}_talker"
        out = subprocess.run([exe], capture_output=True, text=True, check=True).stdout
        assert out == f"{name} says stub\n"
    # --pkg runs make in that package's build folder only
    again = Run(ws, f"-DDDES_ROSCPP_SOURCE_DIR={stub}", "--pkg", "talker_b")
    assert again.code == 0, again
    assert any(line.startswith("#### Running command: \"make ") and
               line.endswith(f'in "{ws / "build" / "talker_b"}"') for line in again.out), again


@needs_tools
def test_a_build_past_its_time_limit_is_stopped(tmp_path: Path) -> None:
    ws = chatter_workspace(tmp_path / "ws")
    run = Run(ws, "--timeout", "0.2")
    assert run.code == 1
    assert run.err[-1].startswith("catkin_make: stopped: the build ran past its time limit of "
                                  "0.2 s")
    assert run.seconds < 30


# -- roscpp_tutorials, unchanged (needs ddes's roscpp library) --------------------------------------
def _tutorials_workspace(root: Path, only: list[str] | None = None) -> Path:
    pkg = root / "src" / "roscpp_tutorials"
    shutil.copytree(ROSCPP_TUTORIALS, pkg)
    if only is not None:  # one node: the package's CMakeLists cut down to its talker
        text = (ROSCPP_TUTORIALS / "CMakeLists.txt").read_text(encoding="utf-8")
        start = text.index("foreach(dir")
        end = text.index("endforeach()") + len("endforeach()")
        loop = "foreach(dir " + " ".join(only) + ")\n  rostutorial(${dir})\nendforeach()"
        tail = text[end:]
        tail = tail[:tail.index("add_executable(time_api_sleep")] + \
            tail[tail.index("install(FILES"):]
        (pkg / "CMakeLists.txt").write_text(text[:start] + loop + tail, encoding="utf-8")
    return root


@needs_tools
@needs_library
@needs_tutorials
def test_roscpp_tutorials_talker_builds_from_its_sources(tmp_path: Path) -> None:
    ws = _tutorials_workspace(tmp_path / "ws", only=["talker"])
    first = Run(ws, "-j2")  # builds ddes's roscpp into the (test run's) cache unless it is there
    assert first.code == 0, first
    exe = ws / "devel" / "lib" / "roscpp_tutorials" / "talker"
    assert exe.is_file()
    assert (ws / "devel" / "include" / "roscpp_tutorials" / "TwoInts.h").is_file()
    # started by hand, outside a world, the node says how it must be started
    alone = subprocess.run([exe], capture_output=True, text=True, env={"PATH": "/usr/bin:/bin"})
    assert alone.returncode == 1 and "must be started by ddes" in alone.stderr
    shutil.rmtree(ws / "build")
    shutil.rmtree(ws / "devel")
    clean = Run(ws, "-j2")  # a clean build: the library comes from the cache
    assert clean.code == 0, clean
    assert not any("building ddes's roscpp" in line for line in clean.out)
    again = Run(ws, "-j2")
    assert again.code == 0, again
    assert not any("Building CXX" in line for line in again.out)
    print(f"talker: first build {first.seconds:.1f} s, clean build {clean.seconds:.1f} s, "
          f"nothing changed {again.seconds:.1f} s")


@pytest.mark.slow
@needs_tools
@needs_library
@needs_tutorials
def test_all_of_roscpp_tutorials_builds(tmp_path: Path) -> None:
    ws = _tutorials_workspace(tmp_path / "ws")
    clean = Run(ws, "-j2")
    assert clean.code == 0, clean
    lib = ws / "devel" / "lib" / "roscpp_tutorials"
    for exe in ("talker", "listener", "add_two_ints_server", "add_two_ints_client", "babbler",
                "listener_class", "timers", "parameters", "time_api_sleep"):
        assert (lib / exe).is_file(), exe
    print(f"roscpp_tutorials: clean build {clean.seconds:.1f} s")


def test_python_m_entry_runs_the_helpers(tmp_path: Path) -> None:
    """The CMake side's ``scan``: packages in order, components, configs for find_package."""
    src = tmp_path / "src"
    _write(src / "b" / "package.xml", _package_xml("b", ["a", "geometry_msgs"]))
    _write(src / "b" / "CMakeLists.txt", "")
    _write(src / "a" / "package.xml", _package_xml("a", ["roscpp"]))
    _write(src / "a" / "CMakeLists.txt", "")
    build = tmp_path / "build"
    proc = subprocess.run([sys.executable, "-m", "ddes.roscpp.catkin", "scan", "--source",
                           str(src), "--build", str(build), "--devel", str(tmp_path / "devel"),
                           "--cmake-dir", str(catkin.CMAKE_DIR)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    text = (build / "ddes_catkin" / "workspace.cmake").read_text(encoding="utf-8")
    assert 'set(DDES_WS_PACKAGES "a;b")' in text
    assert (build / "ddes_catkin" / "share" / "roscpp" / "cmake" / "roscppConfig.cmake").is_file()
    assert (build / "ddes_catkin" / "share" / "b" / "cmake" / "bConfig.cmake").is_file()
    gen = build / "ddes_gencpp" / "include"
    assert (gen / "geometry_msgs" / "Twist.h").is_file()
    assert (gen / "std_msgs" / "String.h").is_file()  # roscpp's
