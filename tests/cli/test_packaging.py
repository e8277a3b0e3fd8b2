"""Packaging promises: the LICENSE is the license pyproject.toml names, the dependencies are
exactly what ddes imports, every lower bound is one .ci/min-versions pins, README.md's set-up
command installs what the suite needs (and no linter), and the sdist carries the tests and docs."""

from __future__ import annotations

import ast
import importlib.util
import re
import subprocess
import sys
import tarfile
from importlib import metadata
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
import tomllib

REPO = Path(__file__).resolve().parents[2]
CI = REPO / ".ci"

if not (REPO / "pyproject.toml").is_file():  # pragma: no cover - the suite runs from a checkout
    pytest.skip("no pyproject.toml next to the tests", allow_module_level=True)


def ci_script(name: str) -> ModuleType:
    """A Python helper of .ci/ (not a package), imported by path."""
    spec = importlib.util.spec_from_file_location(f"ci_{name}", CI / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def pyproject() -> dict[str, Any]:
    return dict(tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8")))


def dist_name(requirement: str) -> str:
    """``"PyYAML>=6.0"`` -> ``"pyyaml"`` (PEP 503 normalised)."""
    match = re.match(r"\s*([A-Za-z0-9][A-Za-z0-9._-]*)", requirement)
    assert match is not None, requirement
    return re.sub(r"[-_.]+", "-", match.group(1)).lower()


# -- the license ---------------------------------------------------------------------------------

def test_the_license_file_is_the_license_pyproject_names() -> None:
    project = pyproject()["project"]
    assert project["license"] == "BSD-3-Clause"
    assert project["license-files"] == ["LICENSE"]
    text = (REPO / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("BSD 3-Clause License\n\nCopyright (c) ")
    assert "The ddes authors" in text.splitlines()[2]
    assert "3. Neither the name of the copyright holder nor the names of its" in text
    assert not any("License ::" in c for c in project.get("classifiers", []))  # PEP 639


# -- the dependencies are what ddes imports -----------------------------------------------------

def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def runtime_imports(tree: ast.AST) -> set[str]:
    """Top-level names of every module imported outside ``if TYPE_CHECKING:`` (any scope)."""
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            for child in node.orelse:
                visit(child)
            return
        if isinstance(node, ast.Import):
            found.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(tree)
    return found


def third_party_imports() -> dict[str, list[str]]:
    """Each third-party module ddes imports at run time -> the files that import it.

    The rospy scripts of the bundled catkin packages (``ddes/packages/*/scripts``) are left
    out: ``ddes.compat.scripts`` runs them with ``rospy`` and ``std_msgs.msg`` resolved to ddes.
    """
    found: dict[str, list[str]] = {}
    for path in sorted((REPO / "ddes").rglob("*.py")):
        rel = path.relative_to(REPO)
        if rel.parts[:2] == ("ddes", "packages") and {"scripts", "nodes"} & set(rel.parts[3:-1]):
            continue
        for name in runtime_imports(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            if name not in sys.stdlib_module_names and name not in ("ddes", "__future__"):
                found.setdefault(name, []).append(str(rel))
    return found


def test_the_import_scanner_skips_type_checking_blocks() -> None:
    tree = ast.parse("import a.b\nfrom c import d\nfrom . import e\nif TYPE_CHECKING:\n"
                     "    import f\nelse:\n    import g\ndef h():\n    import i\n")
    assert runtime_imports(tree) == {"a", "c", "g", "i"}


#: (extra, its distributions, the only files that may import them, inside a function).
OPTIONAL = [("batch", {"distributed", "dask"}, {"ddes/grading/batch.py"}),
            ("numpy", {"numpy"}, {"ddes/msg/numpy_msg.py", "ddes/compat/tf/transformations.py",
                                 "ddes/compat/pinned_numpy.py"})]


def test_optional_imports_are_lazy() -> None:
    for _, dists, users in OPTIONAL:
        for rel in users:
            tree = ast.parse((REPO / rel).read_text(encoding="utf-8"), rel)
            top = runtime_imports(ast.Module(body=[n for n in tree.body if not isinstance(
                n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))], type_ignores=[]))
            assert not top & dists, f"{rel} imports {top & dists} at import time"


def test_the_dependencies_are_exactly_what_ddes_imports() -> None:
    declared = {dist_name(r) for r in pyproject()["project"]["dependencies"]}
    providers = metadata.packages_distributions()
    imported: dict[str, list[str]] = {}
    for module, files in third_party_imports().items():
        dists = providers.get(module)
        assert dists, f"{module} (imported by {files[0]}) is installed by no distribution"
        for dist in dists:
            imported.setdefault(dist_name(dist), []).extend(files)
    # An extra's distribution may be imported, lazily (inside a function), by the files it serves.
    for extra, dists, users in OPTIONAL:
        assert dists <= {dist_name(r) for r in pyproject()["project"]["optional-dependencies"][extra]}
        for dist in dists:
            assert set(imported.pop(dist, [])) <= users, f"{dist} is the {extra} extra's"
    missing = {d: f[0] for d, f in imported.items() if d not in declared}
    assert not missing, f"ddes imports these but pyproject.toml does not declare them: {missing}"
    unused = declared - set(imported)
    assert not unused, f"pyproject.toml declares these but ddes never imports them: {unused}"


def test_no_linter_is_a_dependency_or_in_the_test_extra() -> None:
    project = pyproject()["project"]
    extras = project["optional-dependencies"]
    readme_installs = {dist_name(r) for r in project["dependencies"] + extras["test"]}
    assert not readme_installs & {"ruff", "mypy", "types-pyyaml"}
    assert {"ruff", "mypy", "types-pyyaml"} <= {dist_name(r) for r in extras["dev"]}
    assert {"pytest", "hypothesis"} <= readme_installs


# -- lower bounds -------------------------------------------------------------------------------

@pytest.mark.parametrize("requirement, pinned", [
    ("simpy>=4.1,<5", "simpy==4.1"),
    ("mcap-ros1-support>=0.7", "mcap-ros1-support==0.7"),
    ("pytest >= 8.3.4", "pytest==8.3.4"),
    ("lz4>=4.0; python_version < '3.14'", "lz4==4.0 ; python_version < '3.14'"),
    ("ruff==0.17.6", "ruff==0.17.6"),
    ("types-PyYAML", "types-PyYAML"),
    ("rosbags[extra]>=0.10.9", "rosbags[extra]==0.10.9"),
])
def test_min_requirements_pins_each_lower_bound(requirement: str, pinned: str) -> None:
    assert ci_script("min_requirements").pin_lower_bound(requirement) == pinned


def test_every_dependency_has_a_lower_bound_that_min_versions_pins() -> None:
    project = pyproject()["project"]
    for requirement in project["dependencies"] + project["optional-dependencies"]["test"]:
        assert ">=" in requirement, f"{requirement}: no lower bound for .ci/min-versions to test"
    pins = ci_script("min_requirements").requirements(["test"])
    assert all("==" in pin for pin in pins)
    assert "simpy==4.1" in pins  # and simpy<5 stays in the metadata
    assert any(r.replace(" ", "").startswith("simpy>=4.1,<5") for r in project["dependencies"])


def test_ci_runs_the_linters_and_the_readme_commands_as_written() -> None:
    run = (CI / "run").read_text(encoding="utf-8")
    assert "python3 .ci/readme_commands.py" in run
    assert '.venv/bin/pip install -q ".[dev]"' in run
    assert run.index("readme_commands.py") < run.index('".[dev]"') < run.index("ruff check")
    commands = ci_script("readme_commands").setup_commands(
        (REPO / "README.md").read_text(encoding="utf-8"))
    assert commands == ['python3 -m venv .venv && .venv/bin/pip install ".[test]" && '
                        ".venv/bin/ddes demo", ".venv/bin/pytest"]


# -- Pythons ------------------------------------------------------------------------------------

def test_requires_python_and_the_classifiers_agree() -> None:
    project = pyproject()["project"]
    finder = ci_script("find_pythons")
    listed = sorted(int(c.rsplit(".", 1)[1]) for c in project["classifiers"]
                    if re.fullmatch(r"Programming Language :: Python :: 3\.\d+", c))
    assert project["requires-python"] == f">=3.{listed[0]}"
    assert finder.requires_python() == project["requires-python"]
    assert listed == list(range(listed[0], listed[-1] + 1))
    assert sys.version_info[:2] >= (3, listed[0])


@pytest.mark.parametrize("spec, version, admitted", [
    (">=3.10", (3, 10), True), (">=3.10", (3, 9), False), (">=3.10,<3.13", (3, 13), False),
    (">=3.10, !=3.11.*", (3, 11), False), ("~=3.10", (3, 12), True), ("==3.12.*", (3, 12), True),
])
def test_find_pythons_reads_requires_python(spec: str, version: tuple[int, int],
                                            admitted: bool) -> None:
    assert ci_script("find_pythons").admits(spec, version) is admitted


# -- the sdist ----------------------------------------------------------------------------------

def test_the_sdist_checker_names_what_is_missing_and_what_is_stray() -> None:
    check = ci_script("check_sdist")
    good = {"LICENSE", "README.md", "pyproject.toml", "PKG-INFO", "ddes/__init__.py",
            "tests/conftest.py", "docs/time.md", "examples/a.py", "benchmarks/run.py",
            ".ci/run", "ddes.egg-info/SOURCES.txt"}
    assert check.problems(good, {"ddes/__init__.py", "tests/conftest.py"}) == []
    bad = (good - {"docs/time.md"}) | {"tests/__pycache__/x.cpython-311.pyc"}
    assert check.problems(bad, {"ddes/__init__.py", "docs/time.md"}) == [
        "missing: docs/time.md", "missing folder: docs/",
        "stray: tests/__pycache__/x.cpython-311.pyc"]


def test_the_sdist_carries_the_tests_the_docs_and_every_tracked_file(tmp_path: Path) -> None:
    version = metadata.version("setuptools")  # the test extra asks for >=77 (PEP 639 metadata)
    assert int(version.split(".")[0]) >= 77, f"building the sdist needs setuptools>=77, have {version}"
    build = ("import sys; from setuptools import build_meta; "
             "print(build_meta.build_sdist(sys.argv[1]))")
    result = subprocess.run([sys.executable, "-c", build, str(tmp_path)], cwd=REPO,
                            capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 0, result.stderr[-3000:]
    sdist = tmp_path / result.stdout.strip().splitlines()[-1]
    check = ci_script("check_sdist")
    names = check.members(sdist)
    assert check.problems(names, check.tracked()) == []
    for name in ("tests/cli/test_packaging.py", "docs/console.md", "LICENSE", ".ci/run",
                 ".ci/min-versions", "examples/services_add_two_ints.py", "benchmarks/run.py"):
        assert name in names
    with tarfile.open(sdist) as tar:
        member = next(m for m in tar.getmembers() if m.name.endswith("/PKG-INFO")
                      and m.name.count("/") == 1)
        pkg_info = tar.extractfile(member).read().decode()  # type: ignore[union-attr]
    assert "License-Expression: BSD-3-Clause" in pkg_info
    assert "Requires-Dist: simpy<5,>=4.1" in pkg_info
