"""``ring:N``: the cycle of N nodes, written ``0`` to ``N-1`` (SEMANTICS.md §9).

A robot sees the ring from its own node, which it reads as 0, in one of the two
directions: its frames label node ``u`` as ``(u - v) mod N`` or ``(v - u) mod N``.
A common compass or chirality keeps the first direction only.

>>> ring = Ring(9)
>>> [f.labels[2] for f in ring.frames(0, None, "all")]
[2, 7]
>>> len(ring.automorphisms)
18
"""

from __future__ import annotations

import math

from gather_verify.errors import InvalidInput
from gather_verify.worlds.base import DrawnEdge, Frame, Label, Point, World, decimal


class Ring(World):
    kind = "ring"

    def __init__(self, n: int):
        if n < 3:
            raise InvalidInput(f"ring:{n}: a ring has at least 3 nodes")
        self.n = n
        super().__init__(f"ring:{n}", range(n), ((v, (v + 1) % n) for v in range(n)))

    @classmethod
    def from_spec(cls, arg: str) -> Ring:
        return cls(parse_size(arg, "ring:N: a ring has at least 3 nodes", 3))

    def parse_label(self, text: str) -> Label:
        return decimal(text)

    @property
    def automorphisms(self) -> tuple[tuple[int, ...], ...]:  # the dihedral group, 2N
        n = self.n
        return tuple(tuple((s * v + r) % n for v in range(n)) for s in (1, -1) for r in range(n))

    def symmetries(self, frames: str) -> tuple[tuple[int, ...], ...]:
        """Rotations keep a robot's direction: every frame set allows them; reflections only
        when robots have no common direction."""
        return self.automorphisms if frames == "all" else self.automorphisms[:self.n]

    def frame_labels(self, v: int, ball: tuple[int, ...], frames: str) -> list[Frame]:
        directions = (1, -1) if frames == "all" else (1,)
        return [{u: (s * (u - v)) % self.n for u in ball} for s in directions]

    def frame_group(self, frames: str, visibility: int | None) -> list[object]:
        """The two directions (one with a compass or chirality): label ``u`` -> ``±u`` mod N."""
        return ["ring", self.n, [1, -1] if frames == "all" else [1]]

    def layout(self) -> dict[int, Point]:
        """A circle, node 0 at the top, clockwise."""
        return {v: _on_circle(v / self.n) for v in range(self.n)}

    def drawn_edges(self) -> list[DrawnEdge]:
        """Arcs of the circle (a few straight pieces each, one piece from 36 nodes on)."""
        pieces = max(1, math.ceil(36 / self.n))
        out = []
        for v in range(self.n):
            arc = tuple(_on_circle((v + t / pieces) / self.n) for t in range(pieces + 1))
            w = (v + 1) % self.n
            out.append(DrawnEdge(v, w, (arc,)) if v < w else DrawnEdge(w, v, (arc[::-1],)))
        return sorted(out)


def _on_circle(turn: float) -> Point:
    """The point ``turn`` of a full turn clockwise from the top of the unit circle."""
    return math.sin(2 * math.pi * turn), math.cos(2 * math.pi * turn)


def parse_size(arg: str, form: str, low: int = 1, high: int = 10_000) -> int:
    """A positive size from a world's spec (``9`` of ``ring:9``), or one line naming it."""
    if not (arg.isascii() and arg.isdigit()):  # int() takes '５', '٥', ' 5', '+5', '5_0'
        raise InvalidInput(f"world size {arg!r} is not an integer (write {form} with the "
                           "digits 0-9)")
    value = int(arg, 10)
    if not low <= value <= high:
        raise InvalidInput(f"world size {value} is out of range [{low}, {high}] ({form})")
    return value
