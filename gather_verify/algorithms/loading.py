"""Algorithms from anywhere: a file, an importable module, or an installed package.

An algorithm spec names one of three things:

- a registered name, ``paper`` or ``paper:alpha=mer_f`` (:data:`REGISTRY`);
- a file, ``PATH.py:NAME`` or ``PATH.py:NAME:key=value,...``;
- a module, ``package.module:NAME`` (with the same options);
- a name an installed package registers in the ``gather_verify.algorithms``
  entry-point group (``[project.entry-points."gather_verify.algorithms"]``).

``NAME`` is a class or a factory, called with the options as keyword arguments
(strings), or an object with ``decide`` (then no options). A loaded algorithm
is named by its spec with the path made absolute, so traces and stored results
name a file that ``replay`` and the workers of a sweep load again. A file is
loaded afresh when its text changes.

>>> split_external("/tmp/my alg.py:Centre:k=1,j=2")
('/tmp/my alg.py', 'Centre', {'k': '1', 'j': '2'})
>>> split_external("mypkg.algs:Centre")
('mypkg.algs', 'Centre', {})
>>> split_external("paper:alpha=mer_f") is None
True
"""

from __future__ import annotations

import ast
import hashlib
import importlib
import importlib.util
import os
import sys
import sysconfig
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.inputs import not_a_file
from gather_verify.watchdog import OverMemory, Overtime, watched

ENTRY_POINT_GROUP = "gather_verify.algorithms"
_LIBRARY = {os.path.abspath(sysconfig.get_paths()[k])
            for k in ("stdlib", "platstdlib", "purelib", "platlib")}


def parse_options(rest: str, spec: str) -> dict[str, str]:
    """``key=value,...`` as a dict; ValueError names the bad item."""
    options: dict[str, str] = {}
    for item in filter(None, rest.split(",")):
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise InvalidInput(f"bad algorithm option {item!r} in {spec!r}: expected key=value")
        options[key.strip()] = value.strip()
    return options


def split_external(spec: str) -> tuple[str, str, dict[str, str]] | None:
    """``(path or module, NAME, options)`` of a file or module spec; None for a plain name."""
    at = spec.find(".py:")
    if at >= 0:
        where, rest = spec[:at + 3], spec[at + 4:]
    else:
        where, colon, rest = spec.partition(":")
        if not colon or "=" in rest.partition(":")[0] or not _is_module_path(where):
            return None
    name, _, options = rest.partition(":")
    if not name.strip() or "=" in name:
        raise InvalidInput(f"algorithm {spec!r}: name the class or factory after the colon, "
                         f"e.g. {where}:MyAlgorithm")
    return where.strip(), name.strip(), parse_options(options, spec)


def _is_module_path(text: str) -> bool:
    parts = text.strip().split(".")
    return len(parts) > 1 and all(p.isidentifier() for p in parts)


def is_path_spec(spec: str) -> bool:
    """Whether ``spec`` names a ``.py`` file."""
    return ".py:" in spec


def absolute_spec(spec: str, base: str | Path | None = None) -> str:
    """``spec`` with a relative file path taken from ``base`` (a folder; default the
    working directory) and made absolute; other specs unchanged.

    >>> absolute_spec("alg.py:A:k=1", "/data/x")
    '/data/x/alg.py:A:k=1'
    >>> absolute_spec("paper", "/data/x")
    'paper'
    """
    if not is_path_spec(spec):
        return spec
    at = spec.find(".py:")
    path = os.path.expanduser(spec[:at + 3])
    full = os.path.normpath(os.path.join(base or os.getcwd(), path))
    return full + spec[at + 3:]


ALLOW_CODE_ENV = "GATHER_VERIFY_ALLOW_CODE"
"""Set to 1 to let a scenario, trace or database file name code outside its own folder."""


