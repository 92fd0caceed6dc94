"""What a robot sees on a world, in one frame, and the move sets that follow (§3, §9).

A :class:`WorldView` holds the visible part of the world (``graph``, labelled in
the frame), the robot's own node (``me``), the robots and the meeting nodes on it,
and exactly the multiplicity its detection model allows; asking for more raises
:class:`~gather_verify.model.view.MultiplicityHidden`. An algorithm answers
``view.me`` (stay) or a neighbour of it in ``view.graph``. The move set of a robot
is the union over its frames of that answer, mapped back (§3).

>>> from gather_verify.worlds import get_world
>>> ring = get_world("ring:9")
>>> v = WorldView(ring, {0: 1, 3: 1, 5: 1}, frozenset({7}), 3, ring.frames(3, None, "all")[1],
...               "local-weak")
>>> v.me, sorted(v.robots), sorted(v.meeting_nodes), v.neighbours()
(0, [0, 3, 7], [5], (1, 8))
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from typing import TYPE_CHECKING

from gather_verify.model.view import LightHidden, Lights, MultiplicityHidden
from gather_verify.worlds.base import FrameMap, Label, World

if TYPE_CHECKING:
    import networkx as nx

__all__ = ["LightHidden", "Lights", "WorldView"]


class WorldView:
    """A robot's snapshot of a world in one frame (read-only)."""

    __slots__ = ("world", "detection", "_counts", "_meeting", "_node", "_frame", "_map",
                 "_lights", "_colours", "_mine")

    def __init__(self, world: World, counts: Mapping[int, int], meeting: frozenset[int],
                 node: int, frame: FrameMap, detection: str, lights: Lights | None = None,
                 colours: Mapping[int, Counter[int]] | None = None, mine: int = 0):
        self.world, self.detection = world, detection
        self._counts, self._meeting, self._node = counts, meeting, node
        self._frame = frame.labels
        self._map = frame
        self._lights = lights or Lights(1)
        self._colours = colours or {}
        self._mine = mine

    @property
    def light(self) -> int:
        """The robot's own colour (hidden under external lights)."""
        if self._lights.variant == "external":
            raise LightHidden("external lights: a robot does not see its own colour")
        return self._mine

    def _colours_on(self, node: Label) -> Counter[int]:
        if self._lights.variant == "internal":
            raise LightHidden("internal lights: a robot sees no other robot's colour")
        back = self._map.inverse.get(node)
        if back is None:
            raise LightHidden(f"{node} is not in the view")
        seen = Counter(self._colours.get(back, ()))
        if back == self._node and self._lights.variant == "external":
            seen[self._mine] -= 1  # its own light is the one it cannot see
        return +seen

    def colours(self, node: Label | None = None) -> frozenset[int]:
        """The colours of the lights on ``node`` (default: the robot's own node; under
        external lights its own light is not among them), as a set (how many of each:
        :meth:`colour_counts`, under strong detection)."""
        return frozenset(self._colours_on(self.me if node is None else node))

    def colour_counts(self, node: Label | None = None) -> dict[int, int]:
        """How many lights of each colour are on ``node`` (strong detection only)."""
        node = self.me if node is None else node
        self._visible(node, strong=True)
        return dict(self._colours_on(node))

    @property
    def me(self) -> Label:
        """The robot's own node, in its frame."""
        return self._frame[self._node]

    @property
    def graph(self) -> nx.Graph:
        """The visible part of the world, nodes labelled in the robot's frame (frozen)."""
        return self._map.graph

    def neighbours(self, node: Label | None = None) -> tuple[Label, ...]:
        """The neighbours of ``node`` (default: the robot's own) in the visible graph,
        sorted."""
        return self._map.neighbours(self.me if node is None else node)

    def distance(self, a: Label, b: Label) -> int:
        """Hops between two visible nodes inside the visible graph."""
        return self._map.distances[a][b]

    @property
    def robots(self) -> frozenset[Label]:
        """The visible occupied nodes, in the frame."""
        return frozenset(self._frame[u] for u in self._counts if u in self._frame)

    @property
    def meeting_nodes(self) -> frozenset[Label]:
        """The visible meeting nodes, in the frame."""
        return self._map.shown(self._meeting)

    def _visible(self, node: Label, strong: bool) -> int:
        d = self.detection
        if d == "none":
            raise MultiplicityHidden("detection 'none' shows no multiplicity at all")
        if d.startswith("local") and node != self.me:
            raise MultiplicityHidden(
                f"{d} detection shows multiplicity only on the robot's own node, not at {node}")
        if strong and d.endswith("weak"):
            raise MultiplicityHidden(f"{d} detection tells whether a node is a multiplicity, "
                                     "not how many robots are on it")
        back = self._map.inverse
        if node not in back:
            raise MultiplicityHidden(f"{node} is not in the view")
        return self._counts.get(back[node], 0)

    def multiplicity(self, node: Label | None = None) -> bool:
        """Whether ``node`` (default: the robot's own) holds several robots (a bool)."""
        return self._visible(self.me if node is None else node, strong=False) > 1

    def count(self, node: Label | None = None) -> int:
        """How many robots are on ``node`` (strong detection only)."""
        return self._visible(self.me if node is None else node, strong=True)

    def __repr__(self) -> str:
        return (f"WorldView(me={self.me!r}, robots={sorted(self.robots, key=repr)}, "
                f"meeting_nodes={sorted(self.meeting_nodes, key=repr)})")

