"""What one robot sees: its snapshot in its own frame, under a multiplicity-detection model.

SEMANTICS.md §3. The snapshot is translated so the robot is at the origin and
transformed by a D4 element (the robot has no compass and no chirality). A
view holds the occupied nodes and the meeting nodes, and exactly the
multiplicity information its detection model allows; asking for more raises
:class:`MultiplicityHidden`, so an algorithm cannot read what its robots could
not see.

>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(1, 1), (1, 1), (3, 1)], [(1, 1)])
>>> v = View(c, (1, 1), frame=0, detection="local-weak")
>>> sorted(v.robots), v.multiplicity()
([(0, 0), (2, 0)], True)
>>> v.multiplicity((2, 0))
Traceback (most recent call last):
...
gather_verify.model.view.MultiplicityHidden: local-weak detection shows multiplicity only on the robot's own node, not at (2, 0)
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property

from gather_verify.errors import GatherVerifyError, InvalidInput
from gather_verify.model import geometry
from gather_verify.model.canonical import Key
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, Node

DETECTION_MODELS = ("none", "local-weak", "local-strong", "global-weak", "global-strong")
"""Multiplicity detection models, weakest first. The paper's is ``local-weak``."""

FRAME_SETS: dict[str, tuple[int, ...]] = {
    "all": geometry.ALL,  # disoriented: no compass, no chirality (the paper)
    "chirality": geometry.ROTATIONS,  # common handedness
    "compass": (geometry.IDENTITY,),  # common compass
}


class MultiplicityHidden(GatherVerifyError, LookupError):
    """The algorithm asked for multiplicity information its detection model hides.

    Cause: the algorithm read multiplicity its detection model does not show: any at all
    under ``none``, another node's than its own under a ``local-`` model, or a number of
    robots (:meth:`View.count`) under a ``-weak`` model, which tells only whether a node is a
    multiplicity. Fix: make the algorithm decide from what the view shows, or check it under
    a stronger detection model. The explorer reports the read as a ``defined`` violation."""


@dataclass(frozen=True)
class Lights:
    """The robots' lights (§10): ``colours`` K, and who sees a robot's colour: everyone
    (``full``), the others only (``external``), the robot only (``internal``). K = 1 is an
    oblivious robot."""

    colours: int
    variant: str = "full"

    def __str__(self) -> str:
        return f"{self.colours}" + ("" if self.variant == "full" else f":{self.variant}")


class LightHidden(GatherVerifyError, LookupError):
    """The algorithm asked for a colour its lights variant hides.

    Cause: the algorithm read another robot's light under a variant where only its own is
    visible (or its own where only the others' are). Fix: decide from the lights the variant
    shows, or check the algorithm under the variant it was written for."""


def check_detection(detection: str) -> str:
    if detection not in DETECTION_MODELS:
        raise InvalidInput(
            f"unknown multiplicity model {detection!r}: use one of {', '.join(DETECTION_MODELS)}"
        )
    return detection


