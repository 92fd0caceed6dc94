"""Configurations ``C = (R, M)``: robots, meeting nodes, the paper's labels and MER.

Paper §2 ("System Configuration", "Symmetry"), SEMANTICS.md §1. ``R`` is a
multiset of robot nodes, ``M`` a non-empty set of meeting nodes. An *initial*
configuration has its robots on distinct nodes.

>>> c = Configuration([(0, 0), (2, 1)], [(1, 1)])
>>> c.label((1, 1)), c.label((0, 0)), c.label((5, 5))
(1, 4, 0)
>>> c.mer(), c.D
((0, 0, 2, 1), 2)
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable
from functools import cached_property

from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.canonical import CanonicalForm, canonical_form, moved_form
from gather_verify.model.geometry import Node

EMPTY, MEETING, ROBOT_ON_MEETING, MULTI_ON_MEETING, ROBOT, MULTI = range(6)
"""The paper's node labels ``l(v)``."""

MAX_COORDINATE = 10**6
"""Coordinates beyond this are rejected: no exhaustive check can use them."""
MAX_EXTENT = 512
"""Longest side (in edges) of the MER of an *initial* configuration. Classification reads
strings over every node of the MER, so time and memory grow with its area: a 2000 x 2000
MER already takes minutes and gigabytes, while every exhaustive check needs far less."""


def _as_node(value: object, what: str) -> Node:
    if isinstance(value, str | bytes) or not isinstance(value, list | tuple):
        raise InvalidInput(f"bad {what} {value!r}: expected a pair of integers [x, y]")
    if len(value) != 2:
        raise InvalidInput(f"bad {what} {value!r}: expected exactly two coordinates")
    out = []
    for coordinate in value:
        if isinstance(coordinate, bool) or not isinstance(coordinate, numbers.Integral):
            raise InvalidInput(f"bad {what} {list(value)!r}: coordinates must be integers")
        if abs(int(coordinate)) > MAX_COORDINATE:
            raise InvalidInput(f"bad {what} {list(value)!r}: |coordinate| > {MAX_COORDINATE}")
        out.append(int(coordinate))
    return (out[0], out[1])


