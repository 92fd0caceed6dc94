"""The paper's strings: corner strings, key and leading corners, configuration views, orderings.

Paper §2 ("Configuration view", "Symmetricity of the set M") and §4 (the
orderings O, O', O''). From each corner of a rectangle two strings are read,
one per side: the scan runs along the *fast* side (one grid line, from the
corner), then steps one line along the other side, and so on ("column by
column"). A string holds ``l(v)`` per node (``lambda(v)`` for the meeting-node
strings ``alpha``). The *string representation* of a corner is the string
read along its shorter side; on a square, the larger of its two strings. The
*key corner* has the largest representation; the *leading corner* the largest
``alpha``.

The paper's Figure "string2", laid out from its string in columns of 5:

>>> from gather_verify.model.configuration import Configuration
>>> c = from_string("001001400004000000000000404000400401000000100", 5)
>>> key_scans(c)[0].text
'001001400004000000000000404000400401000000100'
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import Literal

from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import (
    EMPTY,
    MEETING,
    ROBOT,
    ROBOT_ON_MEETING,
    Configuration,
)
from gather_verify.model.geometry import Node

Rect = tuple[int, int, int, int]
AlphaRegion = Literal["mer", "mer_f"]


@dataclass(frozen=True)
class Scan:
    """One corner string: where it starts, how it runs, what it reads.

    Held sparsely: ``labels`` lists the position and label of every node with a
    non-zero label, so a scan costs the number of labelled nodes, not the area of
    its rectangle (robots that walk far away make the MER large). ``nodes`` and
    ``text`` give the dense string when one is shown."""

    corner: Node
    fast: Node  # unit step along the scanned grid line
    slow: Node  # unit step from one grid line to the next
    rect: Rect
    labels: tuple[tuple[int, int], ...]  # (position, label), non-zero labels, by position

    @cached_property
    def line(self) -> int:
        """Nodes on one scanned grid line."""
        x0, y0, x1, y1 = self.rect
        return (x1 - x0 if self.fast[0] else y1 - y0) + 1

    @cached_property
    def size(self) -> int:
        x0, y0, x1, y1 = self.rect
        return (x1 - x0 + 1) * (y1 - y0 + 1)

    def index(self, v: Node) -> int:
        """Position of ``v`` in the scan: the paper's ``d'`` of the configuration view."""
        x0, y0, x1, y1 = self.rect
        if not (x0 <= v[0] <= x1 and y0 <= v[1] <= y1):
            raise ValueError(f"{v} is not in the scanned rectangle {self.rect}")
        dx, dy = v[0] - self.corner[0], v[1] - self.corner[1]
        i = dx * self.fast[0] + dy * self.fast[1]
        j = dx * self.slow[0] + dy * self.slow[1]
        return j * self.line + i

    @cached_property
    def order(self) -> tuple[tuple[int, int], ...]:
        """A key that orders scans of one length as their ``text`` (the first differing
        label decides, and label 0 is the least): the earlier a non-zero label, the larger."""
        return tuple((-p, label) for p, label in self.labels)

    @cached_property
    def nodes(self) -> tuple[Node, ...]:
        """Every node of the rectangle, in scan order."""
        return scan_nodes(self.rect, self.corner, self.fast, self.slow)

    @cached_property
    def text(self) -> str:
        """The dense string: one label digit per node."""
        out = ["0"] * self.size
        for p, label in self.labels:
            out[p] = str(label)
        return "".join(out)

    def describe(self) -> str:
        return f"corner {list(self.corner)} along {list(self.fast)} then {list(self.slow)}"


def corners(rect: Rect) -> tuple[Node, ...]:
    """The four corners of a rectangle (x0, y0, x1, y1), counter-clockwise from lower left."""
    x0, y0, x1, y1 = rect
    return ((x0, y0), (x1, y0), (x1, y1), (x0, y1))


def scan_nodes(rect: Rect, corner: Node, fast: Node, slow: Node) -> tuple[Node, ...]:
    """Nodes of ``rect`` in scan order from ``corner``."""
    x0, y0, x1, y1 = rect
    length = {0: x1 - x0, 1: y1 - y0}
    fast_len = length[0] if fast[0] else length[1]
    slow_len = length[0] if slow[0] else length[1]
    cx, cy = corner
    return tuple(
        (cx + i * fast[0] + j * slow[0], cy + i * fast[1] + j * slow[1])
        for j in range(slow_len + 1)
        for i in range(fast_len + 1)
    )


def _directions(rect: Rect, corner: Node) -> tuple[Node, Node]:
    x0, y0, _, _ = rect
    h = (1, 0) if corner[0] == x0 else (-1, 0)
    v = (0, 1) if corner[1] == y0 else (0, -1)
    return h, v


def all_scans(rect: Rect, value: Callable[[Node], int],
              support: Iterable[Node] | None = None) -> list[Scan]:
    """The eight corner strings of ``rect`` (two per corner). ``support``: the nodes where
    ``value`` may be non-zero (default: every node of ``rect``)."""
    x0, y0, x1, y1 = rect
    if support is None:
        support = scan_nodes(rect, (x0, y0), (1, 0), (0, 1))
    marked = [(v, k) for v in support if (k := value(v))
              and x0 <= v[0] <= x1 and y0 <= v[1] <= y1]
    out = []
    sides = {0: x1 - x0 + 1, 1: y1 - y0 + 1}  # nodes along x, along y
    for cx, cy in corners(rect):
        h, v = _directions(rect, (cx, cy))
        for (fx, fy), (sx, sy) in ((h, v), (v, h)):
            line = sides[0] if fx else sides[1]  # the position of u is j * line + i (Scan.index)
            labels = tuple(sorted((((x - cx) * sx + (y - cy) * sy) * line
                                   + (x - cx) * fx + (y - cy) * fy, k)
                                  for (x, y), k in marked))
            out.append(Scan((cx, cy), (fx, fy), (sx, sy), rect, labels))
    return out


def representations(rect: Rect, value: Callable[[Node], int],
                    support: Iterable[Node] | None = None) -> list[Scan]:
    """Each corner's string representation(s): along the shorter side; on a
    square the larger of the two, both when they are equal (``support`` as for
    :func:`all_scans`)."""
    x0, y0, x1, y1 = rect
    width, height = x1 - x0, y1 - y0
    scans = all_scans(rect, value, support)
    if width != height:
        along_x = width < height  # the fast side is the shorter one
        return [s for s in scans if (s.fast[0] != 0) == along_x]
    out: list[Scan] = []
    for a, b in zip(scans[0::2], scans[1::2], strict=True):
        if a.labels == b.labels:
            out.extend((a, b))
        else:
            out.append(max(a, b, key=lambda s: s.order))
    return out


def largest(scans: Iterable[Scan]) -> list[Scan]:
    """The scans whose text is lexicographically largest (ties kept, order kept); all
    of one rectangle and one line length, as a representation's are."""
    scans = list(scans)
    assert len({(s.rect, s.line) for s in scans}) == 1, "strings of different lengths"
    top = max(s.order for s in scans)
    return [s for s in scans if s.order == top]


