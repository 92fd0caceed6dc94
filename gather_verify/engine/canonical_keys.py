"""Canonical keys of whole arrays of states: what :meth:`Encoding.key` computes for one.

A bulk step produces successors as rows of robot codes (``cell * SLOTS + d``). Their
stored keys must be exactly the reference engine's (the same states, ids and traces):
the codes packed in base ``SLOTS * cells``, sorted when anonymity is on, and the least over
the usable elements of ``Aut(M)`` when symmetry is on. :class:`Canon` computes them for
a whole array with a handful of elementwise operations; :func:`decode_keys` is the way
back from keys to codes.
"""

from __future__ import annotations

import numpy as np

from gather_verify.engine.encoding import Encoding


class Canon:
    """Canonical keys of code rows under the enabled reductions (as ``Encoding.key``)."""

    def __init__(self, enc: Encoding, n: int):
        self.anonymity = enc.anonymity
        self.tables = [np.asarray(t, dtype=np.int64) for t in enc.tables]
        self.powers = np.array([enc.base ** j for j in range(n)], dtype=np.uint64)
        self.table_rows = np.array(self.tables, dtype=np.int64) if self.tables else \
            np.zeros((0, 1), dtype=np.int64)
        """The tables as the rows of one array (for the compiled keys)."""
        self.ordered = bool(self.table_rows.size == 0 or (
            self.table_rows.min() >= 0 and self.table_rows.max() < enc.base))
        """Whether every image of a code is a code (a digit of the keys): then a sorted
        image's largest value is its key's leading digit."""

    def pack(self, columns: list[np.ndarray]) -> np.ndarray:
        out = columns[0].astype(np.uint64)
        for j in range(1, len(columns)):
            out += columns[j].astype(np.uint64) * self.powers[j]
        return out

    def sort(self, columns: list[np.ndarray]) -> list[np.ndarray]:
        """Sort each row, the columns given as separate arrays (a transposition network:
        a handful of elementwise min/max, much faster than a row-wise sort for small n)."""
        cols = list(columns)
        n = len(cols)
        for rnd in range(n):
            for i in range(rnd % 2, n - 1, 2):
                lo, hi = np.minimum(cols[i], cols[i + 1]), np.maximum(cols[i], cols[i + 1])
                cols[i], cols[i + 1] = lo, hi
        return cols

    def keys(self, codes: np.ndarray) -> np.ndarray:
        """The stored key of each row of robot codes."""
        columns = [np.ascontiguousarray(codes[:, j]) for j in range(codes.shape[1])]
        best = self.pack(self.sort(columns) if self.anonymity else columns)
        for table in self.tables:
            image = [table[c] for c in columns]
            np.minimum(best, self.pack(self.sort(image) if self.anonymity else image), out=best)
        return best


def decode_keys(keys: np.ndarray, base: int, n: int) -> np.ndarray:
    """The robot codes of each key (one row per key, ``n`` codes, base ``base``)."""
    codes = np.empty((len(keys), n), dtype=np.int64)
    rest, b = keys, np.uint64(base)
    for j in range(n):
        quot = rest // b  # (floor division by a constant is the fast one; % is not)
        codes[:, j] = (rest - quot * b).view(np.int64)
        rest = quot
    return codes

