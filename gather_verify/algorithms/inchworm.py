"""``ring-inchworm``: exclusive perpetual exploration of a ring by two luminous robots that
see two hops (``--world ring:N --lights 2 --visibility 2 --colours "1 0"``), with no common
direction.

Two oblivious robots side by side have the same view: no deterministic rule tells them
apart, and the adversary can make them mirror each other. A light breaks the tie: the
robot lit 1 (the head) steps away from the other whenever they are side by side; the
robot lit 0 (the tail) steps after it whenever they are two apart. The pair crawls round
the ring in the direction the head faces, never on one node, and visits every node again
and again. The direction comes from the two robots' places, so no frame matters.
"""

from __future__ import annotations

from typing import Any


def other(view: Any) -> Any:
    """The other robot's node in the view (None when it is out of sight or on this node)."""
    seen = [r for r in view.robots if r != view.me]
    return seen[0] if len(seen) == 1 else None


def away_from(view: Any, node: Any) -> Any:
    """The neighbour of the robot farther from ``node``."""
    return max(view.neighbours(), key=lambda v: view.distance(v, node))


def towards(view: Any, node: Any) -> Any:
    return min(view.neighbours(), key=lambda v: view.distance(v, node))


class RingInchworm:
    name = "ring-inchworm"
    plane = False  # it reads a finite world's view (view.me, view.neighbours())

    def decide(self, view: Any) -> Any:
        mate = other(view)
        if mate is None:
            return view.me
        gap = view.distance(view.me, mate)
        if view.light == 1 and gap == 1:
            return away_from(view, mate)
        if view.light == 0 and gap == 2:
            return towards(view, mate)
        return view.me
