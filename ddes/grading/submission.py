"""Reading a submission into a folder: a folder, a ``.zip`` or a notebook, safely.

* **folder**: copied file by file; links are refused, sizes bounded;
* **.zip**: every entry is checked before anything is written — no absolute paths, no ``..``,
  no backslashes or drive letters, no links, no duplicate names, no path that is both a file and
  a folder (``x`` and ``x/y``), at most :data:`MAX_FILES` entries, :data:`MAX_FILE` bytes each
  and :data:`MAX_TOTAL` in all, and a compression ratio of at most :data:`MAX_RATIO` (a zip
  bomb); sizes are counted while decompressing, never trusted from the headers;
* **.ipynb**: the notebook JSON is read (not executed); each code cell tagged ``export`` whose
  first line is ``# file: path/in/package.py`` is written to that path.

Every name, whatever its source, is a plain relative path of valid UTF-8 (no lone surrogate, no
control character), each part at most :data:`MAX_NAME` bytes (the filesystem's limit), the
whole at most :data:`MAX_PATH` bytes and :data:`MAX_DEPTH` folders deep.  Every refusal is a
:class:`~ddes.errors.SubmissionError` naming the entry, the rule and what to do; whatever else
goes wrong reading a submission (a corrupt stream, JSON nested past the recursion limit) is one
too, so :func:`prepare` never raises anything else for a bad submission.  Only a failure of the
grading machine itself (its disk full, read-only or failing) is left as the ``OSError`` it is:
that is no fault of the submission.
"""

from __future__ import annotations

import errno
import hashlib
import io
import json
import os
import re
import stat
import zipfile
from pathlib import Path, PurePosixPath

from ddes.errors import SubmissionError

__all__ = ["MAX_DEPTH", "MAX_FILE", "MAX_FILES", "MAX_NAME", "MAX_PATH", "MAX_RATIO", "MAX_TOTAL",
           "prepare", "safe_relpath", "shown"]

MAX_FILES = 2000
MAX_FILE = 8 * 1024 * 1024
MAX_TOTAL = 64 * 1024 * 1024
MAX_RATIO = 200
#: Bytes of one part of a path (a file or folder name): the filesystem's NAME_MAX.
MAX_NAME = 255
#: Bytes of a whole path inside the submission (the grader's folder in front of it stays well
#: under the system's PATH_MAX of 4096).
MAX_PATH = 1024
#: Folders a path may go down.
MAX_DEPTH = 64
_FILE_LINE = re.compile(r"^#\s*file:\s*(\S+)\s*$")
_SURROGATE = re.compile("[\ud800-\udfff]")
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f]")
#: errno values that are the grading machine's trouble, never the submission's.
_MACHINE = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EIO, errno.EMFILE,
                      errno.ENFILE, errno.ENOMEM})


def shown(text: str, limit: int = 80) -> str:
    """``text`` as it is safe to print and to write as UTF-8: each lone surrogate (a byte that
    is not UTF-8, read with ``surrogateescape``, or a JSON ``\\udcff``) becomes U+FFFD, and a
    text longer than ``limit`` characters is cut with "…"."""
    text = _SURROGATE.sub("\ufffd", text)
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _q(name: str, limit: int = 80) -> str:
    """A name quoted for a message: control characters escaped, no surrogate, cut."""
    return repr(shown(name, limit))


