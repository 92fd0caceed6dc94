"""Fingerprints: what produced a stored result, so a result is never taken for another's.

A sweep's rows are keyed by its settings (box, counts, scheduler, detection,
frames, properties, limits: the semantics) and by a fingerprint of the code that
produced them: the algorithm's source, its spec with the options, the source of
every property file it checks, the files named with ``--fingerprint-extra``, and
gather-verify's own source (every ``.py`` file of the installed package and of
``schedulers``, and the viewer). The algorithm's source is the file of its module
and of every local module it imports, transitively, through packages'
``__init__`` files and relative imports: for a file of your own, the ``.py``
files of its folder it imports; for a module of a package, the modules of that
package it imports. An edit to any of them changes the fingerprint, so a sweep
after an edit recomputes instead of printing the old table.

Never covered: data the algorithm reads at run time or at import (a JSON of
parameters, a module loaded by ``importlib`` from a computed name), unless named
with ``--fingerprint-extra``; installed third-party packages (their version is
not recorded); the Python interpreter.

>>> fp = algorithm_fingerprint("go-to-target")
>>> len(fp["digest"]), "go_to_target.py" in fp["files"]
(16, True)
>>> algorithm_fingerprint("go-to-target:x=1")  # the options are part of it  # doctest: +SKIP
"""

from __future__ import annotations

import hashlib
import os
import sys
from collections.abc import Iterable, Sequence
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any


def version() -> str:
    """gather-verify's installed version."""
    try:
        return metadata.version("gather-verify")
    except metadata.PackageNotFoundError:  # pragma: no cover - run from a source tree
        return "unknown"


@lru_cache(maxsize=256)
def _digest(path: str, mtime: int, size: int) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def file_digest(path: Path) -> str:
    stat = path.stat()
    return _digest(str(path), stat.st_mtime_ns, stat.st_size)


def _modules_of(spec: str) -> list[Any]:
    """The modules that define the algorithm ``spec``: its factory's and its class's."""
    from gather_verify.algorithms import REGISTRY, get_algorithm, parse_name
    from gather_verify.algorithms.loading import absolute_spec, load_external, split_external

    algorithm = get_algorithm(spec)
    modules = [sys.modules.get(type(algorithm).__module__)]
    if split_external(spec) is not None:
        modules.append(load_external(absolute_spec(spec))[1])
    else:
        factory = REGISTRY.get(parse_name(spec)[0])
        if factory is not None:
            modules.append(sys.modules.get(getattr(factory, "__module__", "")))
    return [m for m in dict.fromkeys(modules) if m is not None and getattr(m, "__file__", None)]


_PACKAGE = Path(__file__).resolve().parent.parent
"""The folder holding ``gather_verify`` and ``schedulers``."""


_OWN_STAMPS: list[tuple[str, tuple[int, ...]]] = []
"""The stamps of gather-verify's own files when :func:`own_digest` read them."""


@lru_cache(maxsize=1)
def own_digest() -> str:
    """A digest of gather-verify's own source, read once per process: every ``.py`` file of
    ``gather_verify`` and ``schedulers`` and the viewer page (an edit in a source checkout
    is another verifier, whose results are not this one's)."""
    from gather_verify.inputs import stamp_of

    h = hashlib.sha256()
    _OWN_STAMPS.clear()
    for top in ("gather_verify", "schedulers"):
        for path in sorted((_PACKAGE / top).rglob("*")):
            if path.suffix in (".py", ".html") and "__pycache__" not in path.parts:
                h.update(f"{path.relative_to(_PACKAGE).as_posix()}\0".encode())
                with open(path, "rb") as handle:  # the bytes and the stamp of one reading
                    _OWN_STAMPS.append((str(path), stamp_of(os.fstat(handle.fileno()))))
                    h.update(handle.read())
    return h.hexdigest()[:16]


