"""Census: every initial configuration of a box, once per symmetry class, counted per class.

SEMANTICS.md §1-2. A configuration has ``n`` robots on distinct nodes
and ``m`` meeting nodes (a robot may stand on a meeting node). It *fits* a
``w x h`` box of nodes when some placement of it (a translate of one of its 8
images under D4) lies inside the box. Two configurations are the same when one
is the image of the other under a translation and an element of D4.

The *canonical form* of a configuration is, among its 8 images translated so
that the MER's lower-left corner is the origin, the one whose key
``(sorted robots, sorted meeting nodes)`` is smallest. It does not depend on
any box, so :func:`canonical` and :func:`enumerate_configurations` agree.

The enumeration is vectorised: every placement in the box whose MER touches
the origin is encoded as two bitmasks (robots, meeting nodes) in all 8 images
at once; node ``(x, y)`` of an ``S x S`` frame gets bit ``S*S - 1 - (x*S + y)``,
so a larger mask pair means a smaller sorted-tuple key. The representatives
come out sorted by that key: the order is the same on every run and hash seed.

>>> census(1, 1, 2, 1).counts  # doctest: +ELLIPSIS
{'I11': 0, 'I12': 0, 'I13': 2, ...}
>>> [c.robots + tuple(sorted(c.meeting_nodes)) for c in enumerate_configurations(1, 1, 2, 1)]
[((0, 0), (0, 0)), ((0, 0), (0, 1))]
>>> canonical(Configuration([(5, 5)], [(6, 5)])) == Configuration([(0, 0)], [(0, 1)])
True
"""

from __future__ import annotations

import itertools
import math
import numbers
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import cache, lru_cache

import numpy as np

from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.canonical import Key, canonical_form
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.symmetry import Automorphism, meeting_automorphisms
from gather_verify.theory import get_fact

MAX_SIDE = 8
"""Largest box side: an ``S x S`` frame must fit one 64-bit mask."""
MAX_PLACEMENTS = 50_000_000
"""Largest ``C(w*h, n) * C(w*h, m)`` the census will sweep (minutes of work, GBs of memory beyond)."""
_CHUNK = 1 << 20  # placements encoded per numpy batch

CanonicalKey = Key