def safe_relpath(name: str, where: str, *, from_json: bool = False) -> PurePosixPath:
    """A relative path inside the submission, or SubmissionError naming ``name`` (``from_json``:
    the name comes from JSON, where a surrogate is an escape, not a byte of the filesystem)."""
    if not isinstance(name, str) or not name:
        raise SubmissionError(f"{where}: an entry has an empty name: give every file a name")
    if "\\" in name or "\x00" in name:
        raise SubmissionError(f"{where}: entry name {_q(name)} is not a plain relative path "
                              "(write folders with '/', never '\\' or a NUL byte)")
    bad = _SURROGATE.search(name)
    if bad is not None:
        raise SubmissionError(
            f"{where}: entry name {_q(name)} is not valid UTF-8 (it holds "
            f"{_byte_or_code(bad.group(), from_json)}): rename the file with plain characters")
    ctl = _CONTROL.search(name)
    if ctl is not None:
        raise SubmissionError(f"{where}: entry name {_q(name)} holds the control character "
                              f"{ctl.group()!r}: rename the file with plain characters")
    size = len(name.encode("utf-8"))
    if size > MAX_PATH:
        raise SubmissionError(f"{where}: entry name {_q(name)} is {size} bytes long, past the "
                              f"{MAX_PATH} a path inside a submission may have: shorten it")
    p = PurePosixPath(name)
    if p.is_absolute() or re.match(r"^[A-Za-z]:", name):
        raise SubmissionError(f"{where}: entry {_q(name)} is an absolute path")
    if any(part == ".." for part in p.parts):
        raise SubmissionError(f"{where}: entry {_q(name)} climbs out of the submission ('..')")
    parts = [q for q in p.parts if q not in ("", ".")]
    if not parts:
        raise SubmissionError(f"{where}: entry {_q(name)} names no file")
    if len(parts) > MAX_DEPTH + 1:
        raise SubmissionError(f"{where}: entry {_q(name)} is {len(parts) - 1} folders deep (at "
                              f"most {MAX_DEPTH}): flatten the submission's folders")
    for part in parts:
        n = len(part.encode("utf-8"))
        if n > MAX_NAME:
            raise SubmissionError(
                f"{where}: entry {_q(name)}: the name {_q(part, 40)} is {n} bytes long, past "
                f"the {MAX_NAME} bytes a file or folder name may have: shorten it")
    return PurePosixPath(*parts)


def _byte_or_code(ch: str, from_json: bool = False) -> str:
    code = ord(ch)
    if 0xDC80 <= code <= 0xDCFF and not from_json:  # surrogateescape: the byte that is not UTF-8
        return f"the byte 0x{code - 0xDC00:02x}"
    return f"the lone surrogate U+{code:04X}"


def prepare(source: str | os.PathLike[str], dest: str | os.PathLike[str]) -> str:
    """Put the submission ``source`` into the empty folder ``dest``; returns its sha256.

    Raises :class:`~ddes.errors.SubmissionError` for any submission that cannot be read, whatever
    its files hold; an ``OSError`` only when the grading machine fails (its disk full)."""
    src = Path(source)
    where = shown(src.name or str(src))
    try:
        return _prepare(src, Path(dest), where)
    except SubmissionError:
        raise
    except RecursionError:
        raise SubmissionError(f"{where}: nested too deep to read (past Python's recursion "
                              "limit): a submission's files nest a few levels, not thousands"
                              ) from None
    except MemoryError:
        raise SubmissionError(f"{where}: too large to read in memory") from None
    except OSError as exc:
        if exc.errno in _MACHINE:
            raise  # the grading machine's trouble (disk full...), not the submission's
        raise SubmissionError(f"{where}: cannot be read ({_os_text(exc)})") from None
    except Exception as exc:  # noqa: BLE001 - whatever a hostile file makes a reader raise
        raise SubmissionError(f"{where}: cannot be read ({_kind(exc)}: "
                              f"{shown(str(exc), 200)})") from None


def _kind(exc: BaseException) -> str:
    """An exception's type as a reader knows it: ``zlib.error``, ``struct.error``, ``KeyError``."""
    t = type(exc)
    return t.__name__ if t.__module__ == "builtins" else f"{t.__module__}.{t.__name__}"


def _os_text(exc: OSError) -> str:
    """An OSError without its file names (they hold the grader's temporary folder)."""
    if exc.strerror:
        return f"{type(exc).__name__}: {exc.strerror}"
    return f"{type(exc).__name__}: {shown(str(exc), 200)}"


