"""Find message and service types by name and build their classes.

A :class:`MessageRegistry` looks types up on a package path
(:class:`ddes.rospack.RosPack`): ``pkg/Type`` is ``<pkg>/msg/Type.msg``, or
one of the seven messages of ``<pkg>/action/<Name>.action``; ``pkg/Srv`` is
``<pkg>/srv/Srv.srv``.  Specs, md5 sums and generated classes are cached
per registry, so a type's class is built once and is the same object on
every lookup.

The *default registry* (bundled packages + ``DDES_PACKAGE_PATH``) is created
lazily on first use and then kept for the life of the process; it backs the
module-level :func:`get_message_class` and :func:`get_service_class`.  Pass
``registry=`` (or build ``MessageRegistry(paths)``) for anything else.
Classes built from a ``message_definition`` text (bags) are cached by
``(type, text)``; both caches hold only generated, immutable-by-contract
things.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any, cast

from ddes.errors import InvalidMsgSpec, MsgNotFound
from ddes.msg.codegen import generate_message_class
from ddes.msg.gentools import SEPARATOR, compute_full_text, compute_md5, compute_srv_md5
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
from ddes.rospack import PackageNotFound, RosPack
from ddes.time.rostime import Duration, Time

__all__ = [
    "MessageRegistry",
    "default_registry",
    "get_message_class",
    "get_service_class",
    "message_class_from_definition",
    "parse_definition",
]

_KIND_EXT = {"msg": ".msg", "srv": ".srv", "action": ".action"}


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


class MessageRegistry:
    """Message, service and action types on a package path, and their classes.

    ``paths`` come first, then ``DDES_PACKAGE_PATH`` (unless
    ``use_env=False``), then ddes's bundled packages (unless
    ``bundled=False``); the first package of a name wins.
    """

    def __init__(self, paths: Iterable[str | os.PathLike[str]] = (), *, use_env: bool = True,
                 bundled: bool = True, rospack: RosPack | None = None) -> None:
        self.rospack = rospack if rospack is not None else RosPack(
            paths, use_env=use_env, bundled=bundled)
        self._specs: dict[str, MsgSpec] = {}
        self._srv_specs: dict[str, SrvSpec] = {}
        self._actions: dict[str, ActionSpec] = {}
        self._md5: dict[str, str] = {}
        self._full: dict[str, str] = {}
        self._checked: set[str] = set()
        self._classes: dict[str, type[Message]] = {}
        self._srv_classes: dict[str, type[ServiceDefinition]] = {}

    def __repr__(self) -> str:
        return f"MessageRegistry({[str(p) for p in self.rospack.paths]!r})"

    # -- files ---------------------------------------------------------------------------
    def _package_folder(self, pkg: str, base: str, what: str) -> Path:
        try:
            return self.rospack.get_path(pkg)
        except PackageNotFound:
            searched = ", ".join(str(p) for p in self.rospack.paths) or "(empty path)"
            raise MsgNotFound(
                f"Cannot locate {what} [{pkg}/{base}]: unknown package [{pkg}]; searched "
                f"the package path: {searched}. Add the folder holding '{pkg}' to "
                "DDES_PACKAGE_PATH or pass it to MessageRegistry(paths)"
            ) from None

    def add_msg_spec(self, spec: MsgSpec) -> None:
        """Register a parsed message spec (used for definitions not on the path)."""
        self._specs[spec.full_name] = spec

    def get_msg_spec(self, type_name: str) -> MsgSpec:
        """The parsed spec of message ``pkg/Type`` (``Header`` means std_msgs/Header)."""
        if type_name in self._specs:
            return self._specs[type_name]
        pkg, base = _split_name(type_name, "message")
        full = f"{pkg}/{base}"
        if full in self._specs:
            return self._specs[full]
        folder = self._package_folder(pkg, base, "message")
        path = folder / "msg" / f"{base}.msg"
        tried = [str(path)]
        spec: MsgSpec | None = None
        if path.is_file():
            spec = parse_msg(path.read_text(encoding="utf-8"), full, filename=str(path))
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
        path = self._package_folder(pkg, base, "action") / "action" / f"{base}.action"
        if not path.is_file():
            raise MsgNotFound(f"Cannot locate action [{base}] in package [{pkg}]; searched {path}")
        spec = parse_action(path.read_text(encoding="utf-8"), f"{pkg}/{base}",
                            filename=str(path))
        self._actions[type_name] = spec
        return spec

    def get_srv_spec(self, type_name: str) -> SrvSpec:
        """The parsed spec of service ``pkg/Type``."""
        if type_name in self._srv_specs:
            return self._srv_specs[type_name]
        pkg, base = _split_name(type_name, "service")
        path = self._package_folder(pkg, base, "service") / "srv" / f"{base}.srv"
        if not path.is_file():
            raise MsgNotFound(f"Cannot locate service [{base}] in package [{pkg}]; searched {path}")
        spec = parse_srv(path.read_text(encoding="utf-8"), f"{pkg}/{base}", filename=str(path))
        self._srv_specs[type_name] = spec
        return spec

    # -- dependencies, md5, full text ----------------------------------------------------
    def _check_closure(self, spec: MsgSpec, stack: tuple[str, ...] = ()) -> None:
        """Load every dependency of ``spec``; unknown or circular types are errors."""
        if spec.full_name in self._checked:
            return
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

    def _md5_of_spec(self, spec: MsgSpec) -> str:
        self._check_closure(spec)
        return compute_md5(spec, self.get_msg_spec, self._md5)

    def md5sum(self, type_name: str) -> str:
        """md5 of message ``pkg/Type``, as genmsg computes it."""
        spec = self.get_msg_spec(type_name)
        if spec.full_name not in self._md5:
            self._md5[spec.full_name] = self._md5_of_spec(spec)
        return self._md5[spec.full_name]

    def full_text(self, type_name: str) -> str:
        """``message_definition`` (full text) of message ``pkg/Type``."""
        spec = self.get_msg_spec(type_name)
        if spec.full_name not in self._full:
            self._check_closure(spec)
            self._full[spec.full_name] = compute_full_text(spec, self.get_msg_spec)
        return self._full[spec.full_name]

    def srv_md5sum(self, type_name: str) -> str:
        """md5 of service ``pkg/Type`` (request text then response text)."""
        spec = self.get_srv_spec(type_name)
        self._check_closure(spec.request)
        self._check_closure(spec.response)
        return compute_srv_md5(spec, self.get_msg_spec, self._md5)

    # -- classes ---------------------------------------------------------------------------
    def _build(self, spec: MsgSpec) -> type[Message]:
        md5 = self._md5_of_spec(spec)
        full = compute_full_text(spec, self.get_msg_spec)
        return generate_message_class(spec, md5, full, self.get_message_class)

    def get_message_class(self, type_name: str) -> type[Message]:
        """The generated class of message ``pkg/Type``.

        As in genpy, ``time`` and ``duration`` give :class:`ddes.Time` and
        :class:`ddes.Duration`.  Unknown types raise
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

    def list_types(self, package: str, kind: str = "msg") -> list[str]:
        """Full names of the ``kind`` ('msg', 'srv' or 'action') types of ``package``.

        Messages include the seven generated from each .action file (as a
        built ROS workspace lists them), sorted by name.
        """
        if kind not in _KIND_EXT:
            raise ValueError(f"kind must be 'msg', 'srv' or 'action', not {kind!r}")
        try:
            folder = self.rospack.get_path(package)
        except PackageNotFound as exc:
            raise MsgNotFound(str(exc)) from None
        names = self._names_in(folder, kind)
        if kind == "msg":
            for action in self._names_in(folder, "action"):
                names.extend(action + s for s in ACTION_SUFFIXES)
            names = sorted(set(names))
        return [f"{package}/{n}" for n in names]

    def list_packages(self, kind: str = "msg") -> list[str]:
        """Packages on the path that define ``kind`` types, sorted."""
        return [p for p in self.rospack.list() if self.list_types(p, kind)]

    def iter_types(self, kind: str = "msg") -> Iterator[str]:
        """Every ``kind`` type on the path, by package then name."""
        for pkg in self.rospack.list():
            yield from self.list_types(pkg, kind)

    def find(self, base_type: str, kind: str = "msg") -> list[str]:
        """Full names ``pkg/base_type`` of every package defining ``base_type``."""
        return [t for pkg in self.rospack.list() for t in self.list_types(pkg, kind)
                if t.split("/", 1)[1] == base_type]


