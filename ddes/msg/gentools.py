"""md5 sums and full definition text, exactly as genmsg's ``gentools`` computes them.

* md5 text: constants first (``type NAME=value``, value as written), then the
  fields: ``type name`` for builtins (array suffix kept), ``<md5 of the
  nested type> name`` for messages (array brackets dropped); joined with
  ``\\n``, surrounding whitespace stripped.  A service's md5 hashes the
  request text then the response text, with nothing in between.
* full text: the type's own text, then for each dependency (depth first,
  in field order, each type once) a line of 80 ``=``, a line
  ``MSG: pkg/Type`` and that type's text; the very last newline removed.

Every function takes ``get_spec``, which returns the :class:`MsgSpec` of a
resolved message type name, so the same code serves files on a package
path and the ``message_definition`` text of a bag connection.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable

from ddes.msg.spec import MsgSpec, SrvSpec, bare_msg_type, is_builtin

__all__ = [
    "SEPARATOR",
    "all_dependencies",
    "compute_full_text",
    "compute_md5",
    "compute_md5_text",
    "compute_srv_md5",
]

#: The line between the types of a full text (80 ``=``).
SEPARATOR = "=" * 80

GetSpec = Callable[[str], MsgSpec]


def compute_md5_text(spec: MsgSpec, md5_of: Callable[[str], str]) -> str:
    """The text genmsg hashes for ``spec``; ``md5_of`` gives a nested type's md5."""
    lines = [f"{c.type} {c.name}={c.val_text}" for c in spec.constants]
    for f in spec.fields:
        base = bare_msg_type(f.type)
        if is_builtin(base):
            lines.append(f"{f.type} {f.name}")
        else:
            lines.append(f"{md5_of(base)} {f.name}")
    return "\n".join(lines).strip()


def compute_md5(spec: MsgSpec, get_spec: GetSpec,
                cache: dict[str, str] | None = None) -> str:
    """md5 of a message spec (genmsg ``compute_md5``); ``cache`` memoises by type name."""
    memo: dict[str, str] = {} if cache is None else cache

    def md5_of(name: str) -> str:
        if name not in memo:
            memo[name] = compute_md5(get_spec(name), get_spec, memo)
        return memo[name]

    return hashlib.md5(compute_md5_text(spec, md5_of).encode("utf-8")).hexdigest()


def compute_srv_md5(spec: SrvSpec, get_spec: GetSpec,
                    cache: dict[str, str] | None = None) -> str:
    """md5 of a service: request text then response text through one hash."""
    memo: dict[str, str] = {} if cache is None else cache

    def md5_of(name: str) -> str:
        if name not in memo:
            memo[name] = compute_md5(get_spec(name), get_spec, memo)
        return memo[name]

    h = hashlib.md5(compute_md5_text(spec.request, md5_of).encode("utf-8"))
    h.update(compute_md5_text(spec.response, md5_of).encode("utf-8"))
    return h.hexdigest()


def all_dependencies(spec: MsgSpec, get_spec: GetSpec) -> list[str]:
    """Message types ``spec`` depends on, depth first in field order, each once."""
    out: list[str] = []

    def visit(s: MsgSpec) -> None:
        for f in s.fields:
            base = bare_msg_type(f.type)
            if is_builtin(base) or base in out:
                continue  # a type already listed has had its dependencies listed too
            out.append(base)
            visit(get_spec(base))

    visit(spec)
    return out


def compute_full_text(spec: MsgSpec, get_spec: GetSpec) -> str:
    """The ``message_definition`` of ``spec`` (genmsg ``compute_full_text``)."""
    parts = [spec.text, "\n"]
    for dep in all_dependencies(spec, get_spec):
        parts.append(f"{SEPARATOR}\nMSG: {dep}\n{get_spec(dep).text}\n")
    return "".join(parts)[:-1]