def _prepare(src: Path, out: Path, where: str) -> str:
    out.mkdir(parents=True, exist_ok=True)
    if src.is_symlink():
        raise SubmissionError(f"{where} is a link: give the submission itself")
    if src.is_dir():
        return _from_folder(src, out, where)
    if not src.exists():
        raise SubmissionError(f"submission {shown(str(src), 200)} does not exist")
    if not src.is_file():
        raise SubmissionError(f"{where} is not a regular file (a FIFO, a device or a socket): "
                              "give a folder, a .zip or a .ipynb notebook")
    if src.suffix != ".ipynb" and src.suffix != ".zip":
        with open(src, "rb") as f:
            magic = f.read(4)
        if magic != b"PK\x03\x04":
            raise SubmissionError(f"{where}: a submission is a folder, a .zip or a .ipynb "
                                  "notebook")
    with open(src, "rb") as f:
        data = f.read(MAX_TOTAL + 1)
    if len(data) > MAX_TOTAL:
        raise SubmissionError(f"{where}: more than {MAX_TOTAL} bytes (at most {MAX_TOTAL})")
    digest = hashlib.sha256(data).hexdigest()
    if src.suffix == ".zip" or data[:4] == b"PK\x03\x04":
        _from_zip(data, out, where)
    else:
        _from_notebook(where, data, out)
    return digest


class _Tree:
    """The paths of one submission as they are planned: each once, and none both a file and a
    folder (a zip may hold ``x`` and ``x/y``; a filesystem cannot)."""

    def __init__(self, where: str) -> None:
        self.where = where
        self.seen: set[str] = set()
        self.files: dict[str, str] = {}  # path -> the entry that makes it a file
        self.dirs: dict[str, str] = {}  # path -> the entry that makes it a folder

    def add(self, rel: PurePosixPath, entry: str, *, folder: bool = False) -> None:
        key = rel.as_posix()
        for parent in [p.as_posix() for p in reversed(rel.parents) if p.parts]:
            if parent in self.files:
                self._both(parent, self.files[parent], entry)
        if folder and key in self.files:
            self._both(key, self.files[key], entry)
        if not folder and key in self.dirs:
            self._both(key, entry, self.dirs[key])
        if key in self.seen:
            raise SubmissionError(f"{self.where}: {_q(key)} appears twice: keep one of them")
        self.seen.add(key)
        for parent in [p.as_posix() for p in rel.parents if p.parts]:
            self.dirs.setdefault(parent, entry)
        if folder:
            self.dirs.setdefault(key, entry)
        else:
            self.files[key] = entry

    def _both(self, key: str, as_file: str, as_folder: str) -> None:
        raise SubmissionError(
            f"{self.where}: {_q(key)} is both a file (entry {_q(as_file)}) and a folder "
            f"(entry {_q(as_folder)} is inside it): a path cannot be both; rename one of them")


def _write(out: Path, rel: PurePosixPath, data: bytes, where: str) -> None:
    target = out.joinpath(*rel.parts)
    try:
        if target.exists() or target.is_symlink():
            raise SubmissionError(f"{where}: {rel} appears twice: keep one of them")
        target.parent.mkdir(parents=True, exist_ok=True)
        with open(target, "xb") as f:
            f.write(data)
    except OSError as exc:
        if exc.errno in _MACHINE:
            raise
        raise SubmissionError(f"{where}: {_q(rel.as_posix())} cannot be written "
                              f"({_os_text(exc)}): rename it") from None


