"""``grid:WxH``: the finite W × H grid graph, nodes written ``x,y`` (SEMANTICS.md §9).

As on Z², a robot's frame is its own node at the origin and one of the 8 elements
of D4 (4 rotations under chirality, the identity under a compass); the border
shows as the nodes that are missing from the view. Aut(G) is the rectangle's
symmetry group: 8 elements if W = H, else 4.

>>> g = FiniteGrid(3, 2)
>>> g.size, len(g.automorphisms), g.adjacency[g.index[(1, 0)]]
(6, 4, (0, 2, 4))
"""

from __future__ import annotations

from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.worlds.base import Frame, Label, Outline, Point, World, decimal
from gather_verify.worlds.ring import parse_size

D4_FRAMES = {"all": geometry.ALL, "chirality": geometry.ROTATIONS,
             "compass": (geometry.IDENTITY,)}


def parse_box(arg: str, form: str, low: int) -> tuple[int, int]:
    """``WxH`` of a world's spec."""
    w, sep, h = arg.lower().partition("x")
    if not sep:
        raise InvalidInput(f"world size {arg!r}: write {form}")
    return parse_size(w, form, low, 1000), parse_size(h, form, low, 1000)


class GridFamily(World):
    """Worlds whose nodes are ``(x, y)`` and whose frames are D4 around the robot."""

    width: int
    height: int

    def parse_label(self, text: str) -> Label:
        x, y = text.split(",")
        return (decimal(x), decimal(y))

    def offset(self, u: int, v: int) -> tuple[int, int]:
        """Where ``u`` lies seen from ``v``, before the frame turns it."""
        (ux, uy), (vx, vy) = self.labels[u], self.labels[v]
        return ux - vx, uy - vy

    def symmetries(self, frames: str) -> tuple[tuple[int, ...], ...]:
        """The automorphisms made of a translation and an element of D4 the frame set holds
        (on the 4 × 4 torus, the 4-cube, Aut(G) has more: they do not move the robots'
        coordinate frames along, so they are no symmetry of the problem)."""
        out = [p for g in D4_FRAMES[frames] for p in self.placements(g)]
        out.sort(key=lambda p: p != tuple(range(self.size)))
        return tuple(dict.fromkeys(out))

    def placements(self, g: int) -> list[tuple[int, ...]]:
        """The automorphisms whose linear part is D4 element ``g`` (node -> image)."""
        raise NotImplementedError

    def frame_labels(self, v: int, ball: tuple[int, ...], frames: str) -> list[Frame]:
        out = []
        for g in D4_FRAMES[frames]:
            a, b, c, d = geometry.MATRICES[g]
            out.append({u: (a * x + b * y, c * x + d * y)
                        for u in ball for x, y in (self.offset(u, v),)})
        return out

    def frame_group(self, frames: str, visibility: int | None) -> list[object]:
        """The elements of D4 the frame set holds, as matrices on ``(x, y)`` labels."""
        return ["d4", [list(geometry.MATRICES[g]) for g in D4_FRAMES[frames]]]

    def layout(self) -> dict[int, Point]:
        """Each node at its coordinates."""
        return {v: (float(x), float(y)) for v, (x, y) in enumerate(self.labels)}

    def box_outline(self, wraps: bool, title: str) -> Outline:
        """The rectangle half a step outside the nodes."""
        x1, y1 = self.width - 0.5, self.height - 0.5
        return Outline(((-0.5, -0.5), (x1, -0.5), (x1, y1), (-0.5, y1)), wraps, title)


class FiniteGrid(GridFamily):
    kind = "grid"

    def __init__(self, width: int, height: int):
        self.width, self.height = width, height
        labels = [(x, y) for y in range(height) for x in range(width)]
        edges = [(y * width + x, y * width + x + 1) for y in range(height)
                 for x in range(width - 1)]
        edges += [(y * width + x, (y + 1) * width + x) for y in range(height - 1)
                  for x in range(width)]
        if width * height < 2:
            raise InvalidInput(f"grid:{width}x{height} has a single node")
        super().__init__(f"grid:{width}x{height}", labels, edges)

    @classmethod
    def from_spec(cls, arg: str) -> FiniteGrid:
        return cls(*parse_box(arg, "grid:WxH", 1))

    @property
    def automorphisms(self) -> tuple[tuple[int, ...], ...]:
        return self.symmetries("all")

    def outline(self) -> Outline:
        return self.box_outline(False, f"the border of {self.name}: the world ends here")

    def placements(self, g: int) -> list[tuple[int, ...]]:
        a, b, c, d = geometry.MATRICES[g]
        image = [(a * x + b * y, c * x + d * y) for x, y in self.labels]
        xs, ys = [p[0] for p in image], [p[1] for p in image]
        if max(xs) - min(xs) + 1 != self.width:  # a quarter turn of a W != H rectangle
            return []
        mx, my = min(xs), min(ys)
        return [tuple(self.index[(x - mx, y - my)] for x, y in image)]
