"""Find message and service types by name and build their classes.

A :class:`MessageRegistry` looks types up on a package path
(:class:`ddes.rospack.RosPack`): ``pkg/Type`` is ``<pkg>/msg/Type.msg``, or
one of the seven messages of ``<pkg>/action/<Name>.action``; ``pkg/Srv`` is
``<pkg>/srv/Srv.srv``.  Specs, md5 sums and generated classes are cached
per registry, so a type's class is built once and is the same object on
every lookup.

Registries are layered: ``MessageRegistry(paths)`` holds the packages on
``paths`` and takes every other package from its parent, by default the
*bundled registry* (:func:`default_registry`: ddes's own packages, no
environment variable).  A type that comes entirely from the parent is the
parent's class object, so ``std_msgs/String`` is one class in every world
that does not shadow ``std_msgs``.  The bundled registry is the only
process-wide registry; it is built lazily once, is immutable (nothing can be
added to it; its caches hold only parsed specs and generated,
immutable-by-contract classes) and backs the module-level
:func:`get_message_class` and :func:`get_service_class`.  Packages of your
own go in a registry of their own, one per world: two registries never see
each other's types.  ``DDES_PACKAGE_PATH`` is read only by an explicit
:meth:`MessageRegistry.from_environment` call.

Classes built from a ``message_definition`` text (bags) are cached
process-wide by ``(type, text)``.  That is safe across registries because
such a class is built in a private registry with no package path and no
parent, from the specs in the text alone: it is purely a function of the
key, so no registry's packages can leak into it.
"""

from __future__ import annotations

import enum
import functools
import os
import stat
import threading
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any, cast

from ddes.errors import (
    DdesTypeError,
    DdesValueError,
    InvalidMsgSpec,
    MsgNotFound,
    ResourceLimitError,
)
from ddes.msg.codegen import generate_message_class
from ddes.msg.gentools import (
    SEPARATOR,
    all_dependencies,
    compute_full_text,
    compute_md5,
    compute_srv_md5,
)
from ddes.msg.message import Message, ServiceDefinition
from ddes.msg.parser import ACTION_SUFFIXES, parse_action, parse_msg, parse_srv
from ddes.msg.spec import (
    HEADER,
    HEADER_FULL_NAME,
    ActionSpec,
    MsgSpec,
    SrvSpec,
    bare_msg_type,
    is_builtin,
    is_legal_base_name,
)
from ddes.rospack import PackageNotFound, RosPack, env_package_path
from ddes.time.rostime import Duration, Time

__all__ = [
    "MAX_DEFINITION_BYTES",
    "MAX_NESTING_DEPTH",
    "MessageRegistry",
    "default_registry",
    "definition_facts",
    "get_message_class",
    "get_service_class",
    "message_class_from_definition",
    "parse_definition",
]

_KIND_EXT = {"msg": ".msg", "srv": ".srv", "action": ".action"}

#: Deepest chain of nested message types ddes builds (``A`` holds a ``B`` holds a ``C``...).
#: Real types nest fewer than 10 deep; every tool that walks a message recurses per level.
MAX_NESTING_DEPTH = 64


#: The largest .msg/.srv/.action file ddes reads (1 MiB; real ones hold a few KiB).
MAX_DEFINITION_BYTES = 1 << 20


def read_definition(path: Path) -> str:
    """The text of a .msg/.srv/.action file; bytes that are not UTF-8 raise InvalidMsgSpec.

    genmsg opens the file in the locale's encoding (UTF-8 on ROS systems) and
    lets a ``UnicodeDecodeError`` escape; ddes names the file, line and byte.
    Only a regular file of at most :data:`MAX_DEFINITION_BYTES` is read
    (checked on ``stat`` and while reading); past it
    :class:`~ddes.errors.ResourceLimitError`.
    """
    try:
        st = path.stat()
    except OSError as exc:
        raise InvalidMsgSpec(f"{path}: cannot read the definition ({exc.strerror or exc})"
                             ) from None
    if not stat.S_ISREG(st.st_mode):
        raise InvalidMsgSpec(f"{path}: not a regular file; a definition is a text file")
    too_big = (f"{path}: the definition is larger than {MAX_DEFINITION_BYTES} bytes, the most "
               "ddes reads of a .msg/.srv/.action file (ddes.msg.registry.MAX_DEFINITION_BYTES)")
    if st.st_size > MAX_DEFINITION_BYTES:
        raise ResourceLimitError(f"{too_big} (it is {st.st_size} bytes)")
    with open(path, "rb") as f:
        data = f.read(MAX_DEFINITION_BYTES + 1)
    if len(data) > MAX_DEFINITION_BYTES:
        raise ResourceLimitError(too_big)
    return decode_definition(data, str(path))


