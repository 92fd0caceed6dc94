"""Numpy columns of the bulk engines: one that grows as a search appends to it, and a
read-only view that hands Python ints to the per-element code.

A bulk search appends a chunk of parents (or out-degrees), targets and weights at a time
(:class:`Growing`, amortised doubling, optionally reserved up front; :class:`GrowingBits`
for weights that are all 0 or 1, one bit each) and hands the finished columns to
:class:`~gather_verify.engine.explore.Exploration` as :class:`IntColumn` (or
:class:`BitColumn`), which read like the reference engine's lists and arrays. A search that
keeps its edges stores no parents: :class:`LazyColumn` reads them off the edges
(:func:`first_sources`) when a trace first asks.
"""

from __future__ import annotations

import functools
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np

MADV_NOHUGEPAGE = 15
"""Linux's ``madvise`` advice: no transparent huge pages in this range."""


class IntColumn(Sequence[int]):
    """A read-only view of a numpy column that hands out Python ints (for the
    per-element code in :mod:`properties` and :mod:`plane_check`)."""

    __slots__ = ("_array",)

    def __init__(self, array: np.ndarray):
        self._array: np.ndarray | None = array

    @property
    def array(self) -> np.ndarray:
        assert self._array is not None
        return self._array

    def __len__(self) -> int:
        return len(self.array)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return self.array[i].tolist()
        return int(self.array[i])

    def __iter__(self) -> Iterator[int]:
        for start in range(0, len(self.array), 1 << 16):
            yield from self.array[start:start + (1 << 16)].tolist()


@functools.cache
def glibc() -> Any:
    """The C library when it is glibc (loaded on first use, not at import); else None."""
    import ctypes

    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:  # pragma: no cover - not glibc
        return None
    return libc if hasattr(libc, "malloc_trim") else None


