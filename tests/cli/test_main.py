"""The ``ddes`` command as argparse tools behave: ``python -m ddes``, ``--version``, ``-h``, and
a bare ``ddes`` that prints its usage on stderr and exits 2."""

from __future__ import annotations

import subprocess
import sys
from importlib import metadata

import pytest

import ddes
from ddes.cli.main import build_parser, main


def python_m_ddes(*args: str, stdin: str = "") -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "ddes", *args], input=stdin, text=True,
                          capture_output=True, timeout=120, check=False)


def test_bare_ddes_prints_usage_on_stderr_and_exits_2(capsys: pytest.CaptureFixture[str]
                                                      ) -> None:
    with pytest.raises(SystemExit) as exc:
        main([])
    assert exc.value.code == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.startswith("usage: ddes ")
    assert "ddes: error: a command is required: demo, " in err
    for command in ("console", "run", "roslaunch", "rosbag", "rosmsg"):
        assert command in err.splitlines()[-1]


def test_help_exits_0_on_stdout(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["-h"])
    assert exc.value.code == 0
    out, err = capsys.readouterr()
    assert out.startswith("usage: ddes ") and "console" in out and err == ""


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out == f"ddes {ddes.__version__}\n"


def test_an_unknown_command_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["bogus"])
    assert exc.value.code == 2
    assert "invalid choice: 'bogus'" in capsys.readouterr().err


def test_build_parser_is_the_parser_main_uses() -> None:
    assert build_parser().prog == "ddes"


def test_python_m_ddes_version() -> None:
    result = python_m_ddes("--version")
    assert (result.returncode, result.stdout, result.stderr) == (0, f"ddes {ddes.__version__}\n",
                                                                 "")


def test_python_m_ddes_with_no_command_exits_2() -> None:
    result = python_m_ddes()
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.startswith("usage: ddes ") and "a command is required" in result.stderr


def test_python_m_ddes_console() -> None:
    result = python_m_ddes("console", stdin="rostopic list\n")
    assert result.returncode == 0, result.stderr
    assert result.stdout == "$ rostopic list\n/rosout\n/rosout_agg\n"


def test_the_ddes_script_runs_main() -> None:
    try:
        dist = metadata.distribution("ddes")
    except metadata.PackageNotFoundError:
        pytest.skip("ddes is not installed (run from a checkout without pip install)")
    scripts = [e for e in dist.entry_points if e.group == "console_scripts"]
    assert [(e.name, e.value) for e in scripts] == [("ddes", "ddes.cli.main:main")]
    assert scripts[0].load() is main
