"""``rospack``: find packages and their dependencies on the console's package path.

Output follows rospack (ros/rospack ``src/rospack_cmdline.cpp``, as
Debian's Noetic build prints it):

* ``find PKG`` prints the package's folder;
* ``list`` prints ``name path`` lines sorted by name, ``list-names`` the names;
* ``depends1 PKG`` (alias ``deps1``) prints the direct dependencies read from
  ``package.xml`` (``<run_depend>``, then ``<exec_depend>``, then ``<depend>``;
  :meth:`ddes.rospack.RosPack.depends1`), ``depends PKG`` (``deps``) every
  dependency, depth first, each after its own dependencies (rospack's
  post-order);
* ``depends-on PKG`` lists the packages that depend on PKG, directly or not,
  ``depends-on1 PKG`` those that depend on it directly;
* ``help`` prints rospack's usage.

Errors print as rospack prints them, on stderr with exit code 1:
``[rospack] Error: package 'x' not found``, ``[rospack] Error: no such
package x`` (``depends*``), ``[rospack] Error: no package given``,
``[rospack] Error: invalid option(s) given``.  Without a package,
the package of the console's working directory (``roscd``) is used, as
rospack uses the current directory's.  ``-q`` quiets the errors.

ddes specifics (see docs/console.md): the package path is ddes's
(:class:`~ddes.rospack.RosPack`, never ``ROS_PACKAGE_PATH``); a dependency
that is not on it is skipped, as rospack skips one that rosdep resolves to
a system package (ddes bundles no build tools such as ``message_runtime``);
``depends-on`` lists the packages sorted by name (rospack's order is its hash
table's).  The commands about compiler flags, exports, plugins, rosdep and
version control are not offered.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ddes.errors import DdesError, ROSConsoleError
from ddes.rospack import InvalidManifest, PackageNotFound

if TYPE_CHECKING:
    from ddes.console.tooling import ToolContext
    from ddes.rospack import RosPack

__all__ = ["TOOLS", "USAGE", "depends", "depends_on", "rospack"]

#: What ``rospack help`` prints (Debian's rospack 2.6).
USAGE = """USAGE: rospack <command> [options] [package]
  Allowed commands:
    help
    cflags-only-I     [--deps-only] [package]
    cflags-only-other [--deps-only] [package]
    depends           [package] (alias: deps)
    depends-indent    [package] (alias: deps-indent)
    depends-manifests [package] (alias: deps-manifests)
    depends-msgsrv    [package] (alias: deps-msgsrv)
    depends-on        [package]
    depends-on1       [package]
    depends-why --target=<target> [package] (alias: deps-why)
    depends1          [package] (alias: deps1)
    export [--deps-only] --lang=<lang> --attrib=<attrib> [package]
    find [package]
    langs
    libs-only-L     [--deps-only] [package]
    libs-only-l     [--deps-only] [package]
    libs-only-other [--deps-only] [package]
    list
    list-duplicates
    list-names
    plugins --attrib=<attrib> [--top=<toppkg>] [package]
    profile [--length=<length>] [--zombie-only]
    rosdep  [package] (alias: rosdeps)
    rosdep0 [package] (alias: rosdeps0)
    vcs  [package]
    vcs0 [package]
  Extra options:
    -q     Quiets error reports.

 If [package] is omitted, the current working directory
 is used (if it contains a package.xml or manifest.xml).

"""

_OFFERED = ("depends", "deps", "depends1", "deps1", "depends-on", "depends-on1", "find", "help",
            "list", "list-names")
_NOT_OFFERED = ("cflags-only-I", "cflags-only-other", "depends-indent", "deps-indent",
                "depends-manifests", "deps-manifests", "depends-msgsrv", "deps-msgsrv",
                "depends-why", "deps-why", "export", "langs", "libs-only-L", "libs-only-l",
                "libs-only-other", "list-duplicates", "plugins", "profile", "rosdep", "rosdeps",
                "rosdep0", "rosdeps0", "vcs", "vcs0")
#: rospack's options that take a value (``--lang=cpp`` or ``--lang cpp``).
_VALUED = ("--lang", "--attrib", "--top", "--target", "--length")
_FLAGS = ("--deps-only", "--zombie-only")


class _Failed(Exception):
    """rospack's ``logError`` and a failing exit: the message after ``[rospack] Error: ``."""


def _direct(rp: RosPack, name: str) -> list[str]:
    """The dependencies of ``name`` that are on the path (the others are skipped, as rospack
    skips system packages)."""
    return [d for d in rp.depends1(name) if d in rp]


