"""How much memory a search may use on this machine, so a limit stops it before the system does.

The explorer stops with INCOMPLETE (reason ``memory``) when the process's
resident memory passes ``max_memory_mb`` (SEMANTICS.md §5). Its built-in
default is sized for a 24 GiB machine; on a smaller machine, in a container
with a memory cap, or with several worker processes sharing the machine, that
default could be larger than what there is, and the kernel would kill the
process first. :func:`memory_budget_mb` is the default the commands use
instead: a share of the smallest of the physical memory and the cgroup limit,
never above the explorer's default.

>>> 0 < memory_budget_mb(workers=2) <= memory_budget_mb() <= DEFAULT_MAX_MEMORY_MB
True
"""

from __future__ import annotations

import os
from pathlib import Path

from gather_verify.engine.explore import DEFAULT_MAX_MEMORY_MB

SHARE = 0.75
"""Fraction of the machine's memory the searches of one command may use together (the
rest is for the graph analysis after the search, the interpreter and the system)."""


def machine_memory_mb() -> float | None:
    """Physical memory, or the cgroup (container) limit when smaller, in MiB; None if unknown."""
    found: list[float] = []
    try:
        pages, size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
        if pages > 0 and size > 0:
            found.append(pages * size / 2**20)
    except (ValueError, OSError, AttributeError):
        pass
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            text = Path(path).read_text(encoding="ascii").strip()
        except OSError:
            continue
        if text.isdigit() and int(text) < 2**60:
            found.append(int(text) / 2**20)
    return min(found) if found else None


def memory_budget_mb(workers: int = 1) -> float:
    """The default memory limit (MiB) of each of ``workers`` processes searching at once."""
    total = machine_memory_mb()
    if total is None:
        return float(DEFAULT_MAX_MEMORY_MB)
    return float(max(64, min(DEFAULT_MAX_MEMORY_MB, int(SHARE * total / max(1, workers)))))