class View:
    """A robot's snapshot in its own frame (robot at the origin).

    ``robots`` and ``meeting_nodes`` are frozensets of nodes in the robot's
    frame. Multiplicity is read through :meth:`multiplicity` and :meth:`count`.
    """

    __slots__ = ("detection", "_snapshot", "_node", "_frame", "_meeting", "_robots", "_cnt",
                 "__dict__")
    _meeting: frozenset[Node] | None  # each computed on first use, then kept
    _robots: frozenset[Node] | None
    _cnt: dict[Node, int] | None

    def __init__(self, configuration: Configuration, node: Node, frame: int, detection: str):
        check_detection(detection)
        if node not in configuration.counts:
            raise InvalidInput(f"no robot at {node} to take a view from")
        self.detection = detection
        self._snapshot, self._node, self._frame = configuration, node, frame
        self._meeting = self._robots = self._cnt = None

    @classmethod
    def trusted(cls, configuration: Configuration, node: Node, frame: int,
                detection: str) -> View:
        """Build without validation (hot paths that checked ``detection`` and ``node``)."""
        self = object.__new__(cls)
        self.detection = detection
        self._snapshot, self._node, self._frame = configuration, node, frame
        self._meeting = self._robots = self._cnt = None
        return self

    # The frame's coordinates are computed on first use (many algorithms read only a
    # part of the view), then kept.
    @property
    def meeting_nodes(self) -> frozenset[Node]:
        """The meeting nodes, in the robot's frame."""
        if self._meeting is None:
            a, b, c, d = geometry.MATRICES[self._frame]
            px, py = self._node
            ox, oy = a * px + b * py, c * px + d * py
            self._meeting = frozenset([(a * x + b * y - ox, c * x + d * y - oy)
                                       for x, y in self._snapshot.meeting_nodes])
        return self._meeting

    @property
    def robots(self) -> frozenset[Node]:
        """The occupied nodes, in the robot's frame."""
        if self._robots is None:
            self._robots = frozenset(self._counts)
        return self._robots

    @property
    def _counts(self) -> dict[Node, int]:
        if self._cnt is None:
            a, b, c, d = geometry.MATRICES[self._frame]
            px, py = self._node
            self._cnt = {(a * (x - px) + b * (y - py), c * (x - px) + d * (y - py)): k
                         for (x, y), k in self._snapshot.counts.items()}
        return self._cnt

    @property
    def me(self) -> Node:
        """The robot's own node in its frame: the origin (as on a finite world's view)."""
        return ORIGIN

    def neighbours(self, v: Node = ORIGIN) -> tuple[Node, ...]:
        """The four neighbours of ``v`` in the frame, sorted (as on a finite world's view)."""
        return tuple(sorted(geometry.add(v, step) for step in geometry.STEPS))

    @property
    def light(self) -> int:
        """The robot's own colour: 0 for an oblivious robot, one colour (:class:`LuminousView`
        has lights)."""
        return 0

    def colours(self, v: Node = ORIGIN) -> frozenset[int]:
        """The colours of the lights on ``v``: ``{0}`` on an occupied node of an oblivious
        robot's view (one colour), as :meth:`LuminousView.colours` with ``--lights 1``."""
        return frozenset({0}) if v in self._counts else frozenset()

    def colour_counts(self, v: Node = ORIGIN) -> dict[int, int]:
        """How many lights of each colour are on ``v`` (strong detection only)."""
        self._visible(v, strong=True)
        k = self._counts.get(v, 0)
        return {0: k} if k else {}

    def _visible(self, v: Node, strong: bool) -> None:
        d = self.detection
        if d == "none":
            raise MultiplicityHidden("detection 'none' shows no multiplicity at all")
        if d.startswith("local") and v != ORIGIN:
            raise MultiplicityHidden(
                f"{d} detection shows multiplicity only on the robot's own node, not at {v}"
            )
        if strong and d.endswith("weak"):
            raise MultiplicityHidden(f"{d} detection tells whether a node is a multiplicity, "
                                     "not how many robots are on it")

    def multiplicity(self, v: Node = ORIGIN) -> bool:
        """Whether node ``v`` (default: the robot's own) holds several robots: a **bool**,
        the weak detection models' answer (``view.multiplicity() > 1`` is always False;
        the number of robots is :meth:`count`, under the strong models only). Unlike
        :meth:`Configuration.multiplicity <gather_verify.model.configuration.Configuration.multiplicity>`,
        which counts (the verifier's global view, not the robot's)."""
        self._visible(v, strong=False)
        return self._counts.get(v, 0) > 1

    def count(self, v: Node = ORIGIN) -> int:
        """How many robots are on ``v`` (strong detection only)."""
        self._visible(v, strong=True)
        return self._counts.get(v, 0)

    @cached_property
    def configuration(self) -> Configuration:
        """The snapshot as a configuration in the robot's frame, one robot per
        occupied node (what every detection model can see)."""
        return Configuration.trusted(tuple(sorted(self.robots)), self.meeting_nodes)

    def canonical(self) -> tuple[Key, int, Node]:
        """The canonical form of what the view shows (robots and meeting nodes), with the
        first ``(g, t)`` mapping the view onto it: exactly
        ``canonical.canonical(self.robots, self.meeting_nodes)``, derived from the snapshot's
        own canonical form (computed once for all its views) instead of searched again.

        The view is ``F(u - p)`` for the snapshot's nodes ``u`` (frame ``F``, robot at
        ``p``), so ``g`` reaches the key from the view exactly when ``g o F`` reaches it from
        the snapshot, with translation ``t_h + h(p)`` for ``h = g o F``.

        >>> from gather_verify.model.canonical import canonical
        >>> c = Configuration([(1, 1), (3, 1), (3, 4)], [(2, 2)])
        >>> v = View(c, (3, 1), frame=geometry.ROT90, detection="local-weak")
        >>> v.canonical() == canonical(v.robots, v.meeting_nodes)
        True
        """
        key, reach = self._snapshot.canonical_form
        undo = geometry.INVERSE[self._frame]
        if len(reach) == 1:
            (h, t), = reach
            g = geometry.COMPOSE[h][undo]
        else:
            g, h, t = min((geometry.COMPOSE[h][undo], h, t) for h, t in reach)
        px, py = self._node
        a, b, c, d = geometry.MATRICES[h]
        return key, g, (t[0] + a * px + b * py, t[1] + c * px + d * py)

    def key(self) -> tuple[object, ...]:
        """Everything this view lets an algorithm read; equal keys, equal decisions."""
        d = self.detection
        if d == "none":
            extra: object = None
        elif d == "local-weak":
            extra = self._counts[ORIGIN] > 1
        elif d == "local-strong":
            extra = self._counts[ORIGIN]
        elif d == "global-weak":
            extra = frozenset(v for v, k in self._counts.items() if k > 1)
        else:
            extra = frozenset(self._counts.items())
        return (self.robots, self.meeting_nodes, d, extra)

    def __repr__(self) -> str:
        return (f"View(robots={sorted(self.robots)}, meeting_nodes={sorted(self.meeting_nodes)}, "
                f"detection={self.detection!r})")


