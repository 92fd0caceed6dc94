"""``nearest-centre``: a reference algorithm a user would try first.

Every robot walks (along any shortest path: the adversary picks) to the
meeting node nearest to the centre of the bounding box of the occupied nodes.
Ties are broken by the nearest to the centre of mass of the occupied nodes
(each occupied node counted once: under ``local-weak`` detection a robot
cannot count the robots elsewhere); if still tied, every robot stays. Both
centres and both distances (Manhattan to the box centre, squared Euclidean to
the centre of mass) are invariant under the grid isometries, so the algorithm
is equivariant. The target is recomputed from every snapshot, so it may move
as robots move: this is a yardstick, not a correct algorithm.

>>> from gather_verify.model.configuration import Configuration
>>> from gather_verify.algorithms.moves import move_set
>>> c = Configuration([(0, 0), (4, 0)], [(2, 1), (9, 9)])
>>> NearestCentre().target(c)
(2, 1)
>>> sorted(move_set(NearestCentre(), c, (0, 0)))
[(0, 1), (1, 0)]
"""

from __future__ import annotations

from collections.abc import Iterable

from gather_verify.algorithms.base import commutes_with_translations
from gather_verify.algorithms.go_to_target import step_towards
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, Node, bounding_box
from gather_verify.model.view import View


def centre_target(occupied: Iterable[Node], meeting_nodes: Iterable[Node]) -> Node | None:
    """The meeting node nearest the box centre, then the centre of mass; None if tied."""
    occupied = list(occupied)
    x0, y0, x1, y1 = bounding_box(occupied)
    n = len(occupied)
    sx, sy = sum(v[0] for v in occupied), sum(v[1] for v in occupied)

    def rank(m: Node) -> tuple[int, int]:
        box = abs(2 * m[0] - x0 - x1) + abs(2 * m[1] - y0 - y1)
        mass = (n * m[0] - sx) ** 2 + (n * m[1] - sy) ** 2
        return (box, mass)

    ranked = sorted(meeting_nodes, key=rank)
    if len(ranked) > 1 and rank(ranked[0]) == rank(ranked[1]):
        return None
    return ranked[0]


class NearestCentre:
    """Walk to the meeting node nearest the centre of the robots (see module docstring)."""

    name = "nearest-centre"

    def decide(self, view: View) -> Node:
        target = centre_target(view.robots, view.meeting_nodes)
        return ORIGIN if target is None else step_towards(target)

    @commutes_with_translations
    def target(self, configuration: Configuration) -> Node | None:
        return centre_target(configuration.occupied, configuration.meeting_nodes)
