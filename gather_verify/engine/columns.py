"""Numpy columns of the bulk engines: one that grows as a search appends to it, and a
read-only view that hands Python ints to the per-element code.

A bulk search appends a chunk of parents, offsets, targets and weights at a time
(:class:`Growing`, amortised doubling, optionally reserved up front) and hands the
finished columns to :class:`~gather_verify.engine.explore.Exploration` as
:class:`IntColumn`, which reads like the reference engine's lists and arrays.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np


class IntColumn(Sequence[int]):
    """A read-only view of a numpy column that hands out Python ints (for the
    per-element code in :mod:`properties` and :mod:`check`)."""

    __slots__ = ("array",)

    def __init__(self, array: np.ndarray):
        self.array = array

    def __len__(self) -> int:
        return len(self.array)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return self.array[i].tolist()
        return int(self.array[i])

    def __iter__(self) -> Iterator[int]:
        for start in range(0, len(self.array), 1 << 16):
            yield from self.array[start:start + (1 << 16)].tolist()



class Growing:
    """An append-only numpy column (amortised doubling)."""

    def __init__(self, dtype: Any, capacity: int = 1 << 16):
        self.data = np.empty(capacity, dtype=dtype)
        self.size = 0

    def extend(self, values: np.ndarray) -> None:
        need = self.size + len(values)
        if need > len(self.data):
            grown = np.empty(max(need, 2 * len(self.data)), dtype=self.data.dtype)
            grown[:self.size] = self.data[:self.size]
            self.data = grown
        self.data[self.size:need] = values
        self.size = need

    def array(self) -> np.ndarray:
        return self.data[:self.size]

    def widen(self, dtype: Any) -> None:
        """Hold larger values from now on (the values so far kept)."""
        if self.data.dtype != dtype:
            self.data = self.data.astype(dtype)