# -- the configuration: key corners and views -------------------------------------


def label_function(configuration: Configuration, *, weak: bool) -> Callable[[Node], int]:
    """``l(v)``, or with ``weak`` the label with multiplicities not told apart."""
    return configuration.weak_label if weak else configuration.label


def key_scans(configuration: Configuration, *, weak: bool = False) -> list[Scan]:
    """The largest string representation(s) over MER; their corners are the key corners."""
    return largest(representations(configuration.mer(), label_function(configuration, weak=weak),
                                   configuration.occupied | configuration.meeting_nodes))


def key_corners(configuration: Configuration, *, weak: bool = False) -> list[Node]:
    """The key corner(s); unique exactly when no corner ties."""
    return sorted({s.corner for s in key_scans(configuration, weak=weak)})


def configuration_view(scan: Scan, configuration: Configuration, v: Node) -> tuple[int, int]:
    """The paper's configuration view ``(d', l(v))`` of node ``v`` from a key scan.

    ``d'`` is read as the position of ``v`` in the key corner's string (see
    docs/interpretations.md, "configuration view").
    """
    return (scan.index(v), configuration.label(v))


def max_view(
    configuration: Configuration, candidates: Iterable[Node], *, weak: bool = False
) -> Node | None:
    """The candidate with the maximum configuration view, or None when the key
    corners disagree (the paper's choice is then not defined)."""
    candidates = list(candidates)
    picks = {max(candidates, key=s.index) for s in key_scans(configuration, weak=weak)}
    return picks.pop() if len(picks) == 1 else None


