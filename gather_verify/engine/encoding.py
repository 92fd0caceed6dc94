"""The engine's state encoding: robots and states as integers over a box of the grid.

SEMANTICS.md §4. Both engines store a state as one integer key and hand its
robots to the schedulers as *codes* ``cell * (degree + 1) + d``
(``geometry.SLOTS`` = degree + 1 = 5): ``cell`` indexes a node
of the search region (a box, column-major), ``d`` is 0 when the robot is idle,
else 1 + the index in ``geometry.STEPS`` of its pending unit step. A state
packs its codes in base ``SLOTS * cells``; with the reductions on, the codes are
sorted (anonymity) and the key is the least over the usable elements of
``Aut(M)`` (symmetry). The group and the limits of a search are decided here
too (its region, by :mod:`gather_verify.engine.region`), so the engines and the
schedulers share one encoding.
"""

from __future__ import annotations

import os
import resource
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import StrEnum
from functools import cached_property
from typing import Any

import numpy as np

from gather_verify.algorithms.moves import frames_for
from gather_verify.engine.region import DEFAULT_MARGIN
from gather_verify.engine.region import region_box as region_box  # its callers' old import
from gather_verify.kernels.codes import OUTSIDE
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import SLOTS, STEPS, Node
from gather_verify.model.symmetry import Automorphism, meeting_automorphisms
from schedulers.base import Frontier, State

STEP_INDEX = {step: i + 1 for i, step in enumerate(STEPS)}

DEFAULT_MAX_STATES = 30_000_000
DEFAULT_MAX_SECONDS = 3600.0
DEFAULT_MAX_MEMORY_MB = 16_000
"""Defaults sized for a 24 GiB machine (the reference path needs ~300 bytes/state)."""


@dataclass(frozen=True)
class Limits:
    """When to stop: any limit hit makes the search INCOMPLETE (never VERIFIED)."""

    max_states: int = DEFAULT_MAX_STATES
    max_seconds: float = DEFAULT_MAX_SECONDS
    max_memory_mb: float = DEFAULT_MAX_MEMORY_MB
    margin: int = DEFAULT_MARGIN


NO_LIMITS = Limits()
"""The default limits (a module-level value, so it can be a default argument)."""


class Stop(StrEnum):
    """Why a search stopped before expanding every reachable state (its ``stopped``; else
    the name of the halting property it stopped at, or None when it expanded them all).
    A ``str`` enum: reports, JSON and stored rows read the plain name."""

    TIME = "time"  # Limits.max_seconds
    MEMORY = "memory"  # Limits.max_memory_mb
    STATES = "states"  # Limits.max_states
    REGION = "region"  # a successor left the search region (a margin too small)
    SETTLED = "settled"  # every requested property had its counterexample (``settle``)
    WATCH = "watch"  # the finite worlds' search: its ``watch`` asked it to stop


_STATM: list[int] = []  # this process's id and its open /proc/self/statm