def decode_definition(data: bytes, origin: str) -> str:
    """``data`` decoded as UTF-8, or InvalidMsgSpec naming ``origin``, line and byte offset."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        bad = data[exc.start:exc.end]
        raise InvalidMsgSpec(
            f"{origin}:{line}: invalid UTF-8 byte{'s' if len(bad) > 1 else ''} {bad!r} at "
            f"byte offset {exc.start} ({exc.reason}); message definitions must be UTF-8 text: "
            "re-save the file as UTF-8 (or remove the byte, e.g. from a comment)"
        ) from None


def _split_name(name: str, what: str) -> tuple[str, str]:
    if not isinstance(name, str):
        raise MsgNotFound(f"{what} type must be a string like 'pkg/Type', got {name!r}")
    name = name.strip()
    if name == HEADER:
        name = HEADER_FULL_NAME
    pkg, sep, base = name.partition("/")
    if not sep:
        raise MsgNotFound(
            f"{what} type is missing package name: {name!r}; write it as 'pkg/Type' "
            "(e.g. std_msgs/String)"
        )
    if not is_legal_base_name(pkg) or not is_legal_base_name(base):
        raise MsgNotFound(f"invalid {what} type name {name!r}; write it as 'pkg/Type'")
    return pkg, base


class _Parent(enum.Enum):
    """Sentinel: the parent of a registry when none is given (the bundled registry)."""

    DEFAULT = "default_registry()"


class MessageRegistry:
    """Message, service and action types on a package path, and their classes.

    ``MessageRegistry(paths)`` layers the packages found on ``paths`` over
    ``parent`` (default: the bundled registry, :func:`default_registry`).
    A package on ``paths`` wins over one of the same name further down the
    chain (first one wins, as with ``ROS_PACKAGE_PATH``); every other
    package comes from the parent.  A type whose whole dependency closure
    comes from the parent *is the parent's class*: ``std_msgs/String`` is one
    class object in every registry that does not shadow ``std_msgs``, so
    messages flow between worlds (and bags) without conversion.  A parent
    type that depends on a shadowed package (``geometry_msgs/PoseStamped``
    over a user ``std_msgs``) is rebuilt here, exactly as a flat package path
    would resolve it.

    ``parent=None`` (or ``bundled=False``) gives a registry of ``paths``
    alone.  ``rospack`` may replace ``paths`` by a ready
    :class:`~ddes.rospack.RosPack` (its bundled folder counts as one of
    this registry's own folders then).  The environment is read only by
    :meth:`from_environment` or an explicit ``use_env=True`` (default
    False), never later.
    """

    def __init__(self, paths: Iterable[str | os.PathLike[str]] = (), *,
                 parent: MessageRegistry | None | _Parent = _Parent.DEFAULT,
                 use_env: bool = False, bundled: bool = True,
                 rospack: RosPack | None = None) -> None:
        if rospack is not None:
            paths = list(paths)
            if paths or use_env:
                raise DdesValueError("MessageRegistry: pass either paths/use_env or rospack, "
                                     "not both")
            own = rospack
        else:
            own = RosPack(paths, use_env=use_env, bundled=False)
        if parent is _Parent.DEFAULT:
            parent = default_registry() if bundled else None
        elif parent is not None and not bundled:
            raise DdesValueError("MessageRegistry: bundled=False means no parent; "
                                 f"got parent={parent!r}")
        if parent is not None and not isinstance(parent, MessageRegistry):
            raise DdesTypeError(f"MessageRegistry parent must be a MessageRegistry or None, "
                                f"not {type(parent).__name__}")
        self._rospack = own
        self._parent: MessageRegistry | None = parent
        self._frozen = False
        self._added: set[str] = set()
        self._specs: dict[str, MsgSpec] = {}
        self._srv_specs: dict[str, SrvSpec] = {}
        self._actions: dict[str, ActionSpec] = {}
        self._md5: dict[str, str] = {}
        self._full: dict[str, str] = {}
        self._checked: set[str] = set()
        self._inherited: dict[str, bool] = {}
        self._classes: dict[str, type[Message]] = {}
        self._srv_classes: dict[str, type[ServiceDefinition]] = {}

    @classmethod
    def from_environment(cls, environ: Mapping[str, str] = os.environ, *,
                         paths: Iterable[str | os.PathLike[str]] = (),
                         parent: MessageRegistry | None | _Parent = _Parent.DEFAULT
                         ) -> MessageRegistry:
        """A registry of ``paths`` then the folders of ``DDES_PACKAGE_PATH`` in ``environ``.

        ``DDES_PACKAGE_PATH`` is ``os.pathsep``-separated.  It is read once,
        by this call: changing the environment later changes nothing.  This
        is the only place ddes's message registries read the environment.
        """
        return cls([*paths, *env_package_path(environ)], parent=parent)

    @property
    def rospack(self) -> RosPack:
        """This registry's own package path (the parent's is not included)."""
        return self._rospack

    @property
    def parent(self) -> MessageRegistry | None:
        """The registry below this one (None for the bundled registry)."""
        return self._parent

    @property
    def frozen(self) -> bool:
        """True for the shared bundled registry: nothing can be added to it."""
        return self._frozen

    @property
    def search_path(self) -> tuple[Path, ...]:
        """Every folder searched, this registry's first, then the parent's."""
        below = self._parent.search_path if self._parent is not None else ()
        return (*self._rospack.paths, *below)

    def __repr__(self) -> str:
        if self._frozen and self._parent is None:
            return "<bundled MessageRegistry (ddes.msg.default_registry())>"
        own = [str(p) for p in self._rospack.paths]
        parent = "default_registry()" if self._parent is _BUNDLED else repr(self._parent)
        return f"MessageRegistry({own!r}, parent={parent})"

    # -- files ---------------------------------------------------------------------------
    def _holds(self, full: str) -> bool:
        """True if this registry (not a parent) defines type ``full``."""
        return full in self._added or full.partition("/")[0] in self._rospack

    def _chain_has(self, pkg: str, full: str = "") -> bool:
        """True if this registry or one below it has package ``pkg`` (or added type ``full``)."""
        if full in self._added or pkg in self._rospack:
            return True
        return self._parent is not None and self._parent._chain_has(pkg, full)

    def _unknown_package(self, pkg: str, base: str, what: str) -> MsgNotFound:
        searched = ", ".join(str(p) for p in self.search_path) or "(empty path)"
        return MsgNotFound(
            f"Cannot locate {what} [{pkg}/{base}]: unknown package [{pkg}]; searched "
            f"the package path: {searched}. Add the folder holding '{pkg}' to the package "
            "path: MessageRegistry(paths), World(package_path=[...]), or DDES_PACKAGE_PATH "
            "read by MessageRegistry.from_environment()"
        )

    def _package_folder(self, pkg: str, base: str, what: str) -> Path:
        try:
            return self._rospack.get_path(pkg)
        except PackageNotFound:
            raise self._unknown_package(pkg, base, what) from None

    def add_msg_spec(self, spec: MsgSpec) -> None:
        """Register a parsed message spec (used for definitions not on the path).

        Do it before the type (or one using it) is first looked up.  The
        shared bundled registry is immutable: adding to it raises
        :class:`~ddes.errors.DdesTypeError`; build a ``MessageRegistry``
        over it instead.
        """
        if self._frozen:
            raise DdesTypeError(
                f"the bundled registry is shared by every world and cannot be changed (adding "
                f"{spec.full_name}); build MessageRegistry(paths) over it instead"
            )
        self._added.add(spec.full_name)
        self._specs[spec.full_name] = spec
        self._inherited.clear()

    def get_msg_spec(self, type_name: str) -> MsgSpec:
        """The parsed spec of message ``pkg/Type`` (``Header`` means std_msgs/Header)."""
        if type_name in self._specs:
            return self._specs[type_name]
        pkg, base = _split_name(type_name, "message")
        full = f"{pkg}/{base}"
        if full in self._specs:
            return self._specs[full]
        if pkg not in self._rospack:
            if self._parent is None or not self._parent._chain_has(pkg, full):
                raise self._unknown_package(pkg, base, "message")
            inherited = self._parent.get_msg_spec(full)
            self._specs[full] = inherited
            return inherited
        folder = self._package_folder(pkg, base, "message")
        path = folder / "msg" / f"{base}.msg"
        tried = [str(path)]
        spec: MsgSpec | None = None
        if path.is_file():
            spec = parse_msg(read_definition(path), full, filename=str(path))
        else:
            for suffix in ACTION_SUFFIXES:
                stem = base[: -len(suffix)]
                if base.endswith(suffix) and stem:
                    action_path = folder / "action" / f"{stem}.action"
                    tried.append(str(action_path))
                    if action_path.is_file():
                        spec = self.get_action_spec(f"{pkg}/{stem}").messages[suffix]
                        break
            if spec is None:
                raise MsgNotFound(
                    f"Cannot locate message [{base}] in package [{pkg}] ({folder}); "
                    f"searched {', '.join(dict.fromkeys(tried))}"
                )
        self._specs[full] = spec
        return spec

    def get_action_spec(self, type_name: str) -> ActionSpec:
        """The seven message specs generated from action ``pkg/Name``."""
        if type_name in self._actions:
            return self._actions[type_name]
        pkg, base = _split_name(type_name, "action")
        if pkg not in self._rospack and self._parent is not None and self._parent._chain_has(pkg):
            spec = self._parent.get_action_spec(f"{pkg}/{base}")
        else:
            path = self._package_folder(pkg, base, "action") / "action" / f"{base}.action"
            if not path.is_file():
                raise MsgNotFound(
                    f"Cannot locate action [{base}] in package [{pkg}]; searched {path}")
            spec = parse_action(read_definition(path), f"{pkg}/{base}",
                                filename=str(path))
        self._actions[type_name] = spec
        return spec

    def get_srv_spec(self, type_name: str) -> SrvSpec:
        """The parsed spec of service ``pkg/Type``."""
        if type_name in self._srv_specs:
            return self._srv_specs[type_name]
        pkg, base = _split_name(type_name, "service")
        if pkg not in self._rospack and self._parent is not None and self._parent._chain_has(pkg):
            spec = self._parent.get_srv_spec(f"{pkg}/{base}")
        else:
            path = self._package_folder(pkg, base, "service") / "srv" / f"{base}.srv"
            if not path.is_file():
                raise MsgNotFound(
                    f"Cannot locate service [{base}] in package [{pkg}]; searched {path}")
            spec = parse_srv(read_definition(path), f"{pkg}/{base}",
                             filename=str(path))
        self._srv_specs[type_name] = spec
        return spec

    # -- dependencies, md5, full text ----------------------------------------------------
    def _check_closure(self, spec: MsgSpec, stack: tuple[str, ...] = ()) -> None:
        """Load every dependency of ``spec``; unknown or circular types are errors."""
        if spec.full_name in self._checked:
            return
        if len(stack) >= MAX_NESTING_DEPTH:
            chain = " -> ".join((*stack[:3], "...", *stack[-2:], spec.full_name))
            raise InvalidMsgSpec(
                f"{spec.filename or spec.full_name}: message types nest more than "
                f"ddes.msg.registry.MAX_NESTING_DEPTH ({MAX_NESTING_DEPTH}) deep ({chain}); "
                "flatten the definitions (or raise the limit if they are genuine)"
            )
        for f in spec.fields:
            base = bare_msg_type(f.type)
            if is_builtin(base):
                continue
            where = f"{spec.filename or spec.full_name}:{f.line}"
            if base in stack or base == spec.full_name:
                cycle = " -> ".join((*stack, spec.full_name, base))
                raise InvalidMsgSpec(f"{where}: circular message dependency {cycle}")
            try:
                dep = self.get_msg_spec(base)
            except MsgNotFound as exc:
                raise InvalidMsgSpec(
                    f"{where}: unknown type [{f.type}] of field '{f.name}': {exc}"
                ) from exc
            self._check_closure(dep, (*stack, spec.full_name))
        self._checked.add(spec.full_name)

    def _inherits(self, spec: MsgSpec) -> bool:
        """True if every type ``spec`` uses (transitively) comes from the parent.

        Call after :meth:`_check_closure` (no unknown or circular types).
        """
        return self._parent is not None and all(
            self._type_inherited(bare_msg_type(f.type))
            for f in spec.fields if not is_builtin(bare_msg_type(f.type)))

    def _type_inherited(self, type_name: str) -> bool:
        """True if message ``type_name`` is the parent's: it and its closure are not ours."""
        done = self._inherited.get(type_name)
        if done is None:
            spec = self.get_msg_spec(type_name)
            done = not self._holds(spec.full_name) and self._inherits(spec)
            self._inherited[type_name] = done
        return done

    def _md5_of_spec(self, spec: MsgSpec) -> str:
        self._check_closure(spec)
        return compute_md5(spec, self.get_msg_spec, self._md5)

    def md5sum(self, type_name: str) -> str:
        """md5 of message ``pkg/Type``, as genmsg computes it."""
        spec = self.get_msg_spec(type_name)
        if spec.full_name not in self._md5:
            self._check_closure(spec)
            if self._parent is not None and self._type_inherited(spec.full_name):
                self._md5[spec.full_name] = self._parent.md5sum(spec.full_name)
            else:
                self._md5[spec.full_name] = self._md5_of_spec(spec)
        return self._md5[spec.full_name]

    def full_text(self, type_name: str) -> str:
        """``message_definition`` (full text) of message ``pkg/Type``."""
        spec = self.get_msg_spec(type_name)
        if spec.full_name not in self._full:
            self._check_closure(spec)
            if self._parent is not None and self._type_inherited(spec.full_name):
                self._full[spec.full_name] = self._parent.full_text(spec.full_name)
            else:
                self._full[spec.full_name] = compute_full_text(spec, self.get_msg_spec)
        return self._full[spec.full_name]

    def _srv_inherited(self, spec: SrvSpec) -> bool:
        return (self._parent is not None and not self._holds(spec.full_name)
                and self._inherits(spec.request) and self._inherits(spec.response))

    def srv_md5sum(self, type_name: str) -> str:
        """md5 of service ``pkg/Type`` (request text then response text)."""
        spec = self.get_srv_spec(type_name)
        self._check_closure(spec.request)
        self._check_closure(spec.response)
        if self._parent is not None and self._srv_inherited(spec):
            return self._parent.srv_md5sum(spec.full_name)
        return compute_srv_md5(spec, self.get_msg_spec, self._md5)

    # -- classes ---------------------------------------------------------------------------
    def _build(self, spec: MsgSpec) -> type[Message]:
        md5 = self._md5_of_spec(spec)
        full = compute_full_text(spec, self.get_msg_spec)
        return generate_message_class(spec, md5, full, self.get_message_class)

    def get_message_class(self, type_name: str) -> type[Message]:
        """The generated class of message ``pkg/Type``.

        As in genpy, ``time`` and ``duration`` give :class:`ddes.Time` and
        :class:`ddes.Duration`.  A type this registry takes entirely from its
        parent is the parent's class object.  Unknown types raise
        :class:`~ddes.errors.MsgNotFound` saying where ddes looked; a
        malformed definition raises :class:`~ddes.errors.InvalidMsgSpec`.
        """
        cls = self._classes.get(type_name)
        if cls is not None:
            return cls
        if type_name in ("time", "duration"):
            return cast("type[Message]", Time if type_name == "time" else Duration)
        spec = self.get_msg_spec(type_name)
        cls = self._classes.get(spec.full_name)
        if cls is None:
            self._check_closure(spec)
            if self._parent is not None and self._type_inherited(spec.full_name):
                cls = self._parent.get_message_class(spec.full_name)
            else:
                cls = self._build(spec)
            self._classes[spec.full_name] = cls
        self._classes[type_name] = cls
        return cls

    def get_service_class(self, type_name: str) -> type[ServiceDefinition]:
        """The generated class of service ``pkg/Type`` (with request/response classes)."""
        cls = self._srv_classes.get(type_name)
        if cls is not None:
            return cls
        spec = self.get_srv_spec(type_name)
        self._check_closure(spec.request)
        self._check_closure(spec.response)
        if self._parent is not None and self._srv_inherited(spec):
            cls = self._parent.get_service_class(spec.full_name)
            self._srv_classes[type_name] = cls
            return cls
        request = self._build(spec.request)
        response = self._build(spec.response)
        cls = cast("type[ServiceDefinition]", type(spec.short_name, (ServiceDefinition,), {
            "__module__": "ddes.msg.generated",
            "__qualname__": spec.short_name,
            "__doc__": f"Service {spec.full_name} (generated by ddes).\n\n{spec.text}",
            "_type": spec.full_name,
            "_md5sum": self.srv_md5sum(type_name),
            "_request_class": request,
            "_response_class": response,
            "_spec": spec,
        }))
        self._srv_classes[type_name] = cls
        return cls

    # -- listing ---------------------------------------------------------------------------
    def _names_in(self, folder: Path, kind: str) -> list[str]:
        ext = _KIND_EXT[kind]
        sub = folder / kind
        if not sub.is_dir():
            return []
        return sorted(p.name[: -len(ext)] for p in sub.iterdir()
                      if p.is_file() and p.name.endswith(ext))

    def _packages(self) -> list[str]:
        """Every package name on the whole chain, sorted."""
        names = set(self._rospack.list())
        if self._parent is not None:
            names.update(self._parent._packages())
        return sorted(names)

    def list_types(self, package: str, kind: str = "msg") -> list[str]:
        """Full names of the ``kind`` ('msg', 'srv' or 'action') types of ``package``.

        Messages include the seven generated from each .action file (as a
        built ROS workspace lists them), sorted by name.  A package this
        registry does not hold is listed by its parent.
        """
        if kind not in _KIND_EXT:
            raise DdesValueError(f"kind must be 'msg', 'srv' or 'action', not {kind!r}")
        if package not in self._rospack and self._parent is not None \
                and self._parent._chain_has(package):
            return self._parent.list_types(package, kind)
        try:
            folder = self._rospack.get_path(package)
        except PackageNotFound:
            searched = ", ".join(str(p) for p in self.search_path) or "(empty path)"
            raise MsgNotFound(
                f"package '{package}' not found; searched: {searched}. Add its parent folder "
                "to the package path: MessageRegistry(paths), World(package_path=[...]), or "
                "DDES_PACKAGE_PATH read by MessageRegistry.from_environment()"
            ) from None
        names = self._names_in(folder, kind)
        if kind == "msg":
            for action in self._names_in(folder, "action"):
                names.extend(action + s for s in ACTION_SUFFIXES)
            names = sorted(set(names))
        return [f"{package}/{n}" for n in names]

    def list_packages(self, kind: str = "msg") -> list[str]:
        """Packages on the path (this registry's and its parents') that define ``kind`` types."""
        return [p for p in self._packages() if self.list_types(p, kind)]

    def iter_types(self, kind: str = "msg") -> Iterator[str]:
        """Every ``kind`` type on the path, by package then name."""
        for pkg in self._packages():
            yield from self.list_types(pkg, kind)

    def find(self, base_type: str, kind: str = "msg") -> list[str]:
        """Full names ``pkg/base_type`` of every package defining ``base_type``."""
        return [t for pkg in self._packages() for t in self.list_types(pkg, kind)
                if t.split("/", 1)[1] == base_type]