# -- the meeting nodes: alpha strings, leading corners, orderings -----------------


def alpha_rect(configuration: Configuration, region: AlphaRegion) -> Rect:
    """Where ``alpha`` is read: MER of ``R`` and ``M`` (the paper's figure) or MER_F."""
    return configuration.mer() if region == "mer" else configuration.mer_f()


def leading_scans(configuration: Configuration, region: AlphaRegion = "mer") -> list[Scan]:
    """The largest ``alpha`` string(s); their corners are the leading corners."""
    return list(_leading_scans(alpha_rect(configuration, region), configuration.meeting_nodes))


@lru_cache(maxsize=1 << 14)
def _leading_scans(rect: Rect, meeting_nodes: frozenset[Node]) -> tuple[Scan, ...]:
    """``alpha`` reads only ``M`` over a rectangle: remembered per (rectangle, ``M``), which
    stay the same while robots move inside the rectangle."""
    return tuple(largest(representations(rect, lambda v: 1 if v in meeting_nodes else 0,
                                         meeting_nodes)))


def leading_corners(configuration: Configuration, region: AlphaRegion = "mer") -> list[Node]:
    return sorted({s.corner for s in leading_scans(configuration, region)})


def meeting_order(scan: Scan, meeting_nodes: Iterable[Node]) -> tuple[Node, ...]:
    """Meeting nodes in the order they appear in ``scan`` (the paper's O, O', O'')."""
    return tuple(sorted(meeting_nodes, key=scan.index))


def ordering_O(configuration: Configuration, region: AlphaRegion = "mer") -> tuple[Node, ...] | None:
    """Ordering O of the meeting nodes from the unique leading corner (None if not unique).

    The paper's "highest order" is the *last* node of O (Figure "orderingalgo"(a)).
    """
    return _ordering_O(alpha_rect(configuration, region), configuration.meeting_nodes)


@lru_cache(maxsize=1 << 14)
def _ordering_O(rect: Rect, meeting_nodes: frozenset[Node]) -> tuple[Node, ...] | None:
    orders = {meeting_order(s, meeting_nodes) for s in _leading_scans(rect, meeting_nodes)}
    return orders.pop() if len(orders) == 1 else None


def ordering_O_prime(
    configuration: Configuration, axis_nodes: Iterable[Node], region: AlphaRegion = "mer"
) -> tuple[Node, ...] | None:
    """Ordering O' of the meeting nodes on the axis L, or None if the leading
    corners order them differently."""
    on_axis = [m for m in configuration.meeting_nodes if m in set(axis_nodes)]
    orders = {meeting_order(s, on_axis) for s in leading_scans(configuration, region)}
    return orders.pop() if len(orders) == 1 else None


# -- building configurations from strings (paper figures) ---------------------------

_ROBOTS = {ROBOT: 1, ROBOT_ON_MEETING: 1}
_MEETING = {MEETING, ROBOT_ON_MEETING}


def from_string(text: str, column: int) -> Configuration:
    """Lay a label string out in columns of ``column`` nodes from the origin.

    Character ``k`` goes to node ``(k // column, k % column)``: the fast side
    is the y axis. Labels 3 and 5 are not allowed (initial configurations).
    """
    if column < 1 or len(text) % column:
        raise InvalidInput(f"string of length {len(text)} does not split into columns of {column}")
    robots, meeting = [], []
    for k, ch in enumerate(text):
        if ch not in "0124":
            raise InvalidInput(f"bad label {ch!r} at position {k}: use 0, 1, 2 or 4")
        label = int(ch)
        v = (k // column, k % column)
        if label in _ROBOTS:
            robots.append(v)
        if label in _MEETING:
            meeting.append(v)
    assert EMPTY == 0
    return Configuration(robots, meeting, initial=True)
