"""``beacon``: gathering on a meeting node of Z² with a light of two colours (SEMANTICS.md §10).

Robots head for their nearest meeting node. The first robot to step onto a meeting node (or
to find itself on one) turns its light on (colour 1): it has *claimed* that node, and stays
there. A robot that sees a lit robot on a meeting node goes there instead; while the lit
robot is still on its way (under ASYNC the light changes at the Look, before the move) the
others wait. A lit robot never moves again.

The light is what makes it work: without it (``broken-beacon``) robots nearest to different
meeting nodes stop on both. Under ASYNC and the centralized adversary one Look at a time
sets a light, so the second robot to claim sees the first claim; under SSYNC two robots
looking at once may claim two meeting nodes, and then they wait for each other for ever:
the checker finds that deadlock.

>>> from gather_verify.plane_check import run_check
>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(1, 1), (3, 2)], [(0, 0), (4, 0)], initial=True)
>>> run_check(c, algorithm="beacon", scheduler="async", lights="2")["verdict"]
'VERIFIED'
>>> run_check(c, algorithm="beacon", scheduler="ssync", lights="2")["property"]
'final'
"""

from __future__ import annotations

from typing import Any

Node = tuple[int, int]


def _distance(a: Node, b: Node) -> int:
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def _towards(view: Any, targets: list[Node]) -> Node:
    """The first neighbour (in the frame's order) closer to the nearest of ``targets``: over
    the frames, every such neighbour."""
    here = view.me
    best = min(_distance(here, t) for t in targets)
    goals = [t for t in targets if _distance(here, t) == best]
    return next(v for v in view.neighbours() if any(_distance(v, t) < best for t in goals))


class Beacon:
    """Claim the first meeting node reached with the light; everyone else goes there."""

    name = "beacon"
    luminous = True  # it answers colours: check it with --lights 2

    def decide(self, view: Any) -> Any:
        if view.light == 1:  # a claimed meeting node: stay on it
            return view.me
        lit = [v for v in view.robots if 1 in view.colours(v)]
        if lit:
            if len(lit) > 1 or lit[0] not in view.meeting_nodes:
                return view.me  # two claims, or the claimer still on its way: wait
            return view.me if lit[0] == view.me else _towards(view, lit)
        meeting = sorted(view.meeting_nodes)
        if view.me in view.meeting_nodes:
            return view.me, 1  # claim the node it stands on (a colour change is an event)
        step = _towards(view, meeting)
        return (step, 1) if step in view.meeting_nodes else step
