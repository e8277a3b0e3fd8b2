"""Hostile files in a submission (issue 38): each is a SubmissionError naming the bad value and what
to do, never a traceback — a file where a folder must be, names past the filesystem's limits,
notebooks whose cells are not text, JSON nested 200,000 deep, lone surrogates, corrupt streams —
and a report that holds such text still prints and writes as UTF-8."""

from __future__ import annotations

import errno
import json
import os
import stat
import struct
import zipfile
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

import ddes.grading.submission as submission
from ddes.errors import DdesError, SubmissionError
from ddes.grading.course import _middle, parse_source
from ddes.grading.report import CriterionReport, GradeReport, utf8_safe, write_atomic
from ddes.grading.scenarios import scenario_seed
from ddes.grading.submission import MAX_DEPTH, MAX_FILES, MAX_NAME, MAX_PATH, prepare

DEEP = 200_000


def make_zip(path: Path, entries: list[tuple[str, bytes]]) -> Path:
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, data in entries:
            zf.writestr(name, data)
    return path


def refused(src: Path, out: Path, text: str) -> str:
    """prepare(src) raises a SubmissionError (a DdesError) matching ``text``; its message."""
    with pytest.raises(SubmissionError, match=text) as info:
        prepare(src, out)
    assert isinstance(info.value, DdesError)
    message = str(info.value)
    message.encode("utf-8")  # printable and writable as it is
    assert "Traceback" not in message and "/tmp" not in message.replace(str(src), "")
    return message


# -- a file where a folder must be ------------------------------------------------------------

@pytest.mark.parametrize("entries", [
    [("x", b"1"), ("x/y", b"2")],
    [("x/y", b"2"), ("x", b"1")],
    [("x/", b""), ("x", b"1")],
    [("x", b"1"), ("x/", b"")],
    [("a/x", b"1"), ("a/x/b/c.py", b"2")],
])
def test_a_file_where_a_folder_must_be_is_refused(tmp_path: Path,
                                                  entries: list[tuple[str, bytes]]) -> None:
    z = make_zip(tmp_path / "s.zip", entries)
    message = refused(z, tmp_path / "out", "is both a file .* and a folder")
    assert "rename one of them" in message


def test_a_notebook_with_a_file_where_a_folder_must_be_is_refused(tmp_path: Path) -> None:
    nb = tmp_path / "hw.ipynb"
    nb.write_bytes(notebook([exported("# file: x\n1\n"), exported("# file: x/y.py\n2\n")]))
    refused(nb, tmp_path / "out", "'x' is both a file")
    assert not (tmp_path / "out" / "x").exists()  # refused before anything was written


def test_duplicates_are_still_refused(tmp_path: Path) -> None:
    z = tmp_path / "dup.zip"
    with zipfile.ZipFile(z, "w") as zf, pytest.warns(UserWarning):
        zf.writestr("a/b.py", "1")
        zf.writestr("a/b.py", "2")
    refused(z, tmp_path / "out", "'a/b.py' appears twice")


# -- names past the filesystem's limits -------------------------------------------------------

@pytest.mark.parametrize("name, text", [
    ("a" * 300 + ".py", f"is 303 bytes long, past the {MAX_NAME} bytes a file or folder name"),
    ("pkg/" + "é" * 150 + ".py", "is 303 bytes long, past the 255"),  # 153 characters, 303 bytes
    ("/".join(["d" * 200] * 25) + "/f.py", f"bytes long, past the {MAX_PATH} a path inside"),
    ("/".join(["d" * 250] * 20) + "/f.py", "bytes long, past the"),  # past PATH_MAX (4096)
    ("a/" * (MAX_DEPTH + 1) + "f.py", f"{MAX_DEPTH + 1} folders deep \\(at most {MAX_DEPTH}\\)"),
])
def test_names_past_the_filesystem_limits_are_refused(tmp_path: Path, name: str,
                                                      text: str) -> None:
    z = make_zip(tmp_path / "s.zip", [("ok.py", b"1"), (name, b"x")])
    message = refused(z, tmp_path / "out", text)
    assert "shorten it" in message or "flatten" in message
    assert len(message) < 400  # the name is quoted cut, not whole


def test_names_at_the_limits_are_kept(tmp_path: Path) -> None:
    name = "/".join(["d" * MAX_NAME] * 3) + "/" + "f" * (MAX_NAME - 3) + ".py"
    assert len(name.encode()) <= MAX_PATH
    prepare(make_zip(tmp_path / "s.zip", [(name, b"1")]), tmp_path / "out")
    assert (tmp_path / "out" / name).read_bytes() == b"1"


