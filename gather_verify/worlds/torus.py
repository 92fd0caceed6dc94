"""``torus:WxH``: the W × H grid with wrap-around, W, H ≥ 3, nodes written ``x,y``
(SEMANTICS.md §9).

A robot's frame is D4 around its own node, as on the grids; a node is presented at
its shortest offset (``-W//2 .. (W-1)//2`` across, likewise up). Aut(G) is the
translations with the rectangle's symmetries.

>>> t = Torus(3, 4)
>>> t.size, t.degree, len(t.automorphisms)
(12, 4, 48)
"""

from __future__ import annotations

from gather_verify.worlds.base import DrawnEdge, Outline, World
from gather_verify.worlds.grid import GridFamily, parse_box


class Torus(GridFamily):
    kind = "torus"

    def __init__(self, width: int, height: int):
        self.width, self.height = width, height
        labels = [(x, y) for y in range(height) for x in range(width)]
        edges = [(y * width + x, y * width + (x + 1) % width) for y in range(height)
                 for x in range(width)]
        edges += [(y * width + x, ((y + 1) % height) * width + x) for y in range(height)
                  for x in range(width)]
        World.__init__(self, f"torus:{width}x{height}", labels, edges)

    @classmethod
    def from_spec(cls, arg: str) -> Torus:
        return cls(*parse_box(arg, "torus:WxH (W, H >= 3)", 3))

    def placements(self, g: int) -> list[tuple[int, ...]]:
        from gather_verify.model import geometry

        a, b, c, d = geometry.MATRICES[g]
        w, h = self.width, self.height
        if w != h and b != 0:  # a quarter turn of a W != H torus
            return []
        return [tuple(self.index[((a * x + b * y + tx) % w, (c * x + d * y + ty) % h)]
                      for x, y in self.labels) for tx in range(w) for ty in range(h)]

    def drawn_edges(self) -> list[DrawnEdge]:
        """The grid's edges; an edge across the seam (from the last column to the first, or
        the last row to the first) as two short stubs: one leaving its node towards the seam,
        one coming back from the opposite side of the seam into the other node."""
        out = []
        for v, (x, y) in enumerate(self.labels):
            for dx, dy in ((1, 0), (0, 1)):
                nx_, ny = x + dx, y + dy
                w = self.index[(nx_ % self.width, ny % self.height)]
                if nx_ < self.width and ny < self.height:
                    out.append(DrawnEdge(v, w, (((x, y), (nx_, ny)),)))
                else:
                    (wx, wy) = self.labels[w]
                    out.append(DrawnEdge(v, w, (((x, y), (x + dx / 2, y + dy / 2)),
                                                ((wx - dx / 2, wy - dy / 2), (wx, wy))), True))
        return out

    def outline(self) -> Outline:
        return self.box_outline(True, f"the seam of {self.name}: an edge that crosses it comes "
                                "back on the opposite side")

    def offset(self, u: int, v: int) -> tuple[int, int]:
        (ux, uy), (vx, vy) = self.labels[u], self.labels[v]
        w, h = self.width, self.height
        return (ux - vx + w // 2) % w - w // 2, (uy - vy + h // 2) % h - h // 2