_BUNDLED_LOCK = threading.Lock()
_BUNDLED: MessageRegistry | None = None


def default_registry() -> MessageRegistry:
    """The shared, immutable registry of ddes's bundled packages (``ddes/packages``).

    Built on first use (once, thread-safely) and kept for the life of the
    process; it reads no environment variable.  It is the default parent of
    every :class:`MessageRegistry`, so bundled types are one class object
    everywhere.  Nothing can be added to it: build ``MessageRegistry(paths)``
    (one per world) for your own packages.
    """
    global _BUNDLED
    registry = _BUNDLED
    if registry is None:
        with _BUNDLED_LOCK:
            if _BUNDLED is None:
                built = MessageRegistry(rospack=RosPack((), bundled=True), parent=None)
                built._frozen = True
                _BUNDLED = built
            registry = _BUNDLED
    return registry


def get_message_class(type_name: str, registry: MessageRegistry | None = None) -> type[Message]:
    """The class of message ``pkg/Type`` (genpy/roslib ``get_message_class``).

    Unlike genpy, an unknown type raises :class:`~ddes.errors.MsgNotFound`
    instead of returning None.  Without ``registry``, the bundled registry
    (:func:`default_registry`) answers; it never reads the environment.
    """
    return (default_registry() if registry is None else registry).get_message_class(type_name)