def own_code_changed() -> str | None:
    """The first of gather-verify's own files that is no longer the one :func:`own_digest`
    read (written since, or gone), else None. A process that imports a module of its own
    after that may run code its digest does not name."""
    from gather_verify.inputs import stamp_of

    own_digest()
    for path, stamp in _OWN_STAMPS:
        try:
            if stamp_of(os.stat(path)) != stamp:
                return path
        except OSError:
            return path
    return None


def _named(files: Iterable[Path], home: Path) -> list[tuple[str, Path]]:
    """Each file with the name it is hashed under: relative to ``home`` (the module's own
    folder, so a sweep's snapshot of it, or the folder moved, keeps the digest), else to
    gather-verify's folder."""
    out = []
    for path in sorted(files):
        for root in (home, _PACKAGE):
            if path.is_relative_to(root):
                out.append((path.relative_to(root).as_posix(), path))
                break
        else:
            out.append((path.as_posix(), path))
    return out


def source_fingerprint(module_file: str | Path, module_name: str | None = None) -> dict[str, Any]:
    """``digest`` and ``files`` of a module's file and the local modules it imports (of the
    copy of a sweep's snapshot while one is in force)."""
    from gather_verify.algorithms.loading import local_sources, source_of

    module_file = source_of(str(module_file))
    files = local_sources(module_file, module_name)
    h = hashlib.sha256()
    names = []
    for name, path in _named(files, Path(module_file).resolve().parent):
        names.append(name)
        h.update(f"{name}\0{file_digest(path)}\0".encode())
    return {"digest": h.hexdigest()[:16], "files": names}


def algorithm_fingerprint(spec: str) -> dict[str, Any]:
    """``digest`` (16 hex digits) of the algorithm's source, spec, gather-verify's version and
    its own source (:func:`own_digest`), with the ``files`` it read (relative to their root
    where possible) and the ``version``."""
    from gather_verify.algorithms.loading import local_sources

    named: dict[str, str] = {}  # name -> digest: the same file reached twice counts once
    for module in _modules_of(spec):
        home = Path(module.__file__).resolve().parent
        for name, path in _named(local_sources(module.__file__, module.__name__), home):
            named[name] = file_digest(path)
    h = hashlib.sha256()
    for name, digest in sorted(named.items()):
        h.update(f"{name}\0{digest}\0".encode())
    h.update(f"{spec}\0{version()}\0{own_digest()}".encode())
    return {"digest": h.hexdigest()[:16], "files": sorted(named), "version": version()}


def files_fingerprint(paths: Iterable[str], disk: bool = False) -> str:
    """A digest of the named files' contents, in the order given (``--fingerprint-extra``):
    the bytes kept when first read (:mod:`gather_verify.inputs`), or with ``disk`` what the
    disk holds now. InvalidInput when one cannot be read."""
    from gather_verify.inputs import digest, disk_digest

    h = hashlib.sha256()
    for text in paths:
        path = Path(text).expanduser()
        got = (disk_digest if disk else digest)(path.resolve(), "--fingerprint-extra")
        h.update(f"{path.name}\0{got}\0".encode())
    return h.hexdigest()[:16]


def world_inputs(world: str) -> dict[str, str]:
    """The files a world's name stands for, named, with the digest of what this process
    reads from them: the graph file of a ``graph:`` world (an input like the algorithm),
    nothing for the others. Every store keyed by a world's name keys it by these too."""
    from gather_verify.inputs import digest

    if not world.startswith("graph:"):
        return {}
    name = world.partition(":")[2]
    return {f"graph file {name}": digest(Path(name).expanduser().resolve(), "graph file")[:16]}


