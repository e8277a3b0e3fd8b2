"""A script's own folder on its ``sys.path``: its helper modules import as script code.

Python puts the folder of the script it runs at ``sys.path[0]``, so a ROS script's
``import helpers`` finds ``helpers.py`` beside it (rospy_tutorials and actionlib's tests do
this).  A ddes script's ``sys.path`` is a list of its own: that folder, then the process's
path; what the script adds to it (``sys.path.append(os.path.dirname(__file__) + "/lib")``)
stays its own.  An ``import`` the script (or one of its helpers) makes looks in the folders
of that list which are not on the process's path first, as Python would, and loads what it
finds there as the script's code: with the script's ``__builtins__``, so a helper's
``import rospy`` is ddes's rospy too, and with one module object per script run, never put in
``sys.modules`` (two scripts' ``helpers.py`` stay apart).  A package there (a folder with
``__init__.py``) imports with its submodules and relative imports.
"""

from __future__ import annotations

import sys
import types
from pathlib import Path
from typing import Any

__all__ = ["LocalModules"]


class LocalModules:
    """The modules one script run loads from its own folders (see the module docstring)."""

    def __init__(self, path: list[str]) -> None:
        #: The script's ``sys.path`` (its folder first).
        self.path = path
        self.modules: dict[str, types.ModuleType] = {}
        self._where: dict[str, Path | None] = {}
        self.builtins: dict[str, Any] = {}

    def _folders(self) -> list[Path]:
        real = set(sys.path)
        return [Path(p) for p in self.path if isinstance(p, str) and p not in real]

    def find(self, top: str) -> Path | None:
        """The file of local module ``top`` (``top.py`` or ``top/__init__.py``), or None."""
        if top in self._where:
            return self._where[top]
        found: Path | None = None
        if top.isidentifier():
            for folder in self._folders():
                for candidate in (folder / top / "__init__.py", folder / f"{top}.py"):
                    if candidate.is_file():
                        found = candidate
                        break
                if found is not None:
                    break
        self._where[top] = found
        return found

    def import_(self, name: str, fromlist: Any, level: int, globals_: Any) -> Any:
        """``__import__`` for a local module, or None when ``name`` is not one."""
        if level:
            package = (globals_ or {}).get("__package__") or ""
            if package.split(".")[0] not in self.modules:
                return None
            base = package.split(".")
            if level > 1:
                base = base[:-(level - 1)]
            full = ".".join([*base, name]) if name else ".".join(base)
        else:
            full = name
            if self.find(name.partition(".")[0]) is None:
                return None
        module = self._load(full)
        for item in fromlist or ():
            if item != "*" and hasattr(module, "__path__") and not hasattr(module, item):
                try:
                    self._load(f"{full}.{item}")
                except ModuleNotFoundError:
                    pass
        if fromlist or level:
            return module
        return self.modules[full.partition(".")[0]]

    def _load(self, full: str) -> types.ModuleType:
        if full in self.modules:
            return self.modules[full]
        parent_name, _, last = full.rpartition(".")
        if parent_name:
            parent = self._load(parent_name)
            folder = Path(next(iter(getattr(parent, "__path__", [])), ""))
            file: Path | None = None
            for candidate in (folder / last / "__init__.py", folder / f"{last}.py"):
                if folder.parts and candidate.is_file():
                    file = candidate
                    break
        else:
            file = self.find(full)
        if file is None:
            raise ModuleNotFoundError(f"No module named '{full}'", name=full)
        module = types.ModuleType(full)
        is_package = file.name == "__init__.py"
        module.__file__ = str(file)
        module.__builtins__ = self.builtins  # type: ignore[attr-defined]
        module.__package__ = full if is_package else parent_name
        if is_package:
            module.__path__ = [str(file.parent)]
        self.modules[full] = module
        code = compile(file.read_text(encoding="utf-8"), str(file), "exec")
        try:
            exec(code, module.__dict__)  # noqa: S102 - the user's own module, as import runs it
        except BaseException:
            del self.modules[full]
            raise
        if parent_name:
            setattr(self.modules[parent_name], last, module)
        return module
