"""Compiled kernels of the union engine (numba), and the switch back to numpy.

The union engine (:mod:`gather_verify.engine.union`) counts, for every seed of a
meeting-node class, the states and events its own search would see: a set of
seeds per state, 64 a word, pulled along the edges from the sources down. In
numpy that is a pass over every state per 64 seeds, whatever their reach; a
compiled loop visits each (state, seed) pair once, through the bits that are set.

``GATHER_VERIFY_KERNELS=numpy`` (or numba missing) selects the numpy path,
which stays the tested reference (``tests/test_union_kernels.py``).
"""

from __future__ import annotations

import os

import numpy as np

try:
    import numba
except ImportError:  # pragma: no cover - numba is a dependency; the numpy path remains
    numba = None

_MAGIC = 0x03F79D71B4CB0A89
_DE_BRUIJN = np.zeros(64, dtype=np.int64)
for _i in range(64):
    _DE_BRUIJN[((1 << _i) * _MAGIC % (1 << 64)) >> 58] = _i


def compiled() -> bool:
    """Whether the compiled kernels run (numba installed, and not switched off)."""
    return numba is not None and os.environ.get("GATHER_VERIFY_KERNELS", "numba") != "numpy"


def _seed_counts_py(topo: np.ndarray, pred_off: np.ndarray, pred_src: np.ndarray,
                    seeds: np.ndarray, events: np.ndarray, table: np.ndarray,
                    counts: np.ndarray, transitions: np.ndarray) -> None:
    """States and events reachable from each of ``seeds``: ``topo`` lists every state
    the seeds reach, each after its predecessors; results go to ``counts[j]`` and
    ``transitions[j]`` for ``seeds[j]``."""
    n_states = len(pred_off) - 1
    mark = np.zeros(n_states, dtype=np.uint64)
    one, magic, shift = np.uint64(1), np.uint64(_MAGIC), np.uint64(58)
    for lo in range(0, len(seeds), 64):
        mark[:] = 0
        hi = min(len(seeds), lo + 64)
        for j in range(lo, hi):
            mark[seeds[j]] |= one << np.uint64(j - lo)
        for s in topo:
            m = mark[s]
            for e in range(pred_off[s], pred_off[s + 1]):
                m |= mark[pred_src[e]]
            mark[s] = m
            w = events[s]
            while m:
                low = m & (~m + one)
                b = lo + table[(low * magic) >> shift]
                counts[b] += 1
                transitions[b] += w
                m ^= low


_seed_counts = (numba.njit(cache=True, nogil=True)(_seed_counts_py) if numba is not None
                else None)


def seed_counts(topo: np.ndarray, pred_off: np.ndarray, pred_src: np.ndarray,
                seeds: np.ndarray, events: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per seed: the states and events it reaches (compiled; see the module docstring)."""
    counts = np.zeros(len(seeds), dtype=np.int64)
    transitions = np.zeros(len(seeds), dtype=np.int64)
    _seed_counts(topo.astype(np.int64), pred_off.astype(np.int64), pred_src.astype(np.int64),
                 seeds.astype(np.int64), events.astype(np.int64), _DE_BRUIJN, counts,
                 transitions)
    return counts, transitions