def get_service_class(type_name: str,
                      registry: MessageRegistry | None = None) -> type[ServiceDefinition]:
    """The class of service ``pkg/Type`` (genpy/roslib ``get_service_class``)."""
    return (default_registry() if registry is None else registry).get_service_class(type_name)


def _definition_type(name: object, origin: str) -> str:
    if not isinstance(name, str):
        raise InvalidMsgSpec(f"{origin}: the type must be a string like 'pkg/Type', "
                             f"got {type(name).__name__} {name!r:.80}")
    pkg, sep, base = name.partition("/")
    if not sep or not is_legal_base_name(pkg) or not is_legal_base_name(base):
        raise InvalidMsgSpec(f"{origin}: {name!r:.80} is not a legal message type; write it "
                             "as 'pkg/Type' (letters, digits and '_')")
    return name


def parse_definition(type_name: str, full_text: str | bytes) -> list[MsgSpec]:
    """Split a ``message_definition`` into the specs of the type and its dependencies.

    ``full_text`` may be bytes (a bag's connection header): it must be UTF-8.
    Every failure is :class:`~ddes.errors.InvalidMsgSpec`.
    """
    type_name = _definition_type(type_name, "<message_definition>")
    origin = f"<message_definition of {type_name}>"
    if isinstance(full_text, (bytes, bytearray, memoryview)):
        full_text = decode_definition(bytes(full_text), origin)
    elif not isinstance(full_text, str):
        raise InvalidMsgSpec(f"{origin}: the definition must be str or bytes, not "
                             f"{type(full_text).__name__}")
    sections = full_text.split(f"\n{SEPARATOR}\n")
    specs = [parse_msg(sections[0], type_name, filename=origin)]
    for section in sections[1:]:
        head, _, text = section.partition("\n")
        if not head.startswith("MSG: "):
            raise InvalidMsgSpec(
                f"{origin}: a section after a '=' * 80 separator must start with "
                f"'MSG: pkg/Type', found {head[:60]!r}"
            )
        name = head[5:].strip()
        if name != HEADER:
            name = _definition_type(name, origin)
        specs.append(parse_msg(text, HEADER_FULL_NAME if name == HEADER else name,
                               filename=f"{origin} section {name}"))
    return specs