def small_pages(array: np.ndarray) -> np.ndarray:
    """``array`` (untouched room reserved up front), its pages kept small: numpy asks for
    transparent huge pages on large arrays, and a column written from its start would hold
    up to 2 MB resident past its last value; with small pages only what is written is.
    Where there is no glibc, nothing changes."""
    libc = glibc()
    page = 4096
    start = -(-array.ctypes.data // page) * page  # the first whole page
    end = (array.ctypes.data + array.nbytes) // page * page
    if libc is not None and end > start:
        import ctypes

        libc.madvise(ctypes.c_void_p(start), ctypes.c_size_t(end - start), MADV_NOHUGEPAGE)
    return array


class Growing:
    """An append-only numpy column (amortised doubling)."""

    def __init__(self, dtype: Any, capacity: int = 1 << 16):
        self.data = np.empty(capacity, dtype=dtype)
        self.size = 0

    def extend(self, values: np.ndarray) -> None:
        self.claim(len(values))[:] = values

    def claim(self, count: int) -> np.ndarray:
        """The next ``count`` slots, counted as written: the caller fills them in place (no
        temporary array of the values to copy in)."""
        need = self.size + count
        if need > len(self.data):
            grown = np.empty(max(need, 2 * len(self.data)), dtype=self.data.dtype)
            grown[:self.size] = self.data[:self.size]
            self.data = grown
        out = self.data[self.size:need]
        self.size = need
        return out

    def array(self) -> np.ndarray:
        return self.data[:self.size]

    def widen(self, dtype: Any) -> None:
        """Hold larger values from now on (the values so far kept; the reserved room past
        them stays untouched, so costs no memory)."""
        if self.data.dtype != dtype:
            wider = np.empty(len(self.data), dtype=dtype)
            wider[:self.size] = self.data[:self.size]
            self.data = wider


class BitColumn(Sequence[int]):
    """A read-only column of 0/1 values kept one bit each (bit ``i % 8`` of byte ``i // 8``,
    ``np.packbits(..., bitorder="little")``): the weights of a graph whose events move at
    most one robot one edge (ASYNC), an eighth of a byte column."""

    __slots__ = ("bits", "size")

    def __init__(self, bits: np.ndarray, size: int):
        self.bits, self.size = bits, size

    def __len__(self) -> int:
        return self.size

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return self.array[i].tolist() if i.start is None and i.stop is None else \
                self._range(*i.indices(self.size))
        if i < 0:
            i += self.size
        if not 0 <= i < self.size:
            raise IndexError(i)
        return int(self.bits[i >> 3]) >> (i & 7) & 1

    def _range(self, start: int, stop: int, step: int) -> list[int]:
        if stop <= start:
            return [self[k] for k in range(start, stop, step)]
        lo = start >> 3
        got = np.unpackbits(self.bits[lo:(stop + 7) >> 3], bitorder="little")
        return got[start - 8 * lo:stop - 8 * lo:step].tolist()

    def __iter__(self) -> Iterator[int]:
        for start in range(0, self.size, 1 << 16):
            yield from self._range(start, min(self.size, start + (1 << 16)), 1)

    @property
    def array(self) -> np.ndarray:
        """The values as an ``int8`` array (a byte each: a copy, for the numpy code)."""
        return np.unpackbits(self.bits, count=self.size, bitorder="little").view(np.int8)


class GrowingBits:
    """An append-only column of 0/1 values, one bit each (:class:`BitColumn`'s layout)."""

    def __init__(self, capacity: int = 1 << 16):
        self.data = Growing(np.uint8, (capacity + 7) >> 3)
        self.size = 0

    def extend(self, values: np.ndarray) -> None:
        tail = self.size & 7
        if tail:  # the last byte is partly filled: packed again with the new values
            self.data.size -= 1
            last = np.unpackbits(self.data.data[self.data.size:self.data.size + 1],
                                 count=tail, bitorder="little")
            values = np.concatenate([last, values.astype(np.uint8)])
        self.data.extend(np.packbits(values.astype(bool), bitorder="little"))
        self.size += len(values) - tail

    def column(self) -> BitColumn:
        return BitColumn(self.data.array(), self.size)

    def array(self) -> np.ndarray:
        return self.column().array


ID_BYTES = 3
"""Bytes of a target id while every id fits them (:class:`GrowingIds`)."""


def _unpack_ids(raw: np.ndarray) -> np.ndarray:
    """``int32`` ids from their three little-endian bytes each."""
    out = np.zeros((len(raw) // ID_BYTES, 4), dtype=np.uint8)
    out[:, :ID_BYTES] = raw.reshape(-1, ID_BYTES)
    return out.view("<i4").ravel()


class IdColumn(Sequence[int]):
    """A read-only column of the edges' target ids: three bytes each (``packed``, least
    significant first) while every id is below ``2**24``, else ``int32``; :attr:`raw` is what
    the compiled kernels read (with their ``packed`` flag), :attr:`array` an ``int32`` array
    (a copy when packed, for the numpy code)."""

    __slots__ = ("data", "size", "packed")

    def __init__(self, data: np.ndarray, size: int, packed: bool):
        self.data, self.size, self.packed = data, size, packed

    @property
    def raw(self) -> np.ndarray:
        return self.data[:ID_BYTES * self.size] if self.packed else \
            self.data[:4 * self.size].view("<i4")

    @property
    def array(self) -> np.ndarray:
        return _unpack_ids(self.raw) if self.packed else self.raw

    def __len__(self) -> int:
        return self.size

    def _range(self, start: int, stop: int) -> np.ndarray:
        if not self.packed:
            return self.raw[start:stop]
        return _unpack_ids(self.data[ID_BYTES * start:ID_BYTES * max(start, stop)])

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            start, stop, step = i.indices(self.size)
            return self._range(start, stop)[::step].tolist() if step > 0 else \
                [self[k] for k in range(start, stop, step)]
        if i < 0:
            i += self.size
        if not 0 <= i < self.size:
            raise IndexError(i)
        if self.packed:  # (read state by state in the Python code: no array made)
            return int.from_bytes(self.data[ID_BYTES * i:ID_BYTES * i + ID_BYTES].tobytes(),
                                  "little")
        return int(self.raw[i])

    def __iter__(self) -> Iterator[int]:
        for start in range(0, self.size, 1 << 16):
            yield from self._range(start, min(self.size, start + (1 << 16))).tolist()


class GrowingIds:
    """An append-only column of target ids (:class:`IdColumn`'s layout): three bytes each
    while they fit, then four, widened in place (from the last id back, each moving to a
    higher address: no second copy of the edges)."""

    def __init__(self, capacity: int = 1 << 16):
        self.data = Growing(np.uint8, 4 * capacity)  # room for int32 ids (untouched: free)
        self.size = 0
        self.packed = True

    def extend(self, ids: np.ndarray, below: int) -> None:
        """Append ``ids`` (each below ``below``)."""
        if self.packed and below > 1 << (8 * ID_BYTES):
            self._widen()
        # written straight into the column (int32 ids, a bulk search's, are read in place)
        wide = np.ascontiguousarray(ids, dtype="<i4")
        if self.packed:
            raw = wide.view(np.uint8).reshape(-1, 4)[:, :ID_BYTES]
            self.data.claim(ID_BYTES * len(ids)).reshape(-1, ID_BYTES)[:] = raw
        else:
            self.data.claim(4 * len(ids)).view("<i4")[:] = wide
        self.size += len(ids)

    def _widen(self) -> None:
        size, data = self.size, self.data
        data.extend(np.zeros((4 - ID_BYTES) * size, dtype=np.uint8))  # room for 4 bytes each
        wide = data.data[:4 * size].view("<i4")
        step = 1 << 20
        for hi in range(size, 0, -step):  # the last ids first: nothing unread is overwritten
            lo = max(0, hi - step)
            wide[lo:hi] = _unpack_ids(data.data[ID_BYTES * lo:ID_BYTES * hi])
        self.packed = False

    def column(self) -> IdColumn:
        return IdColumn(self.data.array(), self.size, self.packed)


class LazyColumn(IntColumn):
    """An :class:`IntColumn` computed on first use (``make()``), then kept."""

    __slots__ = ("_make",)

    def __init__(self, make: Any):
        self._array = None
        self._make = make

    @property
    def array(self) -> np.ndarray:
        if self._array is None:
            self._array, self._make = self._make(), None
        return self._array


def first_sources(offsets: np.ndarray, targets: np.ndarray | IdColumn, seeds: int,
                  states: int) -> np.ndarray:
    """Per state (``int32``), the first state in id and edge order with an edge to it; -1 for
    the ``seeds`` first ids and a state no edge reaches. A breadth-first search gives a state
    its id at its first occurrence among the successors it generates, in id and edge order,
    and stores every edge of each state it expands: this is its parent column, read off the
    kept edges (compiled: :func:`gather_verify.kernels.first_sources`, the same column).

    >>> first_sources(np.array([0, 2, 3, 4]), np.array([1, 2, 2, 0]), 1, 4).tolist()
    [-1, 0, 0, -1]
    """
    from gather_verify import kernels

    if kernels.enabled():
        if isinstance(targets, IdColumn):
            return kernels.first_sources(offsets, targets.raw, seeds, states, targets.packed)
        return kernels.first_sources(offsets, targets, seeds, states)
    if isinstance(targets, IdColumn):
        targets = targets.array
    parents = np.full(states, -1, dtype=np.int32)
    step = 1 << 16
    for lo in range(0, len(offsets) - 1, step):  # in slices of states: small temporaries
        hi = min(len(offsets) - 1, lo + step)
        a, b = int(offsets[lo]), int(offsets[hi])
        src = np.repeat(np.arange(lo, hi, dtype=np.int32), np.diff(offsets[lo:hi + 1]))
        t, first = np.unique(targets[a:b], return_index=True)  # first edge to each in the slice
        new = (t >= seeds) & (parents[t] < 0)
        parents[t[new]] = src[first[new]]
    return parents