def _check_int(value: object, what: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InvalidInput(f"bad {what} {value!r}: expected an integer")
    if not low <= int(value) <= high:
        raise InvalidInput(f"bad {what} {value}: must be in [{low}, {high}]")
    return int(value)


def validate_census_arguments(n: object, m: object, w: object, h: object) -> tuple[int, int, int, int]:
    """Check a census request; ``ValueError`` names the bad value.

    >>> validate_census_arguments(3, 3, 4, 4)
    (3, 3, 4, 4)
    >>> validate_census_arguments(17, 1, 4, 4)
    Traceback (most recent call last):
    ...
    gather_verify.errors.InvalidInput: bad robot count n=17: a 4x4 box has only 16 nodes
    """
    w = _check_int(w, "box width", 1, MAX_SIDE)
    h = _check_int(h, "box height", 1, MAX_SIDE)
    n = _check_int(n, "robot count", 1, MAX_SIDE * MAX_SIDE)
    m = _check_int(m, "meeting node count", 1, MAX_SIDE * MAX_SIDE)
    cells = w * h
    if n > cells:
        raise InvalidInput(f"bad robot count n={n}: a {w}x{h} box has only {cells} nodes")
    if m > cells:
        raise InvalidInput(f"bad meeting node count m={m}: a {w}x{h} box has only {cells} nodes")
    placements = math.comb(cells, n) * math.comb(cells, m)
    if placements > MAX_PLACEMENTS:
        raise InvalidInput(
            f"census of n={n}, m={m} in a {w}x{h} box has {placements} placements, "
            f"more than the limit {MAX_PLACEMENTS}: use a smaller box or fewer robots"
        )
    return n, m, w, h


# -- the canonical form, plain Python ------------------------------------------------


def canonical_key(configuration: Configuration) -> CanonicalKey:
    """``(sorted robots, sorted meeting nodes)`` of the canonical image (see module doc):
    :func:`gather_verify.model.canonical.canonical_form` of the robot multiset."""
    return canonical_form(configuration.robots, configuration.meeting_nodes).key


def canonical(configuration: Configuration) -> Configuration:
    """The canonical representative of ``configuration`` under translation and D4."""
    robots, meeting = canonical_key(configuration)
    return Configuration.trusted(robots, frozenset(meeting))


# -- the enumeration, vectorised -------------------------------------------------------


def _subsets(cells: int, k: int) -> np.ndarray:
    """All ``k``-subsets of ``range(cells)`` as rows, in lexicographic order."""
    flat = np.fromiter(itertools.chain.from_iterable(itertools.combinations(range(cells), k)),
                       dtype=np.int16, count=math.comb(cells, k) * k)
    return flat.reshape(-1, k)


@cache
def _bits(side: int) -> np.ndarray:
    """The mask of each node of an ``S x S`` frame, by index ``x*S + y``."""
    return np.left_shift(np.uint64(1), np.arange(side * side - 1, -1, -1, dtype=np.uint64))


def _masks(xs: np.ndarray, ys: np.ndarray, side: int) -> np.ndarray:
    """Bitmasks of point sets (rows), node ``(x, y)`` at bit ``side*side - 1 - (x*side + y)``.
    Column by column: numpy reduces a row of a few points far slower than it ORs columns."""
    bits, cells = _bits(side), xs * side + ys
    out = bits[cells[:, 0]]
    for j in range(1, cells.shape[1]):
        out |= bits[cells[:, j]]
    return out


def _canonical_masks(n: int, m: int, w: int, h: int) -> np.ndarray:
    """Sorted unique ``(robot mask, meeting mask)`` rows of the canonical images,
    largest first (that is, smallest canonical key first)."""
    side = max(w, h)
    robot_sets, meeting_sets = _subsets(w * h, n), _subsets(w * h, m)
    found: list[np.ndarray] = []
    rows_per_chunk = max(1, _CHUNK // len(meeting_sets))
    for start in range(0, len(robot_sets), rows_per_chunk):
        block = robot_sets[start:start + rows_per_chunk]
        # every (robot set, meeting set) pair of this block
        r = np.repeat(block, len(meeting_sets), axis=0)
        mt = np.tile(meeting_sets, (len(block), 1))
        points = np.concatenate([r, mt], axis=1)
        xs, ys = (points % w).astype(np.int64), (points // w).astype(np.int64)
        # keep the placements whose MER touches the origin (one per translation class)
        keep = (xs.min(axis=1) == 0) & (ys.min(axis=1) == 0)
        xs, ys = xs[keep], ys[keep]
        best_r = best_m = None
        for g in geometry.ALL:
            a, b, c, d = geometry.MATRICES[g]
            gx, gy = a * xs + b * ys, c * xs + d * ys
            gx -= gx.min(axis=1, keepdims=True)
            gy -= gy.min(axis=1, keepdims=True)
            mr, mm = _masks(gx[:, :n], gy[:, :n], side), _masks(gx[:, n:], gy[:, n:], side)
            if best_r is None:
                best_r, best_m = mr, mm
            else:
                better = (mr > best_r) | ((mr == best_r) & (mm > best_m))
                best_r, best_m = np.where(better, mr, best_r), np.where(better, mm, best_m)
        found.append(np.unique(np.stack([best_r, best_m], axis=1), axis=0))
    unique = np.unique(np.concatenate(found), axis=0)
    return unique[::-1]


@lru_cache(maxsize=1 << 17)
def _decode(mask: int, side: int) -> tuple[Node, ...]:
    """Nodes of a mask, sorted (remembered: a 4 x 4 box has 65,536 masks, and the census of
    n = 4, m = 4 decodes 711,852 of them)."""
    top = side * side - 1
    return tuple(sorted(divmod(top - bit, side) for bit in range(top + 1) if mask >> bit & 1))


def _canonical_masks_lazy(n: int, m: int, w: int, h: int,
                          group: tuple[int, ...] = geometry.ALL) -> Iterator[np.ndarray]:
    """The rows of :func:`_canonical_masks`, in the same order, a block at a time.

    Every class has its canonical image among the placements of the ``side x side``
    frame whose MER touches the origin (the image fits ``w x h`` or ``h x w``). So
    the robot sets of the frame, taken in ``itertools.combinations`` order over
    the nodes sorted by ``(x, y)``, each with every meeting set in that order,
    come in increasing canonical key; keeping the placements that are their own
    canonical image and fit the box gives every class once, in order, without
    looking past the last one asked for. Blocks start small and double, so the
    first configurations cost next to nothing (``sweep --limit``).

    ``group``: the linear parts the classes are taken up to (with every translation): the
    frame group of the robots (SEMANTICS.md §3), all of D4 by default. Under a common
    compass a rotated copy is another problem, so the classes are translation classes,
    and a shape fits the box only as placed."""
    side = max(w, h)
    transposes = any(geometry.MATRICES[g][1] != 0 for g in group)
    # the nodes of the box and of its transpose, sorted by (x, y)
    frame = np.array([(x, y) for x in range(side) for y in range(side)
                      if (x < w and y < h) or (x < h and y < w)], dtype=np.int64)
    meeting_sets = _subsets(len(frame), m)
    mx, my = frame[meeting_sets, 0], frame[meeting_sets, 1]
    m_left, m_low = mx.min(axis=1), my.min(axis=1)  # the meeting sets' extents, once
    m_wide, m_high = mx.max(axis=1), my.max(axis=1)
    robots_iter = itertools.combinations(range(len(frame)), n)
    per_block = 1
    while True:
        block = np.array(list(itertools.islice(robots_iter, per_block)), dtype=np.int64)
        if not len(block):
            return
        per_block = min(2 * per_block, max(1, _CHUNK // len(meeting_sets)))
        bx, by = frame[block, 0], frame[block, 1]
        # every (robot set, meeting set) pair, row-major; those whose MER touches the origin
        # and fits the box, told from the two sets' own extents before any pair is built
        wide = np.maximum(bx.max(axis=1)[:, None], m_wide)
        high = np.maximum(by.max(axis=1)[:, None], m_high)
        fits = (wide < w) & (high < h)
        if transposes:  # some element turns a W x H shape into an H x W one
            fits |= (wide < h) & (high < w)
        keep = ((np.minimum(bx.min(axis=1)[:, None], m_left) == 0)
                & (np.minimum(by.min(axis=1)[:, None], m_low) == 0) & fits)
        ri, mi = np.nonzero(keep)
        xs = np.concatenate([bx[ri], mx[mi]], axis=1)
        ys = np.concatenate([by[ri], my[mi]], axis=1)
        # an image's x is x, W - x, y or H - y once moved back to the origin (W, H: the MER)
        wide, high = wide[ri, mi][:, None], high[ri, mi][:, None]
        axes = {(1, 0): xs, (-1, 0): wide - xs, (0, 1): ys, (0, -1): high - ys}
        own_r, own_m = _masks(xs[:, :n], ys[:, :n], side), _masks(xs[:, n:], ys[:, n:], side)
        alive = np.arange(len(xs))  # the rows no image has beaten yet
        for g in group:
            if g == geometry.IDENTITY:
                continue
            a, b, c, d = geometry.MATRICES[g]
            gx, gy = axes[a, b][alive], axes[c, d][alive]
            mr, mm = _masks(gx[:, :n], gy[:, :n], side), _masks(gx[:, n:], gy[:, n:], side)
            r, mt = own_r[alive], own_m[alive]
            alive = alive[(mr < r) | ((mr == r) & (mm <= mt))]
        if len(alive):
            yield np.stack([own_r[alive], own_m[alive]], axis=1)


def enumerate_configurations(n: int, m: int, w: int, h: int,
                             frames: str = "all") -> Iterator[Configuration]:
    """Canonical representatives of every configuration with ``n`` robots on
    distinct nodes and ``m`` meeting nodes that fits a ``w x h`` box, sorted by
    canonical key (deterministic), one per class of translation and the frame group
    ``frames`` (``all``: D4; ``chirality``: the rotations; ``compass``: translations
    only): a sweep never identifies two configurations its robots can tell apart. Lazy:
    taking the first ``k`` costs about ``k``.

    >>> [sum(1 for _ in enumerate_configurations(2, 1, 2, 2, f)) for f in ("all", "chirality", "compass")]
    [4, 5, 20]
    """
    from gather_verify.model.view import FRAME_SETS

    n, m, w, h = validate_census_arguments(n, m, w, h)
    if frames not in FRAME_SETS:
        raise InvalidInput(f"unknown frames {frames!r}: use one of {', '.join(FRAME_SETS)}")
    side = max(w, h)
    for block in _canonical_masks_lazy(n, m, w, h, FRAME_SETS[frames]):
        for robot_mask, meeting_mask in block.tolist():
            yield Configuration.trusted(_decode(robot_mask, side),
                                        frozenset(_decode(meeting_mask, side)))


@dataclass(frozen=True)
class Census:
    """Counts per class (in the order of the fact ``class``'s values, zeros included) of a box's configurations."""

    n: int
    m: int
    box: tuple[int, int]
    total: int
    counts: dict[str, int]
    representatives: tuple[Configuration, ...] = field(default=(), repr=False)
    classes: tuple[str, ...] = field(default=(), repr=False)  # class of each representative

    def examples(self, name: str) -> list[Configuration]:
        """The representatives of class ``name``."""
        return [c for c, k in zip(self.representatives, self.classes, strict=True) if k == name]

    def to_json(self) -> dict[str, object]:
        return {"total": self.total, "classes": dict(self.counts),
                "robots": self.n, "meeting_nodes": self.m, "box": list(self.box)}


def census(n: int, m: int, w: int, h: int, *, keep: bool = True,
           frames: str = "all") -> Census:
    """Classify one representative per class of the ``w x h`` box and count per class
    (classes up to translation and the isometries of ``frames``, as a sweep counts them).

    ``keep=False`` drops the representatives (only the counts are kept).
    """
    n, m, w, h = validate_census_arguments(n, m, w, h)
    class_of = get_fact("class")  # the paper's classes (gather_verify.theory)
    counts = dict.fromkeys(class_of.values, 0)
    reps: list[Configuration] = []
    names: list[str] = []
    aut_m_cache: dict[frozenset[Node], list[Automorphism]] = {}
    for c in enumerate_configurations(n, m, w, h, frames):
        aut_m = aut_m_cache.get(c.meeting_nodes)
        if aut_m is None:
            aut_m = aut_m_cache[c.meeting_nodes] = meeting_automorphisms(c)
        name = class_of.of(c, aut_m_all=aut_m)
        counts[name] += 1
        if keep:
            reps.append(c)
            names.append(name)
    return Census(n, m, (w, h), sum(counts.values()), counts, tuple(reps), tuple(names))
