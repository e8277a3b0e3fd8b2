"""The parameter server: a tree of dicts with rosmaster's exact semantics.

Keys are global names (relative keys are taken relative to ``/``; nodes
resolve their ``~private`` and relative names first with
:class:`~ddes.graph.names.NameResolver`).  The rules follow RC
``tools/rosmaster/src/rosmaster/paramserver.py``:

* setting ``/a/b/c`` creates ``/a`` and ``/a/b`` as needed, silently
  replacing any non-dict value on the way;
* setting a dict replaces the whole subtree; the root only takes a dict;
* getting a namespace returns a dict (a deep copy, as XML-RPC would);
* deleting a missing key, or the root, raises KeyError;
* ``search_param(ns, key)`` looks the key's *first* component up in ``ns``,
  then in each parent namespace, and returns the full key there.

Values must be XML-RPC types: bool, int (32-bit signed, as XML-RPC), float,
str, bytes, list/tuple (stored as lists) and dicts with str keys.  Anything
else raises a typed error naming the key, where rospy would fail inside
``xmlrpc.client``.  :meth:`ParamServer.subscribe` reproduces the master's
``paramUpdate`` notifications (``compute_param_updates``); :meth:`load` and
:meth:`dump` behave like ``rosparam load``/``rosparam dump``.
"""

from __future__ import annotations

import copy
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from ddes.errors import (
    DdesKeyError,
    DdesTypeError,
    DdesValueError,
    ROSNameException,
    ROSParamException,
)
from ddes.graph.names import GLOBALNS, SEP, check_name, is_global, is_private, ns_join
from ddes.graph.yamlsafe import DEFAULT_LIMITS, YamlLimits, load_yaml_all, read_bounded

__all__ = ["XMLRPC_INT_MAX", "XMLRPC_INT_MIN", "ParamServer", "ParamSubscription", "to_xmlrpc"]

XMLRPC_INT_MAX = 2**31 - 1
XMLRPC_INT_MIN = -(2**31)

#: ``callback(updated_key, value)``; the value is a parameter value (XML-RPC types).
ParamCallback = Callable[[str, Any], object]


class _Unspecified:
    def __repr__(self) -> str:
        return "<unspecified>"


_UNSPECIFIED = _Unspecified()


# -- values ----------------------------------------------------------------------------------