# -- notebooks ------------------------------------------------------------------------------------

def exported(source: object) -> dict[str, object]:
    return {"cell_type": "code", "metadata": {"tags": ["export"]}, "source": source,
            "outputs": []}


def notebook(cells: list[dict[str, object]]) -> bytes:
    return json.dumps({"cells": cells, "metadata": {}, "nbformat": 4,
                       "nbformat_minor": 5}).encode()


@pytest.mark.parametrize("source, text", [
    (5, "cell 0 has no text source: its source is the number 5"),
    (1e300, "its source is the number 1e\\+300"),
    ({"a": 1}, "its source is an object"),
    (None, "its source is null"),
    (True, "its source is true"),
    (["# file: a.py\n", 3], "a list holding the number 3 at item 1"),
    (["# file: a.py\n", None], "a list holding null at item 1"),
    (["# file: a.py\n", ["x"]], "a list holding a list at item 1"),
])
def test_a_cell_source_that_is_not_text_is_refused(tmp_path: Path, source: object,
                                                   text: str) -> None:
    nb = tmp_path / "hw.ipynb"
    nb.write_bytes(notebook([exported(source)]))
    message = refused(nb, tmp_path / "out", text)
    assert "save the notebook again with Jupyter" in message


@pytest.mark.parametrize("data, text", [
    (b"{not json", "not a notebook \\(JSON: Expecting property name"),
    (b"[" * DEEP + b"]" * DEEP, "nests deeper than Python's recursion limit"),
    (b'{"cells": ' + b'{"a": ' * DEEP + b"1" + b"}" * DEEP + b"}", "nests deeper"),
    (b'{"cells": [], "x": "\xff"}', "not UTF-8"),
    (b"[1, 2]", "a notebook has a 'cells' list"),
    (b'{"cells": 5}', "a notebook has a 'cells' list"),
    (b'{"cells": [' + b"9" * 5000 + b"]}", "not a notebook \\(JSON: Exceeds the limit"),
])
def test_a_notebook_that_is_not_readable_json_is_refused(tmp_path: Path, data: bytes,
                                                         text: str) -> None:
    nb = tmp_path / "hw.ipynb"
    nb.write_bytes(data)
    refused(nb, tmp_path / "out", text)


# -- lone surrogates and control characters -------------------------------------------------------

def test_a_lone_surrogate_in_a_notebook_is_refused(tmp_path: Path) -> None:
    nb = tmp_path / "hw.ipynb"
    nb.write_bytes(b'{"cells": [{"cell_type": "code", "metadata": {"tags": ["export"]}, '
                   b'"source": "# file: talker.py\\nx = 1\\nprint(\\"\\udcff\\")\\n"}]}')
    message = refused(nb, tmp_path / "out", "cell 0 holds the lone surrogate U\\+DCFF at line 3")
    assert "remove it" in message
    nb.write_bytes(b'{"cells": [{"cell_type": "code", "metadata": {"tags": ["export"]}, '
                   b'"source": "# file: t\\udcff.py\\nx = 1\\n"}]}')
    refused(nb, tmp_path / "out2", "entry name 't\ufffd.py' is not valid UTF-8 .*U\\+DCFF")
    nb.write_bytes(notebook([exported("# file: ok.py\nprint('\U0001f600')\n")]))  # a real pair
    prepare(nb, tmp_path / "out3")
    assert (tmp_path / "out3" / "ok.py").read_text(encoding="utf-8") == "print('\U0001f600')\n"


def test_a_zip_name_that_is_not_utf8_is_refused(tmp_path: Path) -> None:
    z = make_zip(tmp_path / "s.zip", [("tXX.py", b"print(1)")])
    raw = z.read_bytes().replace(b"tXX.py", b"t\xed\xb3\xbf.p")  # UTF-8 of a lone surrogate
    local, central = raw.find(b"PK\x03\x04"), raw.find(b"PK\x01\x02")
    raw = raw[:local + 6] + struct.pack("<H", 0x800) + raw[local + 8:]  # "the names are UTF-8"
    raw = raw[:central + 8] + struct.pack("<H", 0x800) + raw[central + 10:]
    z.write_bytes(raw)
    refused(z, tmp_path / "out", "an entry's name is not valid UTF-8.*zip it again")