def _from_folder(src: Path, out: Path, where: str) -> str:
    digest = hashlib.sha256()
    total = count = 0
    tree = _Tree(where)

    def refuse(exc: OSError) -> None:
        # os.walk would skip a folder it cannot list: that is a refusal, not a skip
        if exc.errno in _MACHINE:
            raise exc
        folder = Path(os.fsdecode(exc.filename or src))
        rel = folder.relative_to(src).as_posix() if folder.is_relative_to(src) else folder.name
        raise SubmissionError(f"{where}: the folder {_q(rel)} cannot be read ({_os_text(exc)})")

    for dirpath, dirs, files in os.walk(src, onerror=refuse):
        dirs.sort()
        depth = len(Path(dirpath).relative_to(src).parts)
        if depth > MAX_DEPTH:
            raise SubmissionError(f"{where}: {_q(Path(dirpath).relative_to(src).as_posix())} is "
                                  f"{depth} folders deep (at most {MAX_DEPTH}): flatten the "
                                  "submission's folders")
        for d in dirs:
            if os.path.islink(os.path.join(dirpath, d)):
                rel = (Path(dirpath) / d).relative_to(src).as_posix()
                raise SubmissionError(f"{where}: {_q(rel)} is a link: links are refused")
        for name in sorted(files):
            path = Path(dirpath) / name
            st = path.lstat()
            rel = path.relative_to(src).as_posix()
            if stat.S_ISLNK(st.st_mode) or not stat.S_ISREG(st.st_mode):
                raise SubmissionError(f"{shown(rel, 200)}: not a plain file (links and devices "
                                      "are refused)")
            count += 1
            total += st.st_size
            if count > MAX_FILES or st.st_size > MAX_FILE or total > MAX_TOTAL:
                raise SubmissionError(f"{shown(rel, 200)}: the submission is too large (at most "
                                      f"{MAX_FILES} files, {MAX_FILE} bytes each, {MAX_TOTAL} in "
                                      "all)")
            relpath = safe_relpath(rel, where)
            tree.add(relpath, rel)
            with open(path, "rb") as f:
                data = f.read(MAX_FILE + 1)
            if len(data) > MAX_FILE:
                raise SubmissionError(f"{shown(rel, 200)}: larger than {MAX_FILE} bytes")
            digest.update(rel.encode() + b"\x00" + hashlib.sha256(data).digest())
            _write(out, relpath, data, where)
    return digest.hexdigest()


def _from_zip(data: bytes, out: Path, where: str) -> None:
    # every central-directory record starts with this signature: more of them than a few times
    # MAX_FILES is refused before zipfile builds an object per entry (a million tiny entries)
    records = data.count(b"PK\x01\x02")
    if records > 4 * MAX_FILES:
        raise SubmissionError(f"{where}: about {records} entries (at most {MAX_FILES}): zip "
                              "only the files to grade")
    try:
        zf = zipfile.ZipFile(io.BytesIO(data))
    except UnicodeDecodeError:
        raise SubmissionError(f"{where}: an entry's name is not valid UTF-8, though the zip says "
                              "it is: rename the file with plain characters and zip it again"
                              ) from None
    except Exception as exc:  # noqa: BLE001 - BadZipFile, struct.error, ValueError, ...
        raise SubmissionError(f"{where}: not a readable zip ({shown(str(exc), 200)})") from None
    with zf:
        infos = zf.infolist()
        if len(infos) > MAX_FILES:
            raise SubmissionError(f"{where}: {len(infos)} entries (at most {MAX_FILES})")
        tree = _Tree(where)
        plan = []
        for info in infos:
            rel = safe_relpath(info.filename.rstrip("/") if info.is_dir() else info.filename,
                               where)
            mode = info.external_attr >> 16
            if stat.S_ISLNK(mode):
                raise SubmissionError(f"{where}: entry {_q(info.filename)} is a link")
            if info.flag_bits & 0x1:
                raise SubmissionError(f"{where}: entry {_q(info.filename)} is encrypted")
            tree.add(rel, info.filename, folder=info.is_dir())
            if not info.is_dir():
                plan.append((info, rel))
        total = 0
        for info, rel in plan:
            buf = bytearray()
            try:
                with zf.open(info) as f:
                    while True:
                        chunk = f.read(65536)
                        if not chunk:
                            break
                        buf += chunk
                        if len(buf) > MAX_FILE:
                            raise SubmissionError(f"{where}: entry {rel} is larger than "
                                                  f"{MAX_FILE} bytes")
                        if len(buf) > MAX_RATIO * max(info.compress_size, 1) + 65536:
                            raise SubmissionError(f"{where}: entry {rel} inflates more than "
                                                  f"{MAX_RATIO}× (a zip bomb)")
            except SubmissionError:
                raise
            except Exception as exc:  # noqa: BLE001 - zlib.error, BadZipFile (CRC), EOFError...
                raise SubmissionError(f"{where}: entry {rel} cannot be read ({_kind(exc)}: "
                                      f"{shown(str(exc), 200)}): zip the files again") from None
            total += len(buf)
            if total > MAX_TOTAL:
                raise SubmissionError(f"{where}: more than {MAX_TOTAL} bytes once unpacked")
            _write(out, rel, bytes(buf), where)