def _text_registry(type_name: str, full_text: str | bytes) -> MessageRegistry:
    # A private registry with no package path and no parent: every spec comes
    # from the text, so what it gives depends on (type_name, full_text) only and
    # may be shared by every registry (see the module docstring).
    registry = MessageRegistry(rospack=RosPack((), bundled=False), parent=None)
    for spec in parse_definition(type_name, full_text):
        registry.add_msg_spec(spec)
    return registry


@functools.lru_cache(maxsize=256)
def _definition_class(type_name: str, full_text: str | bytes) -> type[Message]:
    return _text_registry(type_name, full_text).get_message_class(type_name)


@functools.lru_cache(maxsize=256)
def _definition_facts(type_name: str, full_text: str | bytes) -> tuple[str, int]:
    registry = _text_registry(type_name, full_text)
    md5 = registry.md5sum(type_name)  # checks the closure: no unknown or circular type
    flat: dict[str, int] = {}

    def fields(name: str) -> int:  # fields once nested types are inlined (codegen's count)
        spec = registry.get_msg_spec(name)
        if spec.full_name not in flat:
            flat[spec.full_name] = sum(
                1 if is_builtin(bare_msg_type(f.type)) else fields(bare_msg_type(f.type))
                for f in spec.fields)
        return flat[spec.full_name]

    root = registry.get_msg_spec(type_name)
    names = [root.full_name, *all_dependencies(root, registry.get_msg_spec)]
    return md5, sum(fields(n) for n in names)


