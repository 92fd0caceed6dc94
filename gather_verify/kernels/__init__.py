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
``NUMBA_CACHE_DIR``), so only the first process pays the compile. :mod:`.codes` holds the
values the kernels share with the engines (the neighbour tables' ``OUTSIDE`` and
``NO_EDGE``, the Z² code's slots per cell), without numba.
"""
from __future__ import annotations

import importlib.util
import os
from collections.abc import Iterable
from typing import Any

ENV = "GATHER_VERIFY_KERNELS"
"""Environment variable: ``numpy`` (or ``0``) selects the numpy/Python reference path (the
same switch as the union engine's, :mod:`gather_verify.engine.union_kernels`)."""
KERNELS = ("find_or_add", "place", "async_successors", "longest_path", "first_sources",
           "tarjan_csr",
           "decode_chunk", "successor_keys", "event_keys", "event_canonical_keys",
           "successor_canonical_keys",
           "pair_keys", "successor_rows", "round_counts", "round_events", "round_keys")
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


def warm(names: Iterable[str] = KERNELS) -> None:
    """Load (or compile) the kernels ``names`` now (default: every one), on tiny inputs of the
    engine's types: a caller measuring memory per state takes its baseline after this fixed
    cost. The first kernel costs most (numba's typing and LLVM set up, about 0.2 s); each
    other one a few milliseconds, so a caller names only those its run uses. The kernels
    that make the tiny inputs of the named ones (``find_or_add``, ``decode_chunk``,
    ``async_successors``, ``round_counts``) are loaded with them."""
    if not enabled():
        return
    wanted = set(names)
    unknown = wanted - set(KERNELS)
    if unknown:
        raise ValueError(f"no kernel named {', '.join(sorted(unknown))} "
                         f"(known: {', '.join(KERNELS)})")
    from gather_verify.kernels import compiled as k

    _warm_index(k, wanted)
    if wanted - {"find_or_add", "place", "longest_path", "tarjan_csr"}:
        _warm_steps(k, wanted)
    _warm_graphs(k, wanted)


def _warm_index(k: Any, wanted: set[str]) -> None:
    """:func:`warm` of the hash index's kernels."""
    import numpy as np

    if wanted & {"find_or_add", "place"}:
        table = np.zeros(16, dtype=np.int32)
        keys = np.empty(16, dtype=np.uint64)
        ids, first = np.empty(2, dtype=np.int32), np.empty(2, dtype=np.int32)
        q = np.array([3, 3], dtype=np.uint64)
        count, _ = k.find_or_add(table, keys, 0, np.uint64(60), 24, q, ids, first,
                                 np.empty(16, dtype=np.int32))
        if "place" in wanted:
            k.place(np.zeros(16, dtype=np.int32), keys, 0, count, np.uint64(60), 24)


def _warm_steps(k: Any, wanted: set[str]) -> None:
    """:func:`warm` of the kernels of a bulk step on Z²: a chunk decoded, its successors
    (asynchronous events and rounds) and their keys."""
    import numpy as np

    from gather_verify.kernels.codes import OUTSIDE, Z2_DEGREE, Z2_SLOTS

    k7 = np.array([7], dtype=np.uint64)
    weights = np.array([1, 9], dtype=np.int64)
    masks = np.ones((1, 2), dtype=np.uint8)
    neighbour = np.full((9, Z2_DEGREE), OUTSIDE, dtype=np.int64)
    powers = np.array([1, 45], dtype=np.uint64)
    codes, cells, srt, ck, idle, rank = k.decode_chunk(k7, 45, 2, weights)
    if wanted & {"async_successors", "successor_keys", "event_keys", "event_canonical_keys",
                 "successor_canonical_keys", "pair_keys", "successor_rows"}:
        src, weight, robot, new = k.async_successors(codes, masks, neighbour,
                                                     np.arange(4, dtype=np.int64))
        old = codes[src, robot].astype(new.dtype)  # as successor_keys returns it
        if "successor_keys" in wanted:
            k.successor_keys(k7, codes, src, robot, new, powers)
        event = np.arange(len(robot), dtype=np.int64)
        # the rounds' events are int64
        src64, robot64, new64 = (a.astype(np.int64) for a in (src, robot, new))
        if "event_keys" in wanted:
            k.event_keys(k7, codes, src64, robot64, new64, event, powers)
        if "event_canonical_keys" in wanted:
            for anonymity in (False, True):
                k.event_canonical_keys(codes, src64, robot64, new64, event, powers,
                                       np.zeros((1, 45), dtype=np.int64), anonymity)
        if "successor_canonical_keys" in wanted:
            for anonymity in (False, True):
                k.successor_canonical_keys(codes, src, robot, new, powers,
                                           np.zeros((1, 45), dtype=np.int64), anonymity, True)
        if "pair_keys" in wanted:
            k.pair_keys(ck, rank, src, robot, old, new, 18, 9)
        if "successor_rows" in wanted:
            k.successor_rows(ck, rank, src, robot, old, new, neighbour,
                             np.zeros((1, 2, Z2_DEGREE), dtype=np.int32))
    if wanted & {"round_counts", "round_events", "round_keys"}:
        subsets = np.ones((1, 2), dtype=np.bool_)
        count = np.ones(32, dtype=np.int64)
        nth = np.full((1 << Z2_SLOTS, Z2_SLOTS), Z2_DEGREE, dtype=np.int64)
        s, e, c = k.round_counts(masks, subsets, count, 16)
        if "round_events" in wanted:
            k.round_events(codes, masks, neighbour, subsets, nth,
                           count, s, np.empty(e, dtype=np.int64), np.empty(e, dtype=np.int8),
                           np.empty(c, dtype=np.int64), np.empty(c, dtype=np.int64),
                           np.empty(c, dtype=np.int64))
        if "round_keys" in wanted:
            k.round_keys(k7, codes, masks, neighbour, subsets, nth, count, s, powers,
                         np.empty(e, dtype=np.int64), np.empty(e, dtype=np.int8),
                         np.empty(e, dtype=np.uint64))


def _warm_graphs(k: Any, wanted: set[str]) -> None:
    """:func:`warm` of the kernels that read a finished state graph."""
    import numpy as np

    off = np.array([0, 1, 1], dtype=np.int32)
    tgt = np.array([1], dtype=np.int32)
    packed = np.array([1, 0, 0], dtype=np.uint8)  # target ids three bytes each
    for t, p in ((tgt, False), (packed, True)):
        if "longest_path" in wanted:
            k.longest_path(off, t, np.zeros(1, dtype=np.int8), False, p)
            k.longest_path(off, t, np.zeros(1, dtype=np.uint8), True, p)  # one bit per edge
        if "first_sources" in wanted:
            k.first_sources(off, t, 1, 2, p)
        if "tarjan_csr" in wanted:
            k.tarjan_csr(off, t, True, p)