def _what(value: object) -> str:
    """A JSON value named for a message: its kind, and a number's start."""
    if value is None or isinstance(value, bool):
        return json.dumps(value)
    if isinstance(value, (int, float)):
        return f"the number {shown(json.dumps(value), 40)}"
    if isinstance(value, list):
        return "a list"
    return "an object" if isinstance(value, dict) else type(value).__name__


def _from_notebook(name: str, data: bytes, out: Path) -> None:
    try:
        nb = json.loads(data.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise SubmissionError(f"{name}: not a notebook (not UTF-8: byte {exc.start}): save it "
                              "again with Jupyter") from None
    except RecursionError:
        raise SubmissionError(f"{name}: not a notebook (its JSON nests deeper than Python's "
                              "recursion limit; a notebook nests a few levels): save it again "
                              "with Jupyter") from None
    except ValueError as exc:
        raise SubmissionError(f"{name}: not a notebook (JSON: {shown(str(exc), 200)})") from None
    cells = nb.get("cells") if isinstance(nb, dict) else None
    if not isinstance(cells, list):
        raise SubmissionError(f"{name}: a notebook has a 'cells' list")
    tree = _Tree(name)
    planned: list[tuple[PurePosixPath, bytes]] = []
    for i, cell in enumerate(cells):
        if not isinstance(cell, dict) or cell.get("cell_type") != "code":
            continue
        meta = cell.get("metadata")
        tags = meta.get("tags", []) if isinstance(meta, dict) else []
        if not isinstance(tags, list) or "export" not in tags:
            continue
        source = cell.get("source", "")
        if isinstance(source, list):
            for k, item in enumerate(source):
                if not isinstance(item, str):
                    raise SubmissionError(
                        f"{name}: cell {i}'s source is a list holding {_what(item)} at item {k}; "
                        "a cell's source is a string or a list of strings: save the notebook "
                        "again with Jupyter")
            text = "".join(source)
        elif isinstance(source, str):
            text = source
        else:
            raise SubmissionError(f"{name}: cell {i} has no text source: its source is "
                                  f"{_what(source)}, not a string or a list of strings; save "
                                  "the notebook again with Jupyter")
        first, _, rest = text.partition("\n")
        m = _FILE_LINE.match(first)
        if m is None:
            raise SubmissionError(f"{name}: exported cell {i} must start with '# file: "
                                  f"path/in/package.py', not {_q(first, 60)}")
        bad = _SURROGATE.search(rest)
        if bad is not None:
            line = rest.count("\n", 0, bad.start()) + 2
            raise SubmissionError(
                f"{name}: cell {i} holds the lone surrogate U+{ord(bad.group()):04X} at line "
                f"{line} (a JSON escape such as \\udcff without its pair), which no UTF-8 file "
                "can hold: remove it, or write the character itself")
        rel = safe_relpath(m.group(1), f"{name} cell {i}", from_json=True)
        tree.add(rel, m.group(1))
        planned.append((rel, rest.encode("utf-8")))
        if len(planned) > MAX_FILES:
            raise SubmissionError(f"{name}: more than {MAX_FILES} exported cells")
    if not planned:
        raise SubmissionError(f"{name}: no code cell is tagged 'export' (tag the cells to grade "
                              "and start each with '# file: path')")
    for rel, body in planned:
        _write(out, rel, body, name)