def definition_facts(type_name: str, full_text: str | bytes) -> tuple[str, int]:
    """``(md5sum, cost)`` of ``type_name`` as its ``message_definition`` defines it.

    Nothing is generated: the md5 is genmsg's (the class's ``_md5sum``) and
    ``cost`` the fields code generation would write for the classes of the
    type and its dependencies, nested types inlined as codegen inlines them
    (memoised per type, so a definition whose types each hold the next one
    twice costs one step per type to size).  Reading a bag's connections
    (``rosbag info`` of an MCAP file) needs only the md5; a reader that will
    build the classes can bound their cost first.  Raises
    :class:`~ddes.errors.InvalidMsgSpec` as :func:`message_class_from_definition`
    does for a definition that does not parse or names unknown types.
    """
    if isinstance(full_text, (bytearray, memoryview)):
        full_text = bytes(full_text)
    if not isinstance(type_name, str) or not isinstance(full_text, (str, bytes)):
        parse_definition(type_name, full_text)  # raises InvalidMsgSpec naming the bad value
    return _definition_facts(type_name, full_text)


def message_class_from_definition(type_name: str, full_text: str | bytes, *,
                                  registry: MessageRegistry | None = None) -> type[Message]:
    """A class for ``type_name`` built from its ``message_definition`` text.

    This is how bags and connections carry types that may not be on the
    package path.  With ``registry``, the registry's own class is returned
    when it knows the type with the same md5 sum, so messages read from a
    bag compare equal to (and are instances of) the registry's classes.
    Built classes are cached by ``(type_name, full_text)``; they depend on
    nothing else (no package path), so the cache is shared safely by all
    registries.
    """
    if isinstance(full_text, (bytearray, memoryview)):
        full_text = bytes(full_text)  # hashable, for the cache
    if not isinstance(type_name, str) or not isinstance(full_text, (str, bytes)):
        parse_definition(type_name, full_text)  # raises InvalidMsgSpec naming the bad value
    cls = _definition_class(type_name, full_text)
    if registry is not None:
        try:
            known = registry.get_message_class(type_name)
        except (MsgNotFound, InvalidMsgSpec):
            return cls
        if known._md5sum == cls._md5sum:
            return known
    return cls


def _rebuild_message(type_name: str, full_text: str, state: list[Any]) -> Message:
    """Unpickle helper: rebuild a message from its type, definition and field values.

    A pickle does not say which world it came from: bundled types come back
    as the bundled (shared) classes, others as classes of their definition.
    """
    cls = message_class_from_definition(type_name, full_text, registry=default_registry())
    msg = object.__new__(cls)
    msg.__setstate__(state)
    return msg