def confined_spec(spec: str, folder: str | Path, where: str) -> str:
    """The trust model for code named *inside* a file (a scenario, a trace): ``spec``
    taken relative to ``folder``, the file's own folder, and allowed only when it lies in
    that folder's tree or in the working directory's (the project you run the command
    from, where ``report --regressions`` files name the algorithm they came from), or is
    a registered name or an installed entry point. A file path elsewhere, or a module
    path (``package.module:NAME`` could name any installed callable), is refused with one
    line unless ``GATHER_VERIFY_ALLOW_CODE=1``: opening a file someone sent you never runs
    code from elsewhere on your machine.

    >>> confined_spec("alg.py:A", "/data/x", "s.json")
    '/data/x/alg.py:A'
    >>> confined_spec("/elsewhere/alg.py:A", "/data/x", "s.json")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    gather_verify.errors.InvalidInput: s.json names code outside its folder ...
    """
    if os.environ.get(ALLOW_CODE_ENV) == "1":
        return absolute_spec(spec, folder)
    if is_path_spec(spec):
        full = absolute_spec(spec, folder)
        path = Path(full[:full.find(".py:") + 3]).resolve()
        if path.is_relative_to(Path(folder).resolve()) or path.is_relative_to(Path.cwd()):
            return full
        what = f"code outside its folder and the working directory ({path})"
    elif split_external(spec) is not None:
        what = f"a module to import ({spec.partition(':')[0]})"
    else:
        return spec
    raise InvalidInput(f"{where} names {what}: code named in a file runs only from that "
                       f"file's own folder or the working directory; move it there, or set "
                       f"{ALLOW_CODE_ENV}=1 if you trust the file")


def relative_spec(spec: str, folder: str | Path) -> str:
    """``spec`` with its file path relative to ``folder`` (what a scenario file written there
    stores, so the folder and the algorithm can move together)."""
    if not is_path_spec(spec):
        return spec
    at = spec.find(".py:")
    rel = os.path.relpath(spec[:at + 3], os.path.abspath(folder))
    return rel.replace(os.sep, "/") + spec[at + 3:]


def _imports(path: Path, package: tuple[str, ...] = ()) -> set[tuple[str, ...]]:
    """Dotted names a module imports, as tuples (``from a import b``: both ``a`` and ``a.b``);
    a relative import (``from .impl import f``, ``from . import impl``) is resolved against
    ``package``, the dotted package the module lies in (relative to the search root)."""
    try:
        source = path.read_bytes()
    except OSError:
        return set()
    key = (hashlib.sha256(source).digest(), package)
    if key not in _PARSED:  # a sweep's worker asks after every task: parse each text once
        _PARSED[key] = frozenset(_parsed_imports(source, str(path), package))
    return set(_PARSED[key])


_PARSED: dict[tuple[bytes, tuple[str, ...]], frozenset[tuple[str, ...]]] = {}
""":func:`_imports` of each text already parsed, by the SHA-256 of its bytes and its package:
the same bytes import the same names, so an edited file (other bytes) is parsed afresh."""