def rss_mb() -> float:
    """Resident set size of this process now, in MiB (``/proc``, else the peak), for
    :attr:`Limits.max_memory_mb`. The file stays open (a search asks once per chunk); a
    forked child opens its own."""
    try:
        if not _STATM or _STATM[0] != os.getpid():
            _STATM[:] = [os.getpid(), os.open("/proc/self/statm", os.O_RDONLY)]
        return int(os.pread(_STATM[1], 64, 0).split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    except (OSError, ValueError, IndexError):
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def symmetry_group(initial: Configuration, frames: str) -> list[Automorphism]:
    """The elements of ``Aut(M)`` the symmetry reduction may use with ``frames``."""
    allowed = set(frames_for(frames))
    group = [a for a in meeting_automorphisms(initial)]
    if allowed == set(geometry.ALL):
        return group
    return [a for a in group if a.g in allowed and all(
        geometry.compose(geometry.compose(a.g, f), geometry.inverse(a.g)) in allowed
        for f in allowed)]


LIST_TABLE_CODES = 1 << 20
"""Up to this many codes a symmetry table is a Python list; beyond, a numpy array."""


class Encoding:
    """Robots and states as integers over a box of the grid.

    >>> enc = Encoding((0, 0, 2, 2))
    >>> s = (((0, 0), (1, 0)), ((2, 2), None))
    >>> enc.decode(enc.key(s), 2) == s
    True
    """

    def __init__(self, box: tuple[int, int, int, int], group: Sequence[Automorphism] = (),
                 anonymity: bool = True):
        self.x0, self.y0, x1, y1 = box
        self.width, self.height = x1 - self.x0 + 1, y1 - self.y0 + 1
        self.cells = self.width * self.height
        self.slots = SLOTS
        """A code's slots per cell: degree + 1 (idle, or one pending step)."""
        self.base = self.cells * SLOTS
        self.anonymity = anonymity
        self.tables = [self._table(a) for a in group if a.g != geometry.IDENTITY or a.t != (0, 0)]

    def inside(self, v: Node) -> bool:
        return 0 <= v[0] - self.x0 < self.width and 0 <= v[1] - self.y0 < self.height

    def node(self, cell: int) -> Node:
        return (self.x0 + cell // self.height, self.y0 + cell % self.height)

    def code(self, v: Node, pending: Node | None) -> int:
        cell = (v[0] - self.x0) * self.height + (v[1] - self.y0)
        return cell * SLOTS + (0 if pending is None else STEP_INDEX[(pending[0] - v[0], pending[1] - v[1])])

    def robot(self, code: int) -> tuple[Node, Node | None]:
        cell, d = divmod(code, SLOTS)
        v = self.node(cell)
        return v, (None if d == 0 else geometry.add(v, STEPS[d - 1]))

    def _table(self, a: Automorphism) -> list[int] | np.ndarray:
        """Every code's image under ``a`` (computed with numpy: a wide region has millions of
        codes). A list, which the reference engine indexes fastest, up to
        :data:`LIST_TABLE_CODES` codes; an array beyond, to bound the memory."""
        code = np.arange(self.base, dtype=np.int64)
        cell, d = np.divmod(code, SLOTS)
        x, y = self.x0 + cell // self.height, self.y0 + cell % self.height
        ma, mb, mc, md = geometry.MATRICES[a.g]
        nx_, ny_ = ma * x + mb * y + a.t[0], mc * x + md * y + a.t[1]
        steps = np.array([(0, 0), *STEPS], dtype=np.int64)  # row d: the pending step
        sx, sy = steps[d, 0], steps[d, 1]
        turned = (ma * sx + mb * sy) * 3 + (mc * sx + md * sy)  # the image step, as one int
        direction = np.zeros(9 * 2, dtype=np.int64)  # image step -> its d (0: none)
        for k, (tx, ty) in enumerate(STEPS):
            direction[tx * 3 + ty] = k + 1
        out = ((nx_ - self.x0) * self.height + (ny_ - self.y0)) * SLOTS + direction[turned]
        return out.tolist() if self.base <= LIST_TABLE_CODES else out

    def pack(self, codes: Iterable[int]) -> int:
        key, scale = 0, 1
        for c in codes:
            key += c * scale
            scale *= self.base
        return key

    def key(self, state: State) -> int:
        """The stored key of ``state`` (its class under the enabled reductions)."""
        return self.least_key([self.code(v, p) for v, p in state])

    def least_key(self, codes: list[int]) -> int:
        """The least packed key of the robots' ``codes`` under the reductions' tables."""
        if self.anonymity:
            codes.sort()
        best = self.pack(codes)
        for table in self.tables:
            image = [table[c] for c in codes] if isinstance(table, list) else \
                table[codes].tolist()
            if self.anonymity:
                image.sort()
            best = min(best, self.pack(image))
        return best

    def decode(self, key: int, n: int) -> State:
        out = []
        for _ in range(n):
            key, c = divmod(key, self.base)
            out.append(self.robot(c))
        return tuple(out)

    @cached_property
    def xy(self) -> np.ndarray:
        """``xy[cell]``: the node of each cell as an ``(x, y)`` row (:meth:`node`, for all)."""
        cells = np.arange(self.cells, dtype=np.int64)
        return np.stack([self.x0 + cells // self.height, self.y0 + cells % self.height], axis=1)

    @cached_property
    def neighbour(self) -> np.ndarray:
        """``neighbour[cell, k]``: the cell one ``STEPS[k]`` away, :data:`OUTSIDE
        <gather_verify.kernels.codes.OUTSIDE>` when that node lies outside the box (a limit
        of the search). Z² has every edge: the table never holds ``NO_EDGE``."""
        out = np.full((self.cells, len(STEPS)), OUTSIDE, dtype=np.int64)
        for k, (dx, dy) in enumerate(STEPS):
            x, y = self.xy[:, 0] + dx - self.x0, self.xy[:, 1] + dy - self.y0
            inside = (x >= 0) & (x < self.width) & (y >= 0) & (y < self.height)
            out[inside, k] = x[inside] * self.height + y[inside]
        return out

    def frontier(self, codes: np.ndarray, masks: np.ndarray) -> Frontier:
        """States as a scheduler's bulk interface takes them (``schedulers.base.Frontier``)."""
        return Frontier(codes, masks, self.neighbour)


class Turns:
    """A ``stateful`` scheduler's own state (round-robin's order and turn) in a Z² key: the
    robots' key (an :class:`Encoding` built without anonymity: the robots keep their places)
    plus ``base ** n`` times the scheduler's ``state_index``.

    The reductions act on that state too, so they stay sound (SEMANTICS.md §4):

    - anonymity: identical robots are relabelled by the scheduler's ``relabel`` (round-robin:
      so that its order is the first it may fix), and the robots listed in that labelling;
      the same robot then acts at each turn, so the state has the same future. Relabelling
      is the only freedom: sorting the robots would forget whose turn comes when;
    - symmetry: an element of ``Aut(M)`` in the frame group moves every robot's node and
      pending step and leaves the scheduler's state alone (its order names robots, not
      nodes), as it does without one.
    """

    def __init__(self, sched: Any, n: int, anonymity: bool, base: int):
        self.sched, self.n, self.anonymity = sched, n, anonymity
        self.scale = base ** n
        self.count = sched.state_count(n)

    def starts(self) -> list[object]:
        return list(self.sched.starts(self.n))

    def key(self, enc: Encoding, state: State, extra: object) -> int:
        """The stored key of ``state`` with the scheduler in ``extra``."""
        if self.anonymity:
            perm, extra = self.sched.relabel(extra, self.n)
            state = tuple(state[i] for i in perm)
        return enc.key(state) + self.scale * self.sched.state_index(extra, self.n)

    def extra(self, key: int) -> object:
        """The scheduler's state of a stored key."""
        return self.sched.state_of(key // self.scale, self.n)

    def of_keys(self, keys: np.ndarray) -> np.ndarray:
        """The scheduler's ``state_index`` of each stored key (``uint64``), as ``int64``."""
        return (keys // np.uint64(self.scale)).astype(np.int64)

    def fits(self) -> bool:
        """Whether every key fits 63 bits (the bulk engines' keys)."""
        return self.scale * self.count < 2**63


class LuminousEncoding(Encoding):
    """:class:`Encoding` with each robot's light (§10): a robot's code is
    ``(cell * SLOTS + d) * K + colour`` over K colours, and a state's robots are
    ``(node, pending, colour)``. With K = 1 the codes, hence the keys, are those of
    :class:`Encoding`. The symmetries move nodes and pending steps, never colours.

    >>> enc = LuminousEncoding((0, 0, 2, 2), colours=3)
    >>> s = (((0, 0), (1, 0), 2), ((2, 2), None, 0))
    >>> enc.decode(enc.key(s), 2) == s
    True
    """

    def __init__(self, box: tuple[int, int, int, int], group: Sequence[Automorphism] = (),
                 anonymity: bool = True, colours: int = 1):
        super().__init__(box, group, anonymity)
        self.colours = colours
        self.base = self.cells * SLOTS * colours
        if colours > 1:
            lit = np.arange(colours, dtype=np.int64)
            tables = [(np.asarray(t, dtype=np.int64)[:, None] * colours + lit).reshape(-1)
                      for t in self.tables]
            self.tables = [t.tolist() if self.base <= LIST_TABLE_CODES else t for t in tables]

    def key(self, state: State) -> int:
        """The stored key of a luminous state (robots ``(node, pending, colour)``)."""
        k = self.colours
        robots: Any = state
        return self.least_key([self.code(v, p) * k + c for v, p, c in robots])

    def decode(self, key: int, n: int) -> State:
        out: list[Any] = []
        for _ in range(n):
            key, c = divmod(key, self.base)
            code, colour = divmod(c, self.colours)
            out.append((*self.robot(code), colour))
        return tuple(out)
