"""Reading submissions safely: folders, zips and notebooks; every bad entry named."""

from __future__ import annotations

import json
import os
import stat
import zipfile
from pathlib import Path

import pytest

from ddes.errors import SubmissionError
from ddes.grading.submission import MAX_FILE, prepare


def make_zip(path: Path, entries: dict[str, bytes], *, link: str | None = None) -> Path:
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, data in entries.items():
            zf.writestr(name, data)
        if link is not None:
            info = zipfile.ZipInfo(link)
            info.external_attr = (stat.S_IFLNK | 0o777) << 16
            zf.writestr(info, "/etc/passwd")
    return path


def test_a_zip_is_unpacked(tmp_path: Path) -> None:
    z = make_zip(tmp_path / "s.zip", {"talker.py": b"print(1)\n", "pkg/a.txt": b"a"})
    digest = prepare(z, tmp_path / "out")
    assert (tmp_path / "out" / "talker.py").read_bytes() == b"print(1)\n"
    assert (tmp_path / "out" / "pkg" / "a.txt").read_bytes() == b"a"
    assert len(digest) == 64


@pytest.mark.parametrize("entries, link, text", [
    ({"/etc/evil": b"x"}, None, "absolute path"),
    ({"../evil.py": b"x"}, None, "climbs out"),
    ({"a/../../evil.py": b"x"}, None, "climbs out"),
    ({"a\\evil.py": b"x"}, None, "not a plain relative path"),
    ({"C:/evil.py": b"x"}, None, "absolute path"),
    ({"ok.py": b"x"}, "link.py", "is a link"),
    ({"big.bin": b"\0" * (MAX_FILE + 1)}, None, "inflates more than|larger than"),
])
def test_bad_zip_entries_are_refused(tmp_path: Path, entries: dict[str, bytes], link: str | None,
                                     text: str) -> None:
    z = make_zip(tmp_path / "s.zip", entries, link=link)
    with pytest.raises(SubmissionError, match=text):
        prepare(z, tmp_path / "out")
    assert not (tmp_path / "evil.py").exists() and not (tmp_path / "evil").exists()


def test_a_zip_bomb_is_refused_without_inflating_it(tmp_path: Path) -> None:
    z = make_zip(tmp_path / "bomb.zip", {"a.txt": b"\0" * (4 * 1024 * 1024)})
    with pytest.raises(SubmissionError, match="zip bomb"):
        prepare(z, tmp_path / "out")


def test_duplicate_entries_and_garbage_are_refused(tmp_path: Path) -> None:
    z = tmp_path / "dup.zip"
    with zipfile.ZipFile(z, "w") as zf, pytest.warns(UserWarning):
        zf.writestr("a.py", "1")
        zf.writestr("a.py", "2")
    with pytest.raises(SubmissionError, match="appears twice"):
        prepare(z, tmp_path / "out")
    bad = tmp_path / "bad.zip"
    bad.write_bytes(b"PK\x03\x04 not really")
    with pytest.raises(SubmissionError, match="not a readable zip"):
        prepare(bad, tmp_path / "out2")


def test_a_folder_with_a_link_is_refused(tmp_path: Path) -> None:
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "talker.py").write_text("x")
    os.symlink("/etc/passwd", sub / "leak")
    with pytest.raises(SubmissionError, match="leak: not a plain file"):
        prepare(sub, tmp_path / "out")


def notebook(cells: list[dict[str, object]]) -> bytes:
    return json.dumps({"cells": cells, "metadata": {}, "nbformat": 4,
                       "nbformat_minor": 5}).encode()


def test_a_notebook_gives_its_exported_cells(tmp_path: Path) -> None:
    nb = tmp_path / "hw.ipynb"
    nb.write_bytes(notebook([
        {"cell_type": "markdown", "metadata": {}, "source": "# file: nope.py\n"},
        {"cell_type": "code", "metadata": {"tags": ["export"]},
         "source": ["# file: talker.py\n", "import rospy\n"], "outputs": []},
        {"cell_type": "code", "metadata": {}, "source": "# file: skipped.py\nx=1", "outputs": []},
    ]))
    prepare(nb, tmp_path / "out")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["talker.py"]
    assert (tmp_path / "out" / "talker.py").read_text() == "import rospy\n"


@pytest.mark.parametrize("cells, text", [
    ([], "no code cell is tagged 'export'"),
    ([{"cell_type": "code", "metadata": {"tags": ["export"]}, "source": "import rospy"}],
     "must start with '# file:"),
    ([{"cell_type": "code", "metadata": {"tags": ["export"]}, "source": "# file: ../x.py\n"}],
     "climbs out"),
])
def test_bad_notebooks_are_refused(tmp_path: Path, cells: list[dict[str, object]],
                                   text: str) -> None:
    nb = tmp_path / "hw.ipynb"
    nb.write_bytes(notebook(cells))
    with pytest.raises(SubmissionError, match=text):
        prepare(nb, tmp_path / "out")
    nb.write_bytes(b"{not json")
    with pytest.raises(SubmissionError, match="not a notebook"):
        prepare(nb, tmp_path / "out3")
