"""Compiled kernels of the union engine (numba), and the switch back to numpy.

Two passes of the union engine (:mod:`gather_verify.engine.union`) over its graph:

- the peeling of sinks (Kahn's algorithm on the reverse graph), which gives each
  state that reaches no cycle its reachable flags, longest path and node box; numpy
  does it round by round (a sort per round), the kernel state by state;
- per seed, the states and events its own search would see: a set of seeds per
  state, 64 a word, pulled along the edges from the sources down. In numpy that is
  a pass over every state per 64 seeds, whatever their reach; the kernel takes up
  to 1,024 seeds a pass (16 words a state), visits only the states they reach, and
  each (state, seed) pair once, through the bits that are set.

``GATHER_VERIFY_KERNELS=numpy`` (or numba missing) selects the numpy path,
which stays the tested reference (``tests/test_union_kernels.py``); the switch is
the bulk engine's (:func:`gather_verify.kernels.enabled`), and numba is imported
when a kernel first runs.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache
from typing import Any

import numpy as np


@cache
def _jit(function: Callable[..., Any]) -> Callable[..., Any]:
    """``function`` compiled on first use (and cached on disk by numba)."""
    import numba

    return numba.njit(cache=True, nogil=True)(function)


_MAGIC = 0x03F79D71B4CB0A89
_DE_BRUIJN = np.zeros(64, dtype=np.int64)
for _i in range(64):
    _DE_BRUIJN[((1 << _i) * _MAGIC % (1 << 64)) >> 58] = _i


def _seed_counts_py(topo: np.ndarray, pred_off: np.ndarray, pred_src: np.ndarray,
                    out_off: np.ndarray, out_tgt: np.ndarray, seeds: np.ndarray,
                    seed_off: np.ndarray, events: np.ndarray, sizes: np.ndarray,
                    table: np.ndarray, words: int, counts: np.ndarray,
                    transitions: np.ndarray) -> None:
    """States and events reachable from each seed ``j``, the states
    ``seeds[seed_off[j]:seed_off[j + 1]]`` (one, or a stateful scheduler's starts): ``topo``
    lists every state the seeds reach, each after its predecessors (a state not in it is
    never counted); results go to ``counts[j]`` and ``transitions[j]``, a state counting
    for ``sizes[s]`` states (a contracted ring: its members) and ``events[s]`` events. Per
    ``64 * words`` seeds (a set of them per state, ``words`` 64-bit words), only the states they reach
    are visited: found forward along ``out_off``/``out_tgt``, then pulled in ``topo``
    order. Each pass costs about the states it reaches, so the more seeds a pass takes,
    the fewer passes over much the same states."""
    n_states = len(pred_off) - 1
    mark = np.zeros((n_states, words), dtype=np.uint64)
    position = np.full(n_states, -1, dtype=np.int64)
    for i in range(len(topo)):
        position[topo[i]] = i
    stamp = np.full(n_states, -1, dtype=np.int64)
    stack = np.empty(n_states, dtype=np.int64)
    reached = np.empty(n_states, dtype=np.int64)  # positions in topo of the states reached
    one, magic, shift = np.uint64(1), np.uint64(_MAGIC), np.uint64(58)
    per_pass = 64 * words
    for lo in range(0, len(seed_off) - 1, per_pass):
        hi = min(len(seed_off) - 1, lo + per_pass)
        top = 0
        for j in range(lo, hi):
            for q in range(seed_off[j], seed_off[j + 1]):
                s = seeds[q]
                mark[s, (j - lo) >> 6] |= one << np.uint64((j - lo) & 63)
                if stamp[s] != lo:
                    stamp[s] = lo
                    stack[top] = s
                    top += 1
        found = 0
        while top:
            top -= 1
            s = stack[top]
            if position[s] >= 0:
                reached[found] = position[s]
                found += 1
            for e in range(out_off[s], out_off[s + 1]):
                t = out_tgt[e]
                if stamp[t] != lo:
                    stamp[t] = lo
                    stack[top] = t
                    top += 1
        order = np.sort(reached[:found])
        for i in range(found):
            s = topo[order[i]]
            w = events[s]
            z = sizes[s]
            for e in range(pred_off[s], pred_off[s + 1]):
                p = pred_src[e]
                for word in range(words):
                    mark[s, word] |= mark[p, word]
            for word in range(words):
                m = mark[s, word]
                base = lo + 64 * word
                while m:
                    low = m & (~m + one)
                    b = base + table[(low * magic) >> shift]
                    counts[b] += z
                    transitions[b] += w
                    m ^= low
        for i in range(found):  # the marks of these seeds, cleared for the next pass
            mark[topo[order[i]]] = 0
        for q in range(seed_off[lo], seed_off[hi]):
            mark[seeds[q]] = 0


def _peel_py(out_off: np.ndarray, tgt: np.ndarray, w: np.ndarray, pred_off: np.ndarray,
             pred_src: np.ndarray, outdeg: np.ndarray, reach: np.ndarray, best: np.ndarray,
             box: np.ndarray, order: np.ndarray) -> int:
    """Peel sinks (``outdeg`` 0) state by state, each after all its successors: its
    ``reach`` (own flags or those of its successors), ``best`` (largest ``w`` + ``best``
    over its edges) and ``box`` (grown by its successors'), in place; the peeled states go
    to ``order`` (sinks first). Returns how many were peeled."""
    n_states = len(out_off) - 1
    count = 0
    for s in range(n_states):
        if outdeg[s] == 0:
            order[count] = s
            count += 1
    head = 0
    while head < count:
        s = order[head]
        head += 1
        for e in range(out_off[s], out_off[s + 1]):
            t = tgt[e]
            reach[s] |= reach[t]
            b = w[e] + best[t]
            if b > best[s]:
                best[s] = b
            if box[t, 0] < box[s, 0]:
                box[s, 0] = box[t, 0]
            if box[t, 1] < box[s, 1]:
                box[s, 1] = box[t, 1]
            if box[t, 2] > box[s, 2]:
                box[s, 2] = box[t, 2]
            if box[t, 3] > box[s, 3]:
                box[s, 3] = box[t, 3]
        for e in range(pred_off[s], pred_off[s + 1]):
            p = pred_src[e]
            outdeg[p] -= 1
            if outdeg[p] == 0:
                order[count] = p
                count += 1
    return count




def peel(out_off: np.ndarray, tgt: np.ndarray, w: np.ndarray, pred_off: np.ndarray,
         pred_src: np.ndarray, outdeg: np.ndarray, reach: np.ndarray, best: np.ndarray,
         box: np.ndarray) -> np.ndarray:
    """The peeled states, sinks first (compiled; ``reach``, ``best``, ``box`` and
    ``outdeg`` are updated in place, see :func:`_peel_py`)."""
    order = np.empty(len(out_off) - 1, dtype=np.int64)
    count = _jit(_peel_py)(out_off, tgt.astype(np.int64), w.astype(np.int64), pred_off,
                  pred_src.astype(np.int64), outdeg, reach, best, box, order)
    return order[:count]


SEED_WORDS = 16
"""64-bit words of seeds per pass of :func:`seed_counts` (fewer when the graph is large)."""


def seed_counts(topo: np.ndarray, pred_off: np.ndarray, pred_src: np.ndarray,
                out_off: np.ndarray, out_tgt: np.ndarray, seeds: np.ndarray,
                events: np.ndarray, seed_off: np.ndarray | None = None,
                sizes: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per seed: the states and events it reaches (compiled; see the module docstring).
    ``seed_off``: seed ``j`` is the states ``seeds[seed_off[j]:seed_off[j + 1]]`` together
    (default: one state each); ``sizes``: the states each state counts for (default one).
    A pass takes up to ``64 * SEED_WORDS`` seeds (the marks of
    the graph in at most 128 MB)."""
    if seed_off is None:
        seed_off = np.arange(len(seeds) + 1)
    k = len(seed_off) - 1
    counts = np.zeros(k, dtype=np.int64)
    transitions = np.zeros(k, dtype=np.int64)
    states = len(pred_off) - 1
    words = max(1, min(SEED_WORDS, -(-k // 64), (128 << 20) // (8 * max(1, states))))
    _jit(_seed_counts_py)(topo.astype(np.int64), pred_off.astype(np.int64),
                          pred_src.astype(np.int64), out_off.astype(np.int64),
                          out_tgt.astype(np.int64), seeds.astype(np.int64),
                          seed_off.astype(np.int64), events.astype(np.int64),
                          np.ones(states, np.int64) if sizes is None else sizes.astype(np.int64),
                          _DE_BRUIJN,
                          words, counts, transitions)
    return counts, transitions