def test_a_folder_name_that_is_not_utf8_is_refused(tmp_path: Path) -> None:
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "talker.py").write_text("print(1)\n")
    with open(os.path.join(os.fsencode(sub), b"t\xff.py"), "wb") as f:
        f.write(b"x")
    refused(sub, tmp_path / "out", "entry name 't\ufffd.py' is not valid UTF-8 \\(it holds the "
            "byte 0xff\\): rename the file")


@pytest.mark.parametrize("name", ["a\nproblem: 10/10.py", "a\x1b[31m.py", "a\x7f.py"])
def test_a_name_with_a_control_character_is_refused(tmp_path: Path, name: str) -> None:
    z = make_zip(tmp_path / "s.zip", [(name, b"1")])
    message = refused(z, tmp_path / "out", "holds the control character")
    assert "\n" not in message and "\x1b" not in message  # quoted, never a line of its own


def test_a_submission_named_not_utf8_gives_a_utf8_message(tmp_path: Path) -> None:
    path = os.path.join(os.fsencode(tmp_path), b"s\xff.zip")
    with open(path, "wb") as f, zipfile.ZipFile(f, "w") as zf:
        zf.writestr("x", b"1")
        zf.writestr("x/y", b"2")
    message = refused(Path(os.fsdecode(path)), tmp_path / "out", "'x' is both a file")
    assert message.startswith("s\ufffd.zip: ")


# -- corrupt, unreadable, too many entries ------------------------------------------------------

def test_a_corrupt_stream_is_refused(tmp_path: Path) -> None:
    z = make_zip(tmp_path / "s.zip", [("talker.py", b"print(1)\n" * 1000)])
    raw = bytearray(z.read_bytes())
    raw[40:60] = b"\xff" * 20  # inside the deflate stream
    z.write_bytes(bytes(raw))
    refused(z, tmp_path / "out", "entry talker.py cannot be read \\((zlib.error|BadZipFile).*"
            "zip the files again")


def test_an_unreadable_or_odd_file_is_refused(tmp_path: Path, monkeypatch: Any) -> None:
    fifo = tmp_path / "s.zip"
    os.mkfifo(fifo)
    refused(fifo, tmp_path / "out", "is not a regular file")  # and never opened (it would block)
    fifo.unlink()
    make_zip(fifo, [("talker.py", b"1")])
    real = open

    def no_read(file: Any, *args: Any, **kwargs: Any) -> Any:
        if str(file) == str(fifo):
            raise PermissionError(errno.EACCES, "Permission denied", str(file))
        return real(file, *args, **kwargs)

    monkeypatch.setattr(submission, "open", no_read, raising=False)
    message = refused(fifo, tmp_path / "out2", "s.zip: cannot be read \\(PermissionError: "
                      "Permission denied\\)")
    assert str(tmp_path) not in message


def test_a_full_disk_is_the_machines_error_not_the_submissions(tmp_path: Path,
                                                               monkeypatch: Any) -> None:
    z = make_zip(tmp_path / "s.zip", [("talker.py", b"1")])
    real = open

    def full(file: Any, mode: str = "r", *args: Any, **kwargs: Any) -> Any:
        if "x" in mode:
            raise OSError(errno.ENOSPC, "No space left on device", str(file))
        return real(file, mode, *args, **kwargs)

    monkeypatch.setattr(submission, "open", full, raising=False)
    with pytest.raises(OSError) as info:
        prepare(z, tmp_path / "out")
    assert not isinstance(info.value, SubmissionError) and info.value.errno == errno.ENOSPC


def test_a_zip_of_a_hundred_thousand_entries_is_refused_before_reading_them(
        tmp_path: Path) -> None:
    z = tmp_path / "many.zip"
    with zipfile.ZipFile(z, "w", zipfile.ZIP_STORED) as zf:
        for i in range(100_000):
            zf.writestr(f"{i}", b"")
    refused(z, tmp_path / "out", f"about 100000 entries \\(at most {MAX_FILES}\\)")


def test_a_folder_deeper_than_the_limit_is_refused(tmp_path: Path) -> None:
    deep = tmp_path / "sub" / Path(*["d"] * (MAX_DEPTH + 1))
    deep.mkdir(parents=True)
    (deep / "f.py").write_text("1")
    refused(tmp_path / "sub", tmp_path / "out", f"folders deep \\(at most {MAX_DEPTH}\\)")


