"""Grid geometry: nodes, the dihedral group D4 and grid isometries.

A node is a pair of integers. The isometries of the grid that fix the origin
form the dihedral group D4 (4 rotations, 4 reflections); every automorphism
of a configuration is ``v -> A v + t`` with ``A`` in D4 (paper §2,
SEMANTICS.md §2). Elements are numbered 0..7 and stored as 2x2 integer
matrices ``(a, b, c, d)`` acting as ``(x, y) -> (a x + b y, c x + d y)``.

>>> apply(ROT90, (1, 0))
(0, 1)
>>> apply(inverse(ROT90), (0, 1))
(1, 0)
>>> [NAMES[g] for g in range(8)]
['id', 'rot90', 'rot180', 'rot270', 'flip-x', 'flip-y', 'flip-diag', 'flip-anti']
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from gather_verify.errors import InvalidInput

Node = tuple[int, int]

ORIGIN: Node = (0, 0)
STEPS: tuple[Node, ...] = ((1, 0), (0, 1), (-1, 0), (0, -1))
"""The four unit moves; with the origin, the only answers an algorithm may give."""
DEGREE = len(STEPS)
"""Every node of Z² has this many neighbours (no edge is missing)."""
SLOTS = DEGREE + 1
"""A robot's code's slots per cell in the engines' encoding (degree + 1): ``cell * SLOTS +
d``, ``d`` = 0 idle, else 1 + the index of its pending step in :data:`STEPS`
(``gather_verify.engine.encoding``; the compiled kernels' ``kernels.codes.Z2_SLOTS``)."""

MATRICES: tuple[tuple[int, int, int, int], ...] = (
    (1, 0, 0, 1),  # identity
    (0, -1, 1, 0),  # rotation by 90 degrees (counter-clockwise)
    (-1, 0, 0, -1),  # rotation by 180 degrees
    (0, 1, -1, 0),  # rotation by 270 degrees
    (-1, 0, 0, 1),  # x -> -x: reflection in a vertical axis
    (1, 0, 0, -1),  # y -> -y: reflection in a horizontal axis
    (0, 1, 1, 0),  # swap: reflection in the diagonal x = y
    (0, -1, -1, 0),  # reflection in the anti-diagonal x = -y
)
NAMES = ("id", "rot90", "rot180", "rot270", "flip-x", "flip-y", "flip-diag", "flip-anti")
IDENTITY, ROT90, ROT180, ROT270, FLIP_X, FLIP_Y, FLIP_DIAG, FLIP_ANTI = range(8)
ROTATIONS = (IDENTITY, ROT90, ROT180, ROT270)
ALL = tuple(range(8))


def apply(g: int, v: Node) -> Node:
    """Image of node ``v`` under the D4 element ``g``."""
    a, b, c, d = MATRICES[g]
    x, y = v
    return (a * x + b * y, c * x + d * y)


def _compose_table() -> tuple[tuple[int, ...], ...]:
    probes = ((1, 0), (0, 1))

    def find(images: tuple[Node, Node]) -> int:
        for h in ALL:
            if (apply(h, probes[0]), apply(h, probes[1])) == images:
                return h
        raise AssertionError("D4 is closed")

    return tuple(
        tuple(find((apply(g, apply(h, probes[0])), apply(g, apply(h, probes[1])))) for h in ALL)
        for g in ALL
    )


COMPOSE = _compose_table()
"""``COMPOSE[g][h]`` is the element ``g o h`` (apply ``h`` first)."""
INVERSE = tuple(next(h for h in ALL if COMPOSE[g][h] == IDENTITY) for g in ALL)


def compose(g: int, h: int) -> int:
    """The element ``g o h``: first ``h``, then ``g``."""
    return COMPOSE[g][h]


def inverse(g: int) -> int:
    """The inverse element of ``g``."""
    return INVERSE[g]


def is_rotation(g: int) -> bool:
    """True for the four rotations (determinant +1), identity included."""
    a, b, c, d = MATRICES[g]
    return a * d - b * c == 1


def add(u: Node, v: Node) -> Node:
    return (u[0] + v[0], u[1] + v[1])


def sub(u: Node, v: Node) -> Node:
    return (u[0] - v[0], u[1] - v[1])


def manhattan(u: Node, v: Node) -> int:
    """Grid distance ``d(u, v)``."""
    return abs(u[0] - v[0]) + abs(u[1] - v[1])


def neighbours(v: Node) -> tuple[Node, ...]:
    """The four grid neighbours of ``v``."""
    return tuple(add(v, s) for s in STEPS)


def bounding_box(nodes: Iterable[Node]) -> tuple[int, int, int, int]:
    """``(xmin, ymin, xmax, ymax)`` of a non-empty collection of nodes."""
    xs, ys = zip(*nodes, strict=True)
    return (min(xs), min(ys), max(xs), max(ys))


def parse_node(text: str) -> Node:
    """Parse ``"x,y"`` into a node; ``ValueError`` names the bad text.

    >>> parse_node("3,-1")
    (3, -1)
    """
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 2:
        raise InvalidInput(f"bad point {text!r}: expected 'x,y' with two integers")
    if not all(_INTEGER.fullmatch(p) for p in parts):  # int() also takes 1_0 and other digits
        raise InvalidInput(f"bad point {text!r}: coordinates must be integers written with "
                           "the digits 0-9 and an optional minus")
    return (int(parts[0], 10), int(parts[1], 10))


_INTEGER = re.compile(r"-?[0-9]+", re.ASCII)


def parse_nodes(text: str) -> list[Node]:
    """Parse ``"x,y x,y ..."``: spaces between points, and nothing else.

    >>> parse_nodes("0,0 1,3")
    [(0, 0), (1, 3)]
    >>> parse_nodes("0,0;1,3")
    Traceback (most recent call last):
    ...
    gather_verify.errors.InvalidInput: bad points '0,0;1,3': separate points with spaces, e.g. "0,0 1,3"
    """
    if ";" in text:
        raise InvalidInput(f"bad points {text!r}: separate points with spaces, e.g. \"0,0 1,3\"")
    return [parse_node(p) for p in text.split()]
