"""Fingerprints: what produced a stored result, so a result is never taken for another's.

A sweep's rows are keyed by its settings (box, counts, scheduler, detection,
frames, properties, limits: the semantics) and by the fingerprint of its
algorithm: a digest of the algorithm's source, its spec with the options, and
gather-verify's version. The source is the file of the algorithm's module and
of every local module it imports, transitively: for a file of your own, the
``.py`` files of its folder it imports; for a module of a package, the modules
of that package it imports; for the built-in algorithms, the modules of
gather-verify the algorithm's module imports. An edit to any of them changes
the fingerprint, so a sweep after an edit recomputes instead of printing the
old table.

>>> fp = algorithm_fingerprint("go-to-target")
>>> len(fp["digest"]), "gather_verify/algorithms/go_to_target.py" in fp["files"]
(16, True)
>>> algorithm_fingerprint("go-to-target:x=1")  # the options are part of it  # doctest: +SKIP
"""

from __future__ import annotations

import hashlib
import os
import sys
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


def algorithm_fingerprint(spec: str) -> dict[str, Any]:
    """``digest`` (16 hex digits) of the algorithm's source, spec and gather-verify's version,
    with the ``files`` it read (relative to their root where possible) and the ``version``."""
    from gather_verify.algorithms.loading import local_sources

    files: set[Path] = set()
    for module in _modules_of(spec):
        files |= set(local_sources(module.__file__, module.__name__))
    package = Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    names = []
    for path in sorted(files):
        shown = path.relative_to(package) if path.is_relative_to(package) else path
        names.append(str(shown).replace(os.sep, "/"))
        h.update(f"{names[-1]}\0{file_digest(path)}\0".encode())
    h.update(f"{spec}\0{version()}".encode())
    return {"digest": h.hexdigest()[:16], "files": sorted(names), "version": version()}