def to_xmlrpc(value: object, where: str = "value") -> Any:
    """A deep copy of ``value`` made of plain XML-RPC types, or a typed error naming ``where``.

    bool, int, float, str and bytes subclasses become their base type,
    tuples become lists and dict subclasses plain dicts, as a round trip
    through XML-RPC would make them.
    """
    if isinstance(value, bool):
        return bool(value)
    if isinstance(value, int):
        if not XMLRPC_INT_MIN <= value <= XMLRPC_INT_MAX:
            raise DdesValueError(
                f"{where}: int {value} exceeds XML-RPC limits (parameter server integers are "
                f"32-bit signed, {XMLRPC_INT_MIN}..{XMLRPC_INT_MAX}); store it as a float or str"
            )
        return int(value)
    if isinstance(value, float):
        return float(value)
    if isinstance(value, str):
        return str(value)
    if isinstance(value, (bytes, bytearray)):
        return bytes(value)
    if isinstance(value, (list, tuple)):
        return [to_xmlrpc(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, dict):
        out: dict[str, Any] = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise DdesTypeError(
                    f"{where}: dictionary key must be string, got {type(k).__name__} {k!r} "
                    f"(XML-RPC structs have string keys)"
                )
            out[str(k)] = to_xmlrpc(v, f"{where}/{k}")
        return out
    if value is None:
        raise DdesTypeError(
            f"{where}: None cannot be stored on the parameter server (XML-RPC has no null; "
            f"rospy fails with 'cannot marshal None'); delete the parameter instead"
        )
    raise DdesTypeError(
        f"{where}: cannot store {type(value).__name__} {value!r} on the parameter server; "
        f"use bool, int, float, str, bytes, list or dict (convert numpy scalars with "
        f"int()/float()/bool())"
    )


# -- subscriptions ------------------------------------------------------------------------------


@dataclass(eq=False)
class ParamSubscription:
    """One :meth:`ParamServer.subscribe` registration; :meth:`unsubscribe` ends it."""

    server: ParamServer
    key: str
    callback: ParamCallback
    caller_id: str | None

    def unsubscribe(self) -> None:
        """Stop receiving updates (idempotent)."""
        self.server._unsubscribe(self)


def _slash(key: str) -> str:
    return key if key == SEP else key + SEP


def _all_keys(prefix: str, value: dict[str, Any], out: list[str]) -> list[str]:
    for k, v in value.items():
        sub = ns_join(prefix, k) + SEP
        out.append(sub)
        if type(v) is dict:
            _all_keys(sub, v, out)
    return out


# -- the server ---------------------------------------------------------------------------------


class ParamServer:
    """The master's parameter tree (one per world)."""

    def __init__(self) -> None:
        self._tree: dict[str, Any] = {}
        self._subs: dict[str, list[ParamSubscription]] = {}

    # -- keys ------------------------------------------------------------------------------
    @staticmethod
    def _key(key: object) -> str:
        """Canonical global form of ``key`` (relative keys are relative to ``/``)."""
        if not isinstance(key, str):
            raise DdesTypeError(f"parameter key must be a str, got {type(key).__name__} {key!r}")
        if is_private(key):
            raise ROSNameException(
                f"private parameter name {key!r} has no meaning on the parameter server; "
                f"resolve it against the node name first (NameResolver.resolve)"
            )
        parts = [x for x in key.split(SEP) if x]
        return SEP + SEP.join(parts)

    @staticmethod
    def _parts(key: str) -> list[str]:
        return [x for x in key.split(SEP) if x]

    # -- the rosmaster API -----------------------------------------------------------------
    def set_param(self, key: str, value: Any, *, caller_id: str | None = None) -> None:
        """Set ``key`` to ``value``; a dict replaces the whole subtree.

        ``caller_id`` (the setting node) is not notified of its own change,
        as the master skips it.  Illegal names raise ROSNameException
        (rospy only warns).
        """
        k = self._key(key)
        check_name(key, "parameter name")
        self._set(k, to_xmlrpc(value, f"parameter {k}"), caller_id)

    def _set(self, key: str, value: Any, caller_id: str | None) -> None:
        if key == GLOBALNS:
            if type(value) is not dict:
                raise DdesTypeError(
                    f"cannot set root of parameter tree to non-dictionary ({value!r}); "
                    f"set a dict on '/' or set individual parameters"
                )
            self._tree = value
        else:
            parts = self._parts(key)
            d = self._tree
            for ns in parts[:-1]:
                sub = d.get(ns)
                if type(sub) is not dict:
                    sub = d[ns] = {}  # implicit conversion of a value into a namespace
                d = sub
            d[parts[-1]] = value
        self._notify(key, value, caller_id)

    def get_param(self, key: str, default: Any = _UNSPECIFIED) -> Any:
        """The value at ``key`` (a deep copy; a namespace gives a dict).

        A missing key returns ``default`` if given, else raises DdesKeyError
        (a KeyError, as ``rospy.get_param`` raises).
        """
        k = self._key(key)
        try:
            return copy.deepcopy(self._lookup(k))
        except KeyError:
            if default is not _UNSPECIFIED:
                return default
            raise DdesKeyError(
                f"parameter {k} is not set; set it first or pass a default "
                f"(get_param({key!r}, default))"
            ) from None

    def _lookup(self, key: str) -> Any:
        val: Any = self._tree
        for ns in self._parts(key):
            if type(val) is not dict or ns not in val:
                raise KeyError(key)
            val = val[ns]
        return val

    def has_param(self, key: str) -> bool:
        """True if ``key`` is a parameter or a namespace (``/`` always is)."""
        try:
            self._lookup(self._key(key))
        except KeyError:
            return False
        return True

    def delete_param(self, key: str) -> None:
        """Delete ``key`` (a value or a whole namespace); KeyError if missing or the root."""
        k = self._key(key)
        if k == GLOBALNS:
            raise DdesKeyError(
                "cannot delete root of parameter tree; set '/' to {} to clear everything"
            )
        parts = self._parts(k)
        try:
            parent = self._lookup(SEP + SEP.join(parts[:-1]))
        except KeyError:
            parent = None
        if type(parent) is not dict or parts[-1] not in parent:
            raise DdesKeyError(f"parameter {k} is not set, so it cannot be deleted")
        del parent[parts[-1]]
        self._notify(k, {}, None)

    def search_param(self, ns: str, key: str) -> str | None:
        """Search ``key`` from ``ns`` up to ``/``, as the master's ``searchParam``.

        Only the key's first component is looked up: in ``ns`` itself, then
        in each parent namespace.  On a match the full key in that namespace
        is returned, even if the rest of it does not exist yet; otherwise
        None.  A global key is returned if set.  The master passes the
        *caller's node name* as ``ns``, so a node's private namespace is
        searched first.  ddes returns canonical names (rosmaster joins the
        key as given, keeping any ``//``).
        """
        if not isinstance(key, str) or not key or is_private(key):
            raise ROSNameException(
                f"invalid key {key!r} for search_param: give a non-empty relative name"
            )
        if not isinstance(ns, str) or not is_global(ns):
            raise ROSNameException(
                f"namespace must be global for search_param, got {ns!r}; use the node's name"
            )
        if is_global(key):
            k = self._key(key)
            return k if self.has_param(k) else None
        key_parts = self._parts(key)
        ns_parts = self._parts(ns)
        for i in range(len(ns_parts), -1, -1):
            if self.has_param(SEP + SEP.join(ns_parts[:i] + key_parts[:1])):
                return SEP + SEP.join(ns_parts[:i] + key_parts)
        return None

    def get_param_names(self) -> list[str]:
        """Sorted full names of every leaf (empty namespaces have no name)."""
        names: list[str] = []

        def walk(prefix: str, d: dict[str, Any]) -> None:
            for k, v in d.items():
                if type(v) is dict:
                    walk(ns_join(prefix, k), v)
                else:
                    names.append(ns_join(prefix, k))

        walk(SEP, self._tree)
        return sorted(names)

    # -- notifications -----------------------------------------------------------------------
    def subscribe(
        self, callback: ParamCallback, key: str = GLOBALNS, *, caller_id: str | None = None
    ) -> ParamSubscription:
        """Call ``callback(updated_key, value)`` when anything at or under ``key`` changes.

        The updates are the master's ``paramUpdate`` calls
        (``compute_param_updates``): a change inside the subscribed
        namespace reports the changed key and its new value; a dict set
        above it reports the subscribed key's new sub-value, or ``{}`` if it
        vanished; a deletion reports ``{}``.  Keys are canonical (no
        trailing slash).  As in rosmaster, overwriting a parent with a
        non-dict value does *not* notify deeper subscribers.  Subscribe to
        ``/`` (the default) to hear every change.
        """
        if not callable(callback):
            raise DdesTypeError(f"subscribe needs a callable, got {callback!r}")
        sub = ParamSubscription(self, _slash(self._key(key)), callback, caller_id)
        self._subs.setdefault(sub.key, []).append(sub)
        return sub

    def _unsubscribe(self, sub: ParamSubscription) -> None:
        subs = self._subs.get(sub.key, [])
        if sub in subs:
            subs.remove(sub)
            if not subs:
                del self._subs[sub.key]

    def _notify(self, key: str, value: Any, caller_id: str | None) -> None:
        if not self._subs:
            return
        pkey = _slash(key)
        all_keys = _all_keys(pkey, value, []) if type(value) is dict else None
        updates: list[tuple[list[ParamSubscription], str, Any]] = []
        for sub_key, subs in self._subs.items():
            if pkey.startswith(sub_key):
                targets = [s for s in subs if caller_id is None or s.caller_id != caller_id]
                updates.append((targets, pkey, value))
            elif all_keys is not None and sub_key.startswith(pkey) and sub_key not in all_keys:
                updates.append((list(subs), sub_key, {}))
        if all_keys is not None:
            for k in all_keys:
                if k in self._subs:
                    val = value
                    for ns in self._parts(k[len(pkey) :]):
                        val = val[ns]
                    updates.append((list(self._subs[k]), k, val))
        for targets, k, val in updates:
            name = k if k == SEP else k[:-1]
            for s in targets:
                s.callback(name, copy.deepcopy(val))

    # -- rosparam load / dump ---------------------------------------------------------------------
    def load(self, source: str | os.PathLike[str], ns: str = GLOBALNS, *,
             limits: YamlLimits = DEFAULT_LIMITS) -> list[tuple[str, Any]]:
        """Load YAML as ``rosparam load`` does; ``source`` is YAML text or a path.

        A ``str`` is YAML text; a :class:`pathlib.Path` (any ``os.PathLike``)
        is read as a file.  Each document goes into ``ns`` (or
        ``ns/_ns`` if it has a ``_ns`` key).  Dicts are *merged* leaf by leaf
        (rosparam's ``set_param_raw``), so an empty dict sets nothing;
        anything else replaces the value at ``ns``.  ``!degrees 90``,
        ``!radians pi/2``, ``deg(90)`` and ``rad(pi)`` become radians.
        Returns the ``(namespace, document)`` pairs loaded.  ``limits`` bound
        the file size, alias expansion and nesting (see
        :mod:`ddes.graph.yamlsafe`); past them :class:`~ddes.errors.ResourceLimitError`.
        """
        if isinstance(source, os.PathLike):
            path = Path(source)
            if not path.exists():
                raise ROSParamException(f"file [{path}] does not exist")
            data = read_bounded(path, what="parameter file", error=ROSParamException,
                                limit=limits.max_bytes)
            try:
                text = data.decode("utf-8")
            except UnicodeDecodeError as exc:
                raise ROSParamException(
                    f"parameter file [{path}] is not UTF-8 text ({exc.reason} at byte "
                    f"{exc.start}); save it as UTF-8") from None
        elif isinstance(source, str):
            text = source
        else:
            raise DdesTypeError(f"load needs YAML text (str) or a path, got {source!r}")
        base = self._key(ns)
        try:
            docs = load_yaml_all(text, angles=True, limits=limits)
        except yaml.YAMLError as exc:
            raise ROSParamException(f"invalid YAML: {exc}") from exc
        loaded: list[tuple[str, Any]] = []
        for doc in docs:
            if doc is None:
                doc = {}  # an empty document loads nothing (roslaunch's reading of #3162)
            target = base
            if type(doc) is dict and "_ns" in doc:
                doc = dict(doc)
                target = self._key(ns_join(base, str(doc.pop("_ns"))))
            if target == GLOBALNS and type(doc) is not dict:
                hint = " (to load a file, pass a pathlib.Path)" if isinstance(source, str) else ""
                raise ROSParamException(f"global / can only be set to a dictionary{hint}")
            self._set_raw(target, doc)
            loaded.append((target, doc))
        return loaded

    def _set_raw(self, key: str, value: Any) -> None:
        if type(value) is dict:
            for k, v in value.items():
                if not isinstance(k, str):
                    raise ROSParamException(
                        f"YAML dictionaries must have string keys. Invalid dictionary is:\n{value}"
                    )
                self._set_raw(self._key(ns_join(key, k)), v)
        else:
            self._set(key, to_xmlrpc(value, f"parameter {key}"), None)

    def dump(self, ns: str = GLOBALNS) -> str:
        """YAML text of ``ns`` as ``rosparam dump`` writes it (``yaml.dump``: block style, sorted)."""
        return yaml.safe_dump(self.get_param(ns), default_flow_style=False, sort_keys=True)

    def __repr__(self) -> str:
        return f"ParamServer({len(self.get_param_names())} parameters)"
