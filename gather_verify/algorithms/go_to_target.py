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


class GoToTarget:
    """Every robot walks to the (unique nearest) meeting node along any shortest path."""

    name = "go-to-target"

    def decide(self, view: View) -> Node:
        meeting = view.meeting_nodes
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

    def target(self, configuration: Configuration) -> Node | None:
        if len(configuration.meeting_nodes) == 1:
            return next(iter(configuration.meeting_nodes))
        return None
