"""``go-to-target``: the yardstick algorithm of SEMANTICS.md §4.

Meant for one meeting node: a robot off it steps to a neighbour closer to it
(any such neighbour: the frame, hence the adversary, decides which), a robot
on it stays. With several meeting nodes it heads for the nearest one when that
is unique and stays otherwise, so it is defined everywhere.

>>> from gather_verify.model.configuration import Configuration
>>> from gather_verify.algorithms.moves import move_set
>>> sorted(move_set(GoToTarget(), Configuration([(0, 0)], [(2, 2)]), (0, 0)))
[(0, 1), (1, 0)]
"""

from __future__ import annotations

from collections.abc import Iterable

from gather_verify.algorithms.base import commutes_with_translations
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, STEPS, Node, manhattan
from gather_verify.model.view import View


def nearest(nodes: frozenset[Node], v: Node) -> Node | None:
    """The unique node of ``nodes`` nearest to ``v``, or None on a tie."""
    best = min(manhattan(m, v) for m in nodes)
    closest = [m for m in nodes if manhattan(m, v) == best]
    return closest[0] if len(closest) == 1 else None


def step_towards(target: Node) -> Node:
    """The first unit step (in scan order of STEPS) that brings the origin closer
    to ``target``; with all 8 frames the adversary sees every shortest step."""
    if target == ORIGIN:
        return ORIGIN
    for step in STEPS:
        if manhattan(step, target) < manhattan(ORIGIN, target):
            return step
    raise AssertionError("some step always gets closer")


_HOME = "gather_verify.algorithms.go_to_target"
"""This module's name: a copy of it under another name (``tools/mutants.py`` edits the code
of ``decide``) asks ``decide`` view by view."""
_MOVES_MEMO: dict[tuple[tuple[int, ...], frozenset[Node]], dict[Node, frozenset[Node]]] = {}
"""(frames, meeting nodes) -> node -> its move set (``GoToTarget.move_sets``)."""


def _steps(offsets: tuple[Node, ...], frames: tuple[int, ...]) -> tuple[Node, ...]:
    """The global steps of a robot whose meeting nodes lie at ``offsets`` from it: per frame
    ``g``, what :meth:`GoToTarget.decide` answers on the view (the offsets mapped by ``g``),
    mapped back to global coordinates."""
    steps = set()
    for g in frames:
        a, b, c, d = geometry.MATRICES[g]
        seen = frozenset((a * x + b * y, c * x + d * y) for x, y in offsets)
        answer = GoToTarget().decide(_Seen(seen))  # type: ignore[arg-type]
        steps.add(geometry.apply(geometry.inverse(g), answer))
    return tuple(sorted(steps))


class _Seen:
    """The part of a view ``decide`` reads: the meeting nodes in the robot's frame."""

    __slots__ = ("meeting_nodes",)

    def __init__(self, meeting_nodes: frozenset[Node]):
        self.meeting_nodes = meeting_nodes


def _on_graph(view):  # noqa: ANN001, ANN202 - a WorldView (any world but Z²)
    """``decide`` on a world's graph: towards the unique nearest visible meeting node, by the
    first neighbour (in the frame's order) strictly closer to it in hops; else stay."""
    me, meeting = view.me, view.meeting_nodes
    if not meeting:
        return me
    best = min(view.distance(me, m) for m in meeting)
    closest = [m for m in meeting if view.distance(me, m) == best]
    if len(closest) != 1 or best == 0:
        return me
    (target,) = closest
    for nb in view.neighbours():
        if view.distance(nb, target) < best:
            return nb
    return me


class GoToTarget:
    """Every robot walks to the (unique nearest) meeting node along any shortest path."""

    name = "go-to-target"

    def decide(self, view: View) -> Node:
        # a world's view: asked of its class (the view's own graph is built when asked for)
        if type(view) is not View and hasattr(type(view), "graph"):
            return _on_graph(view)
        meeting = view.meeting_nodes
        target: Node | None
        if len(meeting) == 1:
            (target,) = meeting
        else:
            target = nearest(meeting, ORIGIN)
            if target is None:
                return ORIGIN
        # step_towards, unrolled (the explorer calls this millions of times)
        x, y = target
        return (1, 0) if x > 0 else (0, 1) if y > 0 else (-1, 0) if x < 0 else \
            (0, -1) if y < 0 else ORIGIN

    def move_sets(self, configuration: Configuration, detection: str,
                  frames: Iterable[int]) -> dict[Node, frozenset[Node]] | None:
        """The union of :meth:`decide` over ``frames`` for every occupied node, at once (the
        optional hook of :func:`~gather_verify.algorithms.moves.move_sets`): a robot's
        answer depends only on where the meeting nodes lie relative to it (``decide`` reads
        no other robot and no multiplicity: the same for every detection model), so the move
        set of a node is computed once per frame set and meeting nodes. None (ask ``decide``
        view by view) for a subclass that answers otherwise (the broken variants) and in a
        copy of this module (the mutants)."""
        if type(self).decide is not GoToTarget.decide or __name__ != _HOME:
            return None  # a subclass, or a copy of this module with its code edited (mutants)
        frames = frames if isinstance(frames, tuple) else tuple(frames)
        meeting = configuration.meeting_nodes
        memo = _MOVES_MEMO.get((frames, meeting))
        if memo is None:
            if len(_MOVES_MEMO) >= 64:
                _MOVES_MEMO.clear()
            memo = _MOVES_MEMO[frames, meeting] = {}
        out = {}
        for v in configuration.counts:
            got = memo.get(v)
            if got is None:
                x, y = v
                steps = _steps(tuple((mx - x, my - y) for mx, my in sorted(meeting)), frames)
                if len(memo) >= 1 << 16:
                    memo.clear()
                got = memo[v] = frozenset((x + dx, y + dy) for dx, dy in steps)
            out[v] = got
        return out

    def answers_by_node(self) -> bool:
        """Whether :meth:`decide` reads nothing but the robot's own node, the graph and the
        meeting nodes (no robot, no multiplicity, no light), so that a robot's actions are a
        function of its node and colour (the optional hook of
        :meth:`~gather_verify.worlds.moves.WorldMoves.table` on a finite world, and of the
        bulk engine's facts table on Z², which then asks each node once). False for a
        subclass that answers otherwise (the broken variants) and in a copy of this module
        (the mutants)."""
        return type(self).decide is GoToTarget.decide and __name__ == _HOME

    def target_by_meeting(self) -> bool:
        """Whether :meth:`target` reads nothing of a configuration but its meeting nodes (the
        optional hook of the bulk engine's facts table, which then asks it once for every
        configuration). False for a subclass with its own ``target`` and in a copy of this
        module (the mutants)."""
        return type(self).target is GoToTarget.target and __name__ == _HOME

    @commutes_with_translations
    def target(self, configuration: Configuration) -> Node | None:
        if len(configuration.meeting_nodes) == 1:
            return next(iter(configuration.meeting_nodes))
        return None