def _parsed_imports(source: bytes, filename: str, package: tuple[str, ...]
                    ) -> set[tuple[str, ...]]:
    """:func:`_imports` of a module's text, parsed."""
    try:
        tree = ast.parse(source, filename=filename)
    except (SyntaxError, ValueError):
        return set()
    out: set[tuple[str, ...]] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out |= {tuple(alias.name.split(".")) for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                up = len(package) - (node.level - 1)
                if up < 0:
                    continue
                base = package[:up] + (tuple(node.module.split(".")) if node.module else ())
            elif node.module:
                base = tuple(node.module.split("."))
            else:
                continue
            if base:
                out.add(base)
            out |= {(*base, alias.name) for alias in node.names}
    return out


def _module_file(root: Path, parts: tuple[str, ...]) -> Path | None:
    """The file of module ``parts`` under ``root`` (a module or a package's ``__init__``)."""
    stem = os.path.join(root, *parts)  # os.path: a sweep's worker looks after every task
    for candidate in (stem + ".py", os.path.join(stem, "__init__.py")):
        if os.path.isfile(candidate):
            return Path(candidate)
    return None


def local_sources(module_file: str | Path, module_name: str | None = None) -> list[Path]:
    """The module's file and every local module it imports, transitively (sorted), through
    a package's ``__init__`` and relative imports too.

    Local: under the module's folder for a file loaded by path or a top-level module
    (unless that folder is the standard library or site-packages: then the file alone);
    under its top-level package for a module of a package."""
    first = Path(module_file).resolve()
    parts = (module_name or "").split(".")
    if module_name and len(parts) > 1 and not module_name.startswith("gather_verify_user_"):
        root = first.parents[len(parts) - (first.name != "__init__.py")]
        scope = root / parts[0]
    else:
        root = scope = first.parent
        if str(scope) in _LIBRARY:
            return [first]
    seen, todo = {first}, [first]
    looked: set[tuple[str, ...]] = set()  # a name imported by many modules is looked up once
    while todo:
        here = todo.pop()
        package = here.parent.relative_to(root).parts if here.is_relative_to(root) else ()
        for dotted in _imports(here, package) - looked:
            looked.add(dotted)
            found = _module_file(root, dotted)
            found = found and found.resolve()
            if found is not None and found.is_relative_to(scope) and found not in seen:
                seen.add(found)
                todo.append(found)
    return sorted(seen)



_FILES: dict[str, tuple[tuple[tuple[str, int, int], ...], ModuleType]] = {}
"""Modules loaded from files: by absolute path, with the stamps (path, mtime, size) of the
file and of the local modules it imports, when it ran."""


def _stamps(files: list[Path]) -> tuple[tuple[str, int, int], ...]:
    out = []
    for f in files:
        try:
            st = f.stat()
            out.append((str(f), st.st_mtime_ns, st.st_size))
        except OSError:
            out.append((str(f), -1, -1))
    return tuple(out)


def load_file(path: str) -> ModuleType:
    """The module of a ``.py`` file, executed again when it or a local module it imports
    changed (those are imported afresh too). Its folder goes on ``sys.path`` (as for a
    script), so it imports its neighbours."""
    path = source_of(path)  # the snapshot taken at the start (:func:`snapshot`), never the disk
    if not os.path.isfile(path):
        raise InvalidInput(f"algorithm file {path}: {not_a_file(path)}")
    known = _FILES.get(path)
    if known is not None and _stamps([Path(f) for f, _, _ in known[0]]) == known[0]:
        return known[1]
    files = local_sources(path)
    stamps = _stamps(files)
    folder = os.path.dirname(path)
    for f in files:  # its neighbours, imported again (from this folder) when it imports them
        if f.is_relative_to(folder) and f != Path(path).resolve():
            parts = f.relative_to(folder).with_suffix("").parts
            sys.modules.pop(".".join(parts[:-1] if parts[-1] == "__init__" else parts), None)
    if folder in sys.path:
        sys.path.remove(folder)
    sys.path.insert(0, folder)
    try:
        text = Path(path).read_bytes()
    except OSError as error:
        raise InvalidInput(f"algorithm file {path}: cannot read ({error.strerror or error})") from None
    name = f"gather_verify_user_{Path(path).stem}_{hashlib.sha256(text).hexdigest()[:12]}"
    loader_spec = importlib.util.spec_from_file_location(name, path)
    if loader_spec is None or loader_spec.loader is None:
        raise InvalidInput(f"algorithm file {path}: not a Python module")
    module = importlib.util.module_from_spec(loader_spec)
    sys.modules[name] = module  # classes defined there pickle by this name
    try:
        with watched():  # an endless loop at import ends with the time limit (watchdog)
            loader_spec.loader.exec_module(module)
    except (KeyboardInterrupt, OverMemory):  # a real Ctrl-C; the memory limit
        del sys.modules[name]
        raise
    except Overtime as error:
        del sys.modules[name]
        raise InvalidInput(f"algorithm file {path}: did not finish importing within "
                           f"{error.seconds:g} s (an endless loop at import?)") from None
    except BaseException as error:  # SystemExit, GeneratorExit ... at import: bad input too
        del sys.modules[name]
        raise InvalidInput(f"algorithm file {path}: importing it failed: "
                         f"{type(error).__name__}: {error}") from None
    _FILES[path] = (stamps, module)
    return module


_RECEIVED: dict[str, tuple[str, str]] = {}
"""Algorithm files loaded from a snapshot, by their original path (on the machine that took
it): the digest of the snapshot and the path of its copy. :func:`load_file` loads the copy,
whatever the original file holds now."""


def source_of(path: str) -> str:
    """The file that stands for the code file ``path`` in this process: the copy of the
    snapshot in force (:func:`snapshot`), else ``path`` itself."""
    got = _RECEIVED.get(path)
    return path if got is None else got[1]


def ship(specs: set[str]) -> dict[str, dict[str, str]]:
    """For each file spec (an algorithm's, or a property file's ``FILE.py:NAME``), its path
    and the text of the file and of the local modules it imports (relative to its folder):
    what a worker on another machine needs to load it."""
    out = {}
    for spec in specs:
        external = split_external(spec) if is_path_spec(spec) else None
        if external is None:
            continue
        path = external[0]
        source = source_of(path)  # a snapshot: its copy
        if not os.path.isfile(source):
            continue  # (loading it says so, in the words of what it is)
        folder = Path(source).resolve().parent
        try:
            out[path] = {str(f.relative_to(folder)): f.read_text(encoding="utf-8")
                         for f in local_sources(source) if f.is_relative_to(folder)}
        except (OSError, UnicodeDecodeError) as error:
            raise InvalidInput(f"code file {path}: cannot read it ({error})") from None
    return out


def receive(sources: dict[str, dict[str, str]]) -> None:
    """Load shipped algorithm files under their original paths from now on: a private folder
    holds the copies, and :func:`load_file` runs them even where the original file exists
    (a sweep's workers run the snapshot its parent took, never a later edit)."""
    import tempfile

    for path, files in sources.items():
        digest = hashlib.sha256(repr(sorted(files.items())).encode()).hexdigest()
        if _RECEIVED.get(path, ("",))[0] == digest:
            continue
        folder = Path(tempfile.mkdtemp(prefix="gather-verify-received-"))
        for name, text in files.items():
            (folder / name).parent.mkdir(parents=True, exist_ok=True)
            (folder / name).write_text(text, encoding="utf-8")
        _RECEIVED[path] = (digest, str(folder / Path(path).name))


@contextmanager
def snapshot(specs: set[str]) -> Iterator[dict[str, dict[str, str]]]:
    """The text of the algorithm files of ``specs``, read once (:func:`ship`), and loaded from
    that copy in this process (and the workers it forks) until the block ends: what a sweep
    fingerprints is what its workers run, even if a file is edited meanwhile. Yields the
    snapshot, for workers on other machines (:func:`receive`)."""
    sources = ship(specs)
    before = dict(_RECEIVED)
    receive(sources)
    try:
        yield sources
    finally:
        _RECEIVED.clear()
        _RECEIVED.update(before)


def load_module(name: str) -> ModuleType:
    try:
        with watched():
            return importlib.import_module(name)
    except (KeyboardInterrupt, OverMemory):  # a real Ctrl-C; the memory limit
        raise
    except Overtime as error:
        raise InvalidInput(f"algorithm module {name!r}: did not finish importing within "
                           f"{error.seconds:g} s (an endless loop at import?)") from None
    except BaseException as error:  # not only ImportError: whatever its import raises
        raise InvalidInput(f"algorithm module {name!r}: cannot import it "
                           f"({type(error).__name__}: {error})") from None


def entry_point_factory(name: str) -> Any | None:
    """The factory an installed package registers under ``name``, if any."""
    from importlib import metadata  # here: 0.06 s, for a name no built-in algorithm has

    for point in metadata.entry_points(group=ENTRY_POINT_GROUP):
        if point.name == name:
            try:
                with watched():
                    return point.load()
            except (KeyboardInterrupt, OverMemory):  # a real Ctrl-C; the memory limit
                raise
            except Overtime as error:
                raise InvalidInput(f"algorithm {name!r} (entry point {point.value}): loading "
                                   f"it did not finish within {error.seconds:g} s") from None
            except BaseException as error:
                raise InvalidInput(f"algorithm {name!r} (entry point {point.value}): "
                                 f"loading it failed: {type(error).__name__}: {error}") from None
    return None


def entry_point_names() -> list[str]:
    from importlib import metadata

    return sorted(point.name for point in metadata.entry_points(group=ENTRY_POINT_GROUP))


def instantiate(target: Any, options: dict[str, str], spec: str) -> Any:
    """``target`` itself when it has ``decide`` (an instance), else ``target(**options)``."""
    if hasattr(target, "decide") and not isinstance(target, type):
        if options:
            raise InvalidInput(f"algorithm {spec!r}: an object takes no options")
        algorithm = target
    elif callable(target):
        try:
            with watched():
                algorithm = target(**options)
        except TypeError as error:
            raise InvalidInput(f"bad options for algorithm {spec!r}: {error}") from None
        except (KeyboardInterrupt, OverMemory):  # a real Ctrl-C; the memory limit
            raise
        except Overtime as error:
            raise InvalidInput(f"algorithm {spec!r}: constructing it did not finish within "
                               f"{error.seconds:g} s") from None
        except BaseException as error:  # the user's constructor rejected its options
            raise InvalidInput(f"algorithm {spec!r}: constructing it failed: "
                               f"{type(error).__name__}: {error}") from None
    else:
        raise InvalidInput(f"algorithm {spec!r}: not a class, a factory or an object with decide")
    if not callable(getattr(algorithm, "decide", None)):
        raise InvalidInput(f"algorithm {spec!r}: the object it gives has no decide(view) method")
    return algorithm


def load_external(spec: str) -> tuple[Any, Any]:
    """``(factory or object, module)`` of a file or module spec (the path already absolute)."""
    where, name, _ = split_external(spec)  # type: ignore[misc]
    module = load_file(where) if is_path_spec(spec) else load_module(where)
    try:
        return getattr(module, name), module
    except AttributeError:
        raise InvalidInput(f"algorithm {spec!r}: {where} defines no {name!r}") from None