class LuminousView(View):
    """A luminous robot's view on Z² (§10): the :class:`View`, and the lights as far as the
    variant and the detection model show them (asking for more raises :class:`LightHidden`
    or :class:`MultiplicityHidden`). The colours do not turn with the frame.

    >>> c = Configuration([(0, 0), (0, 0), (2, 0)], [(2, 0)])
    >>> v = LuminousView.luminous(c, (0, 0), 0, "local-weak", Lights(3),
    ...                           {(0, 0): Counter({1: 1, 2: 1}), (2, 0): Counter({0: 1})}, 1)
    >>> v.light, sorted(v.colours()), sorted(v.colours((2, 0)))
    (1, [1, 2], [0])
    """

    _lights: Lights
    _colours: Mapping[Node, Counter[int]]
    _mine: int

    @classmethod
    def luminous(cls, configuration: Configuration, node: Node, frame: int, detection: str,
                 lights: Lights, colours: Mapping[Node, Counter[int]],
                 mine: int) -> LuminousView:
        """The view of the robot on ``node`` whose light is ``mine``; ``colours``: the
        lights on each occupied node (global coordinates)."""
        self = object.__new__(cls)
        self.detection = detection
        self._snapshot, self._node, self._frame = configuration, node, frame
        self._meeting = self._robots = self._cnt = None
        self._lights, self._colours, self._mine = lights, colours, mine
        return self

    @property
    def light(self) -> int:
        """The robot's own colour (hidden under external lights)."""
        if self._lights.variant == "external":
            raise LightHidden("external lights: a robot does not see its own colour")
        return self._mine

    def _colours_on(self, v: Node) -> Counter[int]:
        if self._lights.variant == "internal":
            raise LightHidden("internal lights: a robot sees no other robot's colour")
        dx, dy = geometry.apply(geometry.inverse(self._frame), v)
        back = (self._node[0] + dx, self._node[1] + dy)
        seen: Counter[int] = Counter(self._colours.get(back, ()))
        if back == self._node and self._lights.variant == "external":
            seen[self._mine] -= 1  # its own light is the one it cannot see
        return +seen

    def colours(self, v: Node = ORIGIN) -> frozenset[int]:
        """The colours of the lights on ``v`` (default: the robot's own node; under external
        lights its own light is not among them), as a set (how many of each:
        :meth:`colour_counts`, under strong detection)."""
        return frozenset(self._colours_on(v))

    def colour_counts(self, v: Node = ORIGIN) -> dict[int, int]:
        """How many lights of each colour are on ``v`` (strong detection only)."""
        self._visible(v, strong=True)
        return dict(self._colours_on(v))

    def key(self) -> tuple[object, ...]:
        """:meth:`View.key` with the lights the variant shows."""
        variant = self._lights.variant
        own = None if variant == "external" else self._mine
        others = None if variant == "internal" else frozenset(
            (v, frozenset(self._colours_on(v))) for v in self.robots)
        return (*super().key(), own, others)

    def __repr__(self) -> str:
        return (f"LuminousView(robots={sorted(self.robots)}, "
                f"meeting_nodes={sorted(self.meeting_nodes)}, detection={self.detection!r}, "
                f"lights={str(self._lights)!r})")
