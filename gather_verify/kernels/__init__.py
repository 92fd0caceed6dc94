"""Compiled kernels (numba) for the bulk engine's hot loops.

Each kernel does, in compiled code, what a numpy/Python function of the engine does, with
the same result: the hash index of visited keys (``KeyIndex.find_or_add`` of
:mod:`gather_verify.engine.key_index`), the per-chunk arithmetic (decoding states,
successor keys, the keys of (configuration, move) pairs), the bulk steps of the ASYNC
and the round schedulers (FSYNC, SSYNC, centralized),
the longest path over the kept graph (``move-bound``), the breadth-first parents
read off it, and Tarjan's strongly connected
components (``termination``). The numpy and Python code stays the tested reference: set
``GATHER_VERIFY_KERNELS=numpy`` (or call :func:`use` with False) to run it instead; the tests
compare the two paths field by field.

The package imports nothing of the project (the engine, the graph properties and the
schedulers all use it: it sits at the bottom of the import layers, beside ``errors``), and
numba only when a kernel is first used (:mod:`.compiled`; the finite worlds' bulk search
imports its own, :mod:`.world`, when it runs). Kernels are compiled on first
use and cached on disk (``cache=True``: numba's cache beside the module, or under
``NUMBA_CACHE_DIR``), so only the first process pays the compile.
"""
from __future__ import annotations

import importlib.util
import os
from typing import Any

ENV = "GATHER_VERIFY_KERNELS"
"""Environment variable: ``numpy`` (or ``0``) selects the numpy/Python reference path (the
same switch as the union engine's, :mod:`gather_verify.engine.union_kernels`)."""
KERNELS = ("find_or_add", "place", "async_successors", "longest_path", "first_sources",
           "tarjan_csr",
           "decode_chunk", "successor_keys", "event_keys", "event_canonical_keys",
           "pair_keys", "successor_rows", "round_counts", "round_events")
"""The compiled functions (in :mod:`gather_verify.kernels.compiled`, imported on first use)."""
_forced: bool | None = None
_available: bool | None = None


def available() -> bool:
    """Whether numba is installed (found without importing it)."""
    global _available
    if _available is None:
        _available = importlib.util.find_spec("numba") is not None
    return _available


def use(flag: bool | None) -> None:
    """Force the kernels on or off for this process (None: back to :data:`ENV`)."""
    global _forced
    _forced = flag


def enabled() -> bool:
    """Whether the compiled kernels run (numba installed, not switched off)."""
    if not available():
        return False
    if _forced is not None:
        return _forced
    return os.environ.get(ENV, "numba") not in ("numpy", "0", "false", "no", "off")


def __getattr__(name: str) -> Any:
    if name in KERNELS:  # importing numba (a quarter of a second) only when a kernel runs
        from gather_verify.kernels import compiled

        return getattr(compiled, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def warm() -> None:
    """Load (or compile) every kernel now, on tiny inputs of the engine's types: a caller
    measuring memory per state takes its baseline after this fixed cost."""
    if not enabled():
        return
    import numpy as np

    from gather_verify.kernels.compiled import (
        async_successors,
        decode_chunk,
        event_canonical_keys,
        event_keys,
        find_or_add,
        first_sources,
        longest_path,
        pair_keys,
        place,
        round_counts,
        round_events,
        successor_keys,
        successor_rows,
        tarjan_csr,
    )

    table = np.zeros(16, dtype=np.int32)
    keys = np.empty(16, dtype=np.uint64)
    ids, first = np.empty(2, dtype=np.int64), np.empty(2, dtype=np.int64)
    q = np.array([3, 3], dtype=np.uint64)
    count, _ = find_or_add(table, keys, 0, np.uint64(60), q, ids, first)
    place(np.zeros(16, dtype=np.int32), keys, 0, count, np.uint64(60))
    k = np.array([7], dtype=np.uint64)
    weights = np.array([1, 9], dtype=np.int64)
    codes, cells, srt, ck, idle, rank = decode_chunk(k, 45, 2, weights)
    masks = np.ones((1, 2), dtype=np.uint8)
    neighbour = np.full((9, 4), -1, dtype=np.int64)
    src, weight, robot, new = async_successors(codes, masks, neighbour,
                                               np.arange(4, dtype=np.int64))
    powers = np.array([1, 45], dtype=np.uint64)
    succ, old = successor_keys(k, codes, src, robot, new, powers)
    event = np.arange(len(robot), dtype=np.int64)
    event_keys(k, codes, src, robot, new, event, powers)
    for anonymity in (False, True):
        event_canonical_keys(codes, src, robot, new, event, powers,
                             np.zeros((1, 45), dtype=np.int64), anonymity)
    pair_keys(ck, rank, src, robot, old, new, 18, 9)
    successor_rows(ck, rank, src, robot, old, new, neighbour,
                   np.full((1, 2, 4), -1, dtype=np.int32))
    subsets = np.ones((1, 2), dtype=np.bool_)
    count = np.ones(32, dtype=np.int64)
    s, e, c = round_counts(masks, subsets, count, 16)
    round_events(codes, masks, neighbour, subsets, np.full((32, 5), 4, dtype=np.int64), count, s,
                 np.empty(e, dtype=np.int64), np.empty(e, dtype=np.int8),
                 np.empty(c, dtype=np.int64), np.empty(c, dtype=np.int64),
                 np.empty(c, dtype=np.int64))
    off = np.array([0, 1, 1], dtype=np.int32)
    tgt = np.array([1], dtype=np.int32)
    packed = np.array([1, 0, 0], dtype=np.uint8)  # target ids three bytes each
    for t, p in ((tgt, False), (packed, True)):
        longest_path(off, t, np.zeros(1, dtype=np.int8), False, p)
        longest_path(off, t, np.zeros(1, dtype=np.uint8), True, p)  # one bit per edge
        first_sources(off, t, 1, 2, p)
        tarjan_csr(off, t, True, p)