def sweep_inputs(algorithm_digest: str, world: str, properties: Iterable[str],
                 extra: Iterable[str], disk: bool = False) -> dict[str, str]:
    """Every input a sweep's rows depend on, named, with the digest of what this process
    computes from: the algorithm (its files, spec, version and gather-verify's own source),
    the graph file of a ``graph:`` world, each property file, the ``--fingerprint-extra``
    files, and gather-verify's own source.

    The graph, algorithm and property files are read once and run from that snapshot; with
    ``disk`` (a sweep's worker, after a task), the inputs read from the disk as they are
    used, the extra files (which your algorithm opens itself) and gather-verify's own source
    (which a process may import a module of late), are those on the disk now: a task whose
    inputs changed while it ran is told apart from the key, and its rows are not stored."""
    from gather_verify.algorithms.loading import is_path_spec

    extra = tuple(extra)
    out = {"algorithm": algorithm_digest, **world_inputs(world)}
    for p in properties:
        if is_path_spec(p):
            out[f"property file {p.rpartition(':')[0]}"] = source_fingerprint(
                p.rpartition(":")[0])["digest"]
    if extra:
        out[f"--fingerprint-extra {' '.join(extra)}"] = files_fingerprint(extra, disk)
    changed = own_code_changed() if disk else None
    out["gather-verify's own source"] = own_digest() if changed is None else f"edited: {changed}"
    return out


def sweep_fingerprint(inputs: dict[str, str]) -> str:
    """A sweep's fingerprint (``SweepSettings.fingerprint``): one digest of every input of
    :func:`sweep_inputs`."""
    text = "\0".join(f"{name}\0{got}" for name, got in sorted(inputs.items()))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def file_algorithm_digest(spec: str) -> str:
    """:func:`algorithm_fingerprint`'s digest of an algorithm in a file (``FILE.py:NAME``),
    from the files alone, nothing imported: the file and the local modules it imports. The
    same digest when ``NAME`` is defined in that file (a class or factory brought in from
    elsewhere adds its own module's files, which only loading it can name)."""
    from gather_verify.algorithms.loading import local_sources

    path = Path(spec[:spec.find(".py:") + 3]).resolve()
    if not path.is_file():
        raise FileNotFoundError(path)
    named = {name: file_digest(p) for name, p in _named(local_sources(path), path.parent)}
    h = hashlib.sha256()
    for name, digest in sorted(named.items()):
        h.update(f"{name}\0{digest}\0".encode())
    h.update(f"{spec}\0{version()}\0{own_digest()}".encode())
    return h.hexdigest()[:16]


def disk_fingerprint(settings: dict[str, Any], extra: Sequence[str] | None,
                     folder: str | Path) -> str | None:
    """The fingerprint the code and data on disk give a stored sweep's ``settings`` now (what
    ``report`` compares with the stored one), or None when it cannot be told without running
    code the database names: a module path, files outside ``folder`` (the database's) and the
    working directory (the trust model, docs/reliability.md), unknown extra files; or when a
    file is gone. A registered algorithm or an installed entry point is loaded, as anywhere."""
    from gather_verify.algorithms.loading import confined_spec, is_path_spec, split_external

    try:
        algorithm, world = settings["algorithm"], settings.get("world", "grid")
        properties, extra = list(settings.get("properties") or ()), list(extra or ())
        if not all(isinstance(x, str) for x in (algorithm, world, *properties, *extra)):
            return None

        if is_path_spec(algorithm):
            digest = file_algorithm_digest(confined_spec(algorithm, folder, "the database"))
        elif split_external(algorithm) is not None:  # a module path: importing it runs code
            return None
        else:
            digest = algorithm_fingerprint(algorithm)["digest"]
        for spec in properties:
            if is_path_spec(spec):
                confined_spec(spec, folder, "the database")
        files = [str(Path(f).resolve()) for f in extra]
        if world.startswith("graph:"):
            files.append(world.partition(":")[2])
        for f in files:
            if not Path(f).is_file() or not (Path(f).resolve().is_relative_to(
                    Path(folder).resolve()) or Path(f).resolve().is_relative_to(Path.cwd())):
                return None
        return sweep_fingerprint(sweep_inputs(digest, world, properties, extra))
    except Exception:  # noqa: BLE001 - a database of another's: never a reason to fail
        return None