def test_a_folder_that_cannot_be_listed_is_refused_not_skipped(tmp_path: Path,
                                                               monkeypatch: Any) -> None:
    sub = tmp_path / "sub"
    (sub / "pkg").mkdir(parents=True)
    (sub / "pkg" / "talker.py").write_text("1")
    real = os.scandir

    def no_list(path: Any) -> Any:
        if str(path).endswith("pkg"):
            raise PermissionError(errno.EACCES, "Permission denied", str(path))
        return real(path)

    monkeypatch.setattr(os, "scandir", no_list)
    refused(sub, tmp_path / "out", "sub: the folder 'pkg' cannot be read \\(PermissionError: "
            "Permission denied\\)")


# -- reports hold what the submission said, and stay UTF-8 ---------------------------------------

def test_a_report_with_lone_surrogates_prints_and_writes_utf8(tmp_path: Path) -> None:
    report = GradeReport(exercise="ex0_talker", title="t", submission="s\udcff.zip", seed=0,
                         public=False, problems=["s\udcff.zip: entry 'x\udcff' appears twice"])
    report.criteria.append(CriterionReport(id="0.1", name="n", points=0, max_points=2,
                                           evidence=["got 'hello \ud800'"],
                                           replay="ddes grade replay ex s\udcff.zip"))
    report.digests["pub\udcff"] = "d"
    report.enforced = ["limit \udcff"]
    text = report.to_text()
    assert "s\ufffd.zip" in text and "hello \ufffd" in text
    text.encode("utf-8")
    report.write_results(tmp_path / "results.json")
    data = json.loads((tmp_path / "results.json").read_bytes().decode("utf-8"))  # strict UTF-8
    assert "hello \ufffd" in data["tests"][0]["output"] and "pub\ufffd" in data["extra_data"]["digests"]
    report.write_junit(tmp_path / "junit.xml")
    (tmp_path / "junit.xml").read_bytes().decode("utf-8")
    write_atomic(tmp_path / "report.txt", "a\udcffb")
    assert (tmp_path / "report.txt").read_text(encoding="utf-8") == "a\ufffdb"
    assert utf8_safe("ok \U0001f600") == "ok \U0001f600"


# -- nesting in what the grader parses of the submission -------------------------------------------

def test_python_source_nested_too_deep_does_not_parse(tmp_path: Path) -> None:
    for text in ("x" + ".a" * DEEP, "x = " + "-" * DEEP + "1"):
        facts = SimpleNamespace(read_text=lambda rel, text=text: text)
        assert parse_source(facts, "a.py") is None  # type: ignore[arg-type]


def test_a_long_launch_error_keeps_what_to_do() -> None:
    text = '<param value="' + "$(arg " * DEEP + '">: roslaunch does not nest substitutions: use $(eval)'
    cut = _middle(text)
    assert len(cut) <= 480 and cut.startswith('<param value="$(arg ')
    assert cut.endswith("roslaunch does not nest substitutions: use $(eval)")
    assert _middle("short") == "short"


def test_a_student_id_that_is_not_utf8_has_a_hidden_seed() -> None:
    secret = b"k" * 16
    seed = scenario_seed(secret, "ex0", "s\udcff", 0, 0)
    assert seed == scenario_seed(secret, "ex0", "s\udcff", 0, 0) != scenario_seed(
        secret, "ex0", "s\udcfe", 0, 0)


def test_the_limits_do_not_refuse_a_usual_package(tmp_path: Path) -> None:
    z = make_zip(tmp_path / "s.zip", [
        ("smb_highlevel_controller/", b""),
        ("smb_highlevel_controller/package.xml", b"<package/>"),
        ("smb_highlevel_controller/scripts/node.py", b"print(1)\n"),
        ("smb_highlevel_controller/src/smb_highlevel_controller/__init__.py", b""),
        ("smb_highlevel_controller/config/café.yaml", b"a: 1\n"),
    ])
    prepare(z, tmp_path / "out")
    got = sorted(p.relative_to(tmp_path / "out").as_posix() for p in (tmp_path / "out").rglob("*")
                 if p.is_file())
    assert got == ["smb_highlevel_controller/config/café.yaml",
                   "smb_highlevel_controller/package.xml",
                   "smb_highlevel_controller/scripts/node.py",
                   "smb_highlevel_controller/src/smb_highlevel_controller/__init__.py"]
    assert stat.S_ISREG((tmp_path / "out" / "smb_highlevel_controller" / "package.xml").stat().st_mode)
