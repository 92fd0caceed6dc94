"""``grid``: the paper's infinite grid Z² (SEMANTICS.md §1-8), one world among the others.

The Z² engines (the region growth of ``check``, the census of ``sweep``, the synthesis
of :mod:`gather_verify.synthesis.plane`) run it: its :attr:`Plane.entry` says so, and
the commands ask the world, not its name. What the edge asks of every world it answers
from the Z² model: nodes are ``(x, y)`` written ``x,y`` (:mod:`~gather_verify.model.geometry`);
a robot's frames are its own node at the origin and one of the 8 elements of D4 (the
rotations under chirality, the identity under a compass); the canonical form of a
configuration is :func:`~gather_verify.model.canonical.canonical_form`'s key, up to the
translations and those elements. Z² has no end, so it has no drawing of its own: the
pictures draw the part of the grid a trace needs.

>>> z2 = Plane()
>>> z2.parse_nodes("0,0 2,-1"), z2.format_node((2, -1))
([(0, 0), (2, -1)], '2,-1')
>>> [f.label((1, 0)) for f in z2.frames((0, 0), None, "chirality")]
[(1, 0), (0, 1), (-1, 0), (0, -1)]
>>> z2.canonical([(2, 1), (5, 1)], [(3, 1)])
(((0, 0), (0, 3)), ((0, 1),))
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any, NamedTuple

from gather_verify.algorithms.moves import frames_for
from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.canonical import Key, canonical_form
from gather_verify.model.configuration import _as_node
from gather_verify.model.geometry import Node
from gather_verify.worlds.base import PLANE


class PlaneFrame(NamedTuple):
    """A frame of Z²: the robot's node ``origin`` moved to (0, 0), then the D4 element
    ``element`` (:data:`gather_verify.model.geometry.MATRICES`)."""

    element: int
    origin: Node

    def label(self, u: Node) -> Node:
        return geometry.apply(self.element, geometry.sub(u, self.origin))


class Plane:
    """Z², behind the face every world offers (:class:`~gather_verify.worlds.base.AnyWorld`)."""

    name = "grid"
    kind = "grid"
    entry = PLANE

    def format_node(self, v: Node) -> str:
        return f"{v[0]},{v[1]}"

    def parse_node(self, text: str) -> Node:
        return geometry.parse_node(text)

    def parse_nodes(self, text: str) -> list[Node]:
        return geometry.parse_nodes(text)

    def node_to_json(self, v: Node) -> object:
        return list(v)

    def node_from_json(self, value: object) -> Node:
        return _as_node(value, "node")

    def group(self, frames: str) -> tuple[int, ...]:
        """The elements of D4 the frame set allows, ascending (one line for an unknown set)."""
        return frames_for(frames)

    def frames(self, v: Node, visibility: int | None, frames: str) -> list[PlaneFrame]:
        if visibility is not None:
            raise InvalidInput("visibility needs a finite world (ring:N, grid:WxH, torus:WxH "
                               "or graph:FILE): on Z² robots see the whole grid")
        return [PlaneFrame(g, v) for g in self.group(frames)]

    def canonical(self, robots: Iterable[Node], meeting: Iterable[Node],
                  frames: str = "all") -> Key:
        return canonical_form(robots, meeting, self.group(frames)).key

    def drawing(self) -> dict[str, Any] | None:
        return None

    def __repr__(self) -> str:
        return "<world grid (Z²)>"