@functools.lru_cache(maxsize=1)
def default_registry() -> MessageRegistry:
    """The process-wide registry: bundled packages plus ``DDES_PACKAGE_PATH``.

    Created on first use and kept; ``DDES_PACKAGE_PATH`` is read then.
    """
    return MessageRegistry()


def get_message_class(type_name: str, registry: MessageRegistry | None = None) -> type[Message]:
    """The class of message ``pkg/Type`` (genpy/roslib ``get_message_class``).

    Unlike genpy, an unknown type raises :class:`~ddes.errors.MsgNotFound`
    instead of returning None.
    """
    return (registry or default_registry()).get_message_class(type_name)


def get_service_class(type_name: str,
                      registry: MessageRegistry | None = None) -> type[ServiceDefinition]:
    """The class of service ``pkg/Type`` (genpy/roslib ``get_service_class``)."""
    return (registry or default_registry()).get_service_class(type_name)


def parse_definition(type_name: str, full_text: str) -> list[MsgSpec]:
    """Split a ``message_definition`` into the specs of the type and its dependencies."""
    sections = full_text.split(f"\n{SEPARATOR}\n")
    origin = f"<message_definition of {type_name}>"
    specs = [parse_msg(sections[0], type_name, filename=origin)]
    for section in sections[1:]:
        head, _, text = section.partition("\n")
        if not head.startswith("MSG: "):
            raise InvalidMsgSpec(
                f"{origin}: a section after a '=' * 80 separator must start with "
                f"'MSG: pkg/Type', found {head[:60]!r}"
            )
        name = head[5:].strip()
        specs.append(parse_msg(text, HEADER_FULL_NAME if name == HEADER else name,
                               filename=f"{origin} section {name}"))
    return specs


@functools.lru_cache(maxsize=256)
def _definition_class(type_name: str, full_text: str) -> type[Message]:
    registry = MessageRegistry(rospack=RosPack((), use_env=False, bundled=False))
    for spec in parse_definition(type_name, full_text):
        registry.add_msg_spec(spec)
    return registry.get_message_class(type_name)


def message_class_from_definition(type_name: str, full_text: str, *,
                                  registry: MessageRegistry | None = None) -> type[Message]:
    """A class for ``type_name`` built from its ``message_definition`` text.

    This is how bags and connections carry types that may not be on the
    package path.  With ``registry``, the registry's own class is returned
    when it knows the type with the same md5 sum, so messages read from a
    bag compare equal to (and are instances of) the registry's classes.
    Built classes are cached by ``(type_name, full_text)``.
    """
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
    """Unpickle helper: rebuild a message from its type, definition and field values."""
    cls = message_class_from_definition(type_name, full_text, registry=default_registry())
    msg = object.__new__(cls)
    msg.__setstate__(state)
    return msg