def depends(rp: RosPack, name: str, direct: bool = False) -> list[str]:
    """``rospack depends[1] NAME``: direct ones in declared order, or all of them post-order."""
    if direct:
        return _direct(rp, name)
    out: list[str] = []

    def walk(pkg: str, chain: list[str]) -> None:
        for dep in _direct(rp, pkg):
            if dep in chain:
                cycle = ", ".join(chain[chain.index(dep):])
                raise _Failed("maximum dependency depth exceeded (likely circular dependency: "
                              f"{cycle})")
            walk(dep, [*chain, dep])
            if dep not in out:
                out.append(dep)

    walk(name, [name])
    return out


def depends_on(rp: RosPack, name: str, direct: bool = False) -> list[str]:
    """``rospack depends-on[1] NAME``: the packages depending on NAME, sorted by name.

    As in rospack, a package whose ``package.xml`` cannot be read is left
    out, and a dependency cycle anywhere on the path is an error
    (``depends-on`` only: ``depends-on1`` does not follow dependencies).
    """
    users: list[str] = []
    for pkg in rp.list():
        try:
            deps = depends(rp, pkg, direct)
        except DdesError:
            continue
        if name in deps:
            users.append(pkg)
    return users


def _package_here(ctx: ToolContext) -> str:
    """rospack's ``inStackage``: the package folder at or above the working directory, or ""."""
    folder = os.path.abspath(ctx.resolve_path("."))
    while True:
        if any(os.path.isfile(os.path.join(folder, m)) for m in ("package.xml", "manifest.xml")):
            return os.path.basename(folder)
        parent = os.path.dirname(folder)
        if parent == folder:
            return ""
        folder = parent


def _parse(argv: list[str]) -> tuple[bool, list[str], list[str]]:
    """``(quiet, options given, positional words)`` of a rospack command line."""
    quiet = False
    options: list[str] = []
    words: list[str] = []
    args = list(argv)
    while args:
        arg = args.pop(0)
        if arg == "-q":
            quiet = True
        elif arg in _FLAGS:
            options.append(arg)
        elif arg.split("=", 1)[0] in _VALUED:
            if "=" not in arg:
                if not args:
                    raise _Failed("failed to parse command-line options: the required argument "
                                  f"for option '{arg}' is missing")
                args.pop(0)
            options.append(arg.split("=", 1)[0])
        elif arg.startswith("-") and arg != "-":
            raise _Failed(f"failed to parse command-line options: unrecognised option '{arg}'")
        else:
            words.append(arg)
    if len(words) > 2:
        raise _Failed("failed to parse command-line options: too many positional options have "
                      "been specified on the command line")
    return quiet, options, words


def rospack(ctx: ToolContext, argv: list[str]) -> int:
    """The ``rospack`` tool (see the module docstring)."""
    if argv in (["-h"], ["--help"]):
        ctx.print(USAGE[:-1])
        return 0
    quiet = "-q" in argv

    def fail(message: str) -> int:
        if not quiet:
            ctx.eprint(f"[rospack] Error: {message}")
        return 1

    try:
        quiet, options, words = _parse(argv)
        if not words:
            fail("no command given.  Try 'rospack help'")
            return 0  # rospack exits 0 here
        command = words[0]
        package = words[1] if len(words) > 1 else ""
        given = bool(package)
        if command in _NOT_OFFERED:
            raise ROSConsoleError(f"rospack {command} is not offered by ddes (it has find, list, "
                                  "list-names, depends, depends1, depends-on, depends-on1)")
        if command not in _OFFERED:
            return fail(f"command {command} not implemented")
        if command == "help":
            if given or options:
                return fail("invalid option(s) given")
            ctx.print(USAGE[:-1])
            return 0
        rp = ctx.rospack
        assert rp is not None
        if command in ("list", "list-names"):
            if given or options:
                return fail("invalid option(s) given")
            for name in rp.list():
                ctx.print(name if command == "list-names" else f"{name} {rp.get_path(name)}")
            return 0
        if not given:
            package = _package_here(ctx)
        if not package:
            return fail("no package given")
        if options:
            return fail("invalid option(s) given")
        if command == "find":
            try:
                ctx.print(str(rp.get_path(package)))
            except PackageNotFound:
                return fail(f"package '{package}' not found")
            return 0
        if package not in rp:
            return fail(f"no such package {package}")
        if command.startswith("depends-on"):
            found = depends_on(rp, package, direct=command == "depends-on1")
        else:
            found = depends(rp, package, direct=command in ("depends1", "deps1"))
        for name in found:
            ctx.print(name)
        return 0
    except _Failed as exc:
        return fail(str(exc))
    except InvalidManifest as exc:
        return fail(exc.rospack_text)
    except DdesError as exc:
        if isinstance(exc, ROSConsoleError):
            raise
        return fail(str(exc))


TOOLS = {"rospack": rospack}
