"""Caches that keep only their most recently used entries.

A sweep under every reading runs 16 or 64 algorithms in one worker; what a process keeps
per algorithm (its instance with the paper's plans, the facts and target memos) is kept
for the few most recently used, or it fills the worker's memory limit. Imports nothing of
the project: every layer may use it.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import TypeVar

V = TypeVar("V")
_MISSING = object()


def most_recent(table: dict, key: Hashable, make: Callable[[], V], keep: int) -> V:
    """``table[key]`` (``make()`` when missing), made the most recent entry; the least
    recently used beyond ``keep`` are dropped (a dict keeps insertion order, so its first
    entry is the least recently used).

    >>> t = {}
    >>> [most_recent(t, k, lambda: k * 10, keep=2) for k in (1, 2, 1, 3)]
    [10, 20, 10, 30]
    >>> list(t)
    [1, 3]
    """
    value = table.pop(key, _MISSING)
    if value is _MISSING:
        while len(table) >= keep:
            del table[next(iter(table))]
        value = make()
    table[key] = value
    return value