class Configuration:
    """A configuration ``(R, M)``; immutable and hashable.

    ``robots`` is kept sorted, so two configurations with the same multiset of
    robot nodes are equal. ``initial=True`` also requires distinct robot nodes.
    """

    __slots__ = ("robots", "meeting_nodes", "__dict__")

    def __init__(
        self,
        robots: Iterable[Node],
        meeting_nodes: Iterable[Node],
        *,
        initial: bool = False,
    ) -> None:
        rs = [_as_node(r, "robot") for r in robots]
        ms = [_as_node(m, "meeting node") for m in meeting_nodes]
        if not rs:
            raise InvalidInput("no robots: a configuration needs at least one robot")
        if not ms:
            raise InvalidInput("no meeting nodes: a configuration needs at least one meeting node")
        seen: set[Node] = set()
        for m in ms:
            if m in seen:
                raise InvalidInput(f"duplicate meeting node {list(m)}")
            seen.add(m)
        if initial:
            seen.clear()
            for r in rs:
                if r in seen:
                    raise InvalidInput(
                        f"duplicate robot {list(r)}: robots of an initial configuration "
                        "stand on distinct nodes"
                    )
                seen.add(r)
            xs, ys = [v[0] for v in rs + ms], [v[1] for v in rs + ms]
            extent = max(max(xs) - min(xs), max(ys) - min(ys))
            if extent > MAX_EXTENT:
                raise InvalidInput(
                    f"the nodes span {extent} edges (MER {max(xs) - min(xs)} x "
                    f"{max(ys) - min(ys)}): at most {MAX_EXTENT} is supported; move them closer"
                )
        self.robots: tuple[Node, ...] = tuple(sorted(rs))
        self.meeting_nodes: frozenset[Node] = frozenset(ms)

    @classmethod
    def trusted(cls, robots: tuple[Node, ...], meeting_nodes: frozenset[Node]) -> Configuration:
        """Build without validation from a sorted robot tuple (hot paths only)."""
        self = object.__new__(cls)
        self.robots = robots
        self.meeting_nodes = meeting_nodes
        return self

    # -- identity -----------------------------------------------------------
    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Configuration)
            and self.robots == other.robots
            and self.meeting_nodes == other.meeting_nodes
        )

    def __hash__(self) -> int:
        return hash((self.robots, self.meeting_nodes))

    def __repr__(self) -> str:
        return f"Configuration(robots={list(self.robots)}, meeting_nodes={sorted(self.meeting_nodes)})"

    # -- the robot multiset ---------------------------------------------------
    @property
    def n(self) -> int:
        """Number of robots (with multiplicity)."""
        return len(self.robots)

    @cached_property
    def counts(self) -> dict[Node, int]:
        """Robots per occupied node (in the order of the robots: as ``dict(Counter(robots))``,
        without a Counter, which costs a search about 2 us per configuration)."""
        out: dict[Node, int] = {}
        for v in self.robots:
            out[v] = out.get(v, 0) + 1
        return out

    @cached_property
    def occupied(self) -> frozenset[Node]:
        """The distinct robot positions (the paper's ``n_1`` is their number)."""
        return frozenset(self.robots)

    @cached_property
    def canonical_form(self) -> CanonicalForm:
        """The canonical form of the occupied nodes and meeting nodes (multiplicity left
        out) under translations and D4, with every isometry that reaches it."""
        return canonical_form(self.occupied, self.meeting_nodes)

    def multiplicity(self, v: Node) -> int:
        """How many robots are on ``v``: an **int** (0 on an empty node). The robot's own
        :meth:`View.multiplicity <gather_verify.model.view.View.multiplicity>` is a bool:
        whether its detection model shows several robots there."""
        return self.counts.get(v, 0)

    # -- labels ---------------------------------------------------------------
    def label(self, v: Node) -> int:
        """The paper's label ``l(v)`` in 0..5."""
        k = self.counts.get(v, 0)
        if v in self.meeting_nodes:
            return MEETING if k == 0 else ROBOT_ON_MEETING if k == 1 else MULTI_ON_MEETING
        return EMPTY if k == 0 else ROBOT if k == 1 else MULTI

    def weak_label(self, v: Node) -> int:
        """``l(v)`` with multiplicities not told apart (3 read as 2, 5 as 4)."""
        occupied = v in self.counts
        if v in self.meeting_nodes:
            return ROBOT_ON_MEETING if occupied else MEETING
        return ROBOT if occupied else EMPTY

    def lam(self, v: Node) -> int:
        """``lambda(v)``: 1 on meeting nodes, else 0."""
        return 1 if v in self.meeting_nodes else 0

    @cached_property
    def labelled(self) -> dict[Node, int]:
        """Every node with a non-zero label, and its label."""
        return {v: self.label(v) for v in self.occupied | self.meeting_nodes}

    # -- rectangles -----------------------------------------------------------
    def mer(self) -> tuple[int, int, int, int]:
        """MER: smallest grid-aligned rectangle holding ``R`` and ``M``."""
        return geometry.bounding_box(self.occupied | self.meeting_nodes)

    def mer_f(self) -> tuple[int, int, int, int]:
        """MER_F: smallest grid-aligned rectangle holding ``M``."""
        return geometry.bounding_box(self.meeting_nodes)

    @property
    def D(self) -> int:
        """Longer side of this configuration's MER, in edges."""
        x0, y0, x1, y1 = self.mer()
        return max(x1 - x0, y1 - y0)

    # -- predicates -----------------------------------------------------------
    @property
    def is_gathered(self) -> bool:
        """Every robot on one meeting node."""
        return len(self.counts) == 1 and self.robots[0] in self.meeting_nodes

    @property
    def has_multiplicity(self) -> bool:
        return len(self.counts) < len(self.robots)

    # -- transformations ------------------------------------------------------
    def transformed(self, g: int, t: Node = (0, 0),
                    meeting_nodes: frozenset[Node] | None = None) -> Configuration:
        """Image under ``v -> g(v) + t`` (``meeting_nodes``: the image of ``M``, when the
        caller has it). If this configuration's canonical form is known, the image's comes
        from it (:func:`~gather_verify.model.canonical.moved_form`), with no search of its own."""
        a, b, c, d = geometry.MATRICES[g]
        tx, ty = t
        image = Configuration.trusted(
            tuple(sorted([(a * x + b * y + tx, c * x + d * y + ty) for x, y in self.robots])),
            frozenset((a * x + b * y + tx, c * x + d * y + ty) for x, y in self.meeting_nodes)
            if meeting_nodes is None else meeting_nodes)
        form = self.__dict__.get("canonical_form")
        if form is not None:
            image.__dict__["canonical_form"] = moved_form(form, g, t)
        return image

    def moved(self, moves: Iterable[tuple[Node, Node]]) -> Configuration:
        """The configuration after robots move ``source -> destination``."""
        robots = list(self.robots)
        for source, destination in moves:
            robots.remove(source)
            robots.append(destination)
        return Configuration.trusted(tuple(sorted(robots)), self.meeting_nodes)

    def to_json(self) -> dict[str, list[list[int]]]:
        return {
            "robots": [list(r) for r in self.robots],
            "meeting_nodes": [list(m) for m in sorted(self.meeting_nodes)],
        }
