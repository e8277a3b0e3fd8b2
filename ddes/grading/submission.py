"""Reading a submission into a folder: a folder, a ``.zip`` or a notebook, safely.

* **folder**: copied file by file; links are refused, sizes bounded;
* **.zip**: every entry is checked before anything is written — no absolute paths, no ``..``,
  no backslashes or drive letters, no links, no duplicate names, at most :data:`MAX_FILES`
  entries, :data:`MAX_FILE` bytes each and :data:`MAX_TOTAL` in all, and a compression ratio of
  at most :data:`MAX_RATIO` (a zip bomb); sizes are counted while decompressing, never trusted
  from the headers;
* **.ipynb**: the notebook JSON is read (not executed); each code cell tagged ``export`` whose
  first line is ``# file: path/in/package.py`` is written to that path.

Every refusal is a :class:`~ddes.errors.SubmissionError` naming the entry and the rule.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import stat
import zipfile
from pathlib import Path, PurePosixPath

from ddes.errors import SubmissionError

__all__ = ["MAX_FILE", "MAX_FILES", "MAX_RATIO", "MAX_TOTAL", "prepare", "safe_relpath"]

MAX_FILES = 2000
MAX_FILE = 8 * 1024 * 1024
MAX_TOTAL = 64 * 1024 * 1024
MAX_RATIO = 200
_FILE_LINE = re.compile(r"^#\s*file:\s*(\S+)\s*$")


def safe_relpath(name: str, where: str) -> PurePosixPath:
    """A relative path inside the submission, or SubmissionError naming ``name``."""
    if not name or "\\" in name or "\x00" in name or len(name) > 512:
        raise SubmissionError(f"{where}: entry name {name[:80]!r} is not a plain relative path")
    p = PurePosixPath(name)
    if p.is_absolute() or re.match(r"^[A-Za-z]:", name):
        raise SubmissionError(f"{where}: entry {name!r} is an absolute path")
    if any(part == ".." for part in p.parts):
        raise SubmissionError(f"{where}: entry {name!r} climbs out of the submission ('..')")
    parts = [q for q in p.parts if q not in ("", ".")]
    if not parts:
        raise SubmissionError(f"{where}: entry {name!r} names no file")
    return PurePosixPath(*parts)


def prepare(source: str | os.PathLike[str], dest: str | os.PathLike[str]) -> str:
    """Put the submission ``source`` into the empty folder ``dest``; returns its sha256."""
    src = Path(source)
    out = Path(dest)
    out.mkdir(parents=True, exist_ok=True)
    if src.is_symlink():
        raise SubmissionError(f"{src} is a link: give the submission itself")
    if src.is_dir():
        return _from_folder(src, out)
    if not src.is_file():
        raise SubmissionError(f"submission {src} does not exist")
    if src.stat().st_size > MAX_TOTAL:
        raise SubmissionError(f"{src.name}: {src.stat().st_size} bytes (at most {MAX_TOTAL})")
    data = src.read_bytes()
    digest = hashlib.sha256(data).hexdigest()
    if src.suffix == ".zip" or data[:4] == b"PK\x03\x04":
        _from_zip(src, out)
    elif src.suffix == ".ipynb":
        _from_notebook(src.name, data, out)
    else:
        raise SubmissionError(f"{src.name}: a submission is a folder, a .zip or a .ipynb notebook")
    return digest


def _write(out: Path, rel: PurePosixPath, data: bytes, where: str) -> None:
    target = out.joinpath(*rel.parts)
    if target.exists():
        raise SubmissionError(f"{where}: {rel} appears twice")
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(data)


def _from_folder(src: Path, out: Path) -> str:
    digest = hashlib.sha256()
    total = count = 0
    for dirpath, dirs, files in os.walk(src):
        dirs.sort()
        for d in dirs:
            if os.path.islink(os.path.join(dirpath, d)):
                raise SubmissionError(f"{os.path.join(dirpath, d)} is a link: links are refused")
        for name in sorted(files):
            path = Path(dirpath) / name
            st = path.lstat()
            rel = path.relative_to(src).as_posix()
            if stat.S_ISLNK(st.st_mode) or not stat.S_ISREG(st.st_mode):
                raise SubmissionError(f"{rel}: not a plain file (links and devices are refused)")
            count += 1
            total += st.st_size
            if count > MAX_FILES or st.st_size > MAX_FILE or total > MAX_TOTAL:
                raise SubmissionError(f"{rel}: the submission is too large (at most {MAX_FILES} "
                                      f"files, {MAX_FILE} bytes each, {MAX_TOTAL} in all)")
            data = path.read_bytes()
            digest.update(rel.encode() + b"\x00" + hashlib.sha256(data).digest())
            _write(out, safe_relpath(rel, src.name), data, src.name)
    return digest.hexdigest()


def _from_zip(src: Path, out: Path) -> None:
    where = src.name
    try:
        zf = zipfile.ZipFile(src)
    except (zipfile.BadZipFile, OSError) as exc:
        raise SubmissionError(f"{where}: not a readable zip ({exc})") from None
    with zf:
        infos = zf.infolist()
        if len(infos) > MAX_FILES:
            raise SubmissionError(f"{where}: {len(infos)} entries (at most {MAX_FILES})")
        seen: set[str] = set()
        plan = []
        for info in infos:
            rel = safe_relpath(info.filename.rstrip("/") if info.is_dir() else info.filename,
                               where)
            mode = info.external_attr >> 16
            if stat.S_ISLNK(mode):
                raise SubmissionError(f"{where}: entry {info.filename!r} is a link")
            if info.flag_bits & 0x1:
                raise SubmissionError(f"{where}: entry {info.filename!r} is encrypted")
            key = rel.as_posix()
            if key in seen:
                raise SubmissionError(f"{where}: entry {key!r} appears twice")
            seen.add(key)
            if not info.is_dir():
                plan.append((info, rel))
        total = 0
        for info, rel in plan:
            data = bytearray()
            try:
                with zf.open(info) as f:
                    while True:
                        chunk = f.read(65536)
                        if not chunk:
                            break
                        data += chunk
                        if len(data) > MAX_FILE:
                            raise SubmissionError(f"{where}: entry {rel} is larger than "
                                                  f"{MAX_FILE} bytes")
                        if len(data) > MAX_RATIO * max(info.compress_size, 1) + 65536:
                            raise SubmissionError(f"{where}: entry {rel} inflates more than "
                                                  f"{MAX_RATIO}× (a zip bomb)")
            except (zipfile.BadZipFile, OSError, EOFError, NotImplementedError) as exc:
                raise SubmissionError(f"{where}: entry {rel} cannot be read ({exc})") from None
            total += len(data)
            if total > MAX_TOTAL:
                raise SubmissionError(f"{where}: more than {MAX_TOTAL} bytes once unpacked")
            _write(out, rel, bytes(data), where)


def _from_notebook(name: str, data: bytes, out: Path) -> None:
    try:
        nb = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as exc:
        raise SubmissionError(f"{name}: not a notebook (JSON: {exc})") from None
    cells = nb.get("cells") if isinstance(nb, dict) else None
    if not isinstance(cells, list):
        raise SubmissionError(f"{name}: a notebook has a 'cells' list")
    written = 0
    for i, cell in enumerate(cells):
        if not isinstance(cell, dict) or cell.get("cell_type") != "code":
            continue
        meta = cell.get("metadata")
        tags = meta.get("tags", []) if isinstance(meta, dict) else []
        if not isinstance(tags, list) or "export" not in tags:
            continue
        source = cell.get("source", "")
        text = "".join(source) if isinstance(source, list) else source
        if not isinstance(text, str):
            raise SubmissionError(f"{name}: cell {i} has no text source")
        first, _, rest = text.partition("\n")
        m = _FILE_LINE.match(first)
        if m is None:
            raise SubmissionError(f"{name}: exported cell {i} must start with '# file: "
                                  f"path/in/package.py', not {first[:60]!r}")
        _write(out, safe_relpath(m.group(1), f"{name} cell {i}"), rest.encode("utf-8"), name)
        written += 1
    if not written:
        raise SubmissionError(f"{name}: no code cell is tagged 'export' (tag the cells to grade "
                              "and start each with '# file: path')")
