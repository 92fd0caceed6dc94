"""``ring-gather``: gathering on a ring without meeting nodes, for a ring world
(``--world ring:N``) under global-weak multiplicity detection.

A demonstration of the field's classic idea, not a published algorithm: first make
one tower, then walk to it.

- Where a tower (a node of several robots) is in sight, a robot off it steps towards
  the nearest tower (if one is nearest); robots on a tower stay.
- With no tower, take the two robots at the smallest gap. If that pair is unique, the
  one of them with the larger gap behind it steps towards the other; every other robot
  stays. The pair stays unique and only one robot moves, so the tower forms under every
  scheduler.
- Anything symmetric (two smallest gaps, or equal gaps behind the pair) has no rule
  that breaks the tie: the robots stay, a deadlock the verifier reports, as the field
  expects of symmetric configurations (two robots never gather this way).

It reads which other nodes are towers, so it needs ``--multiplicity global-weak``;
under a weaker model the read is refused (the ``defined`` property fails).
"""

from __future__ import annotations

from typing import Any


def walk(view: Any, first: Any) -> list[Any]:
    """The ring from ``view.me`` through its neighbour ``first``, once round (``me`` first)."""
    order, prev, here = [view.me], view.me, first
    while here != view.me:
        order.append(here)
        prev, here = here, next(v for v in view.neighbours(here) if v != prev)
    return order


def gaps(view: Any) -> list[tuple[Any, Any, int]]:
    """The gaps round the ring: ``(robot, next robot, hops between)`` in one direction."""
    order = walk(view, view.neighbours()[0])
    robots = [k for k, v in enumerate(order) if v in view.robots]
    out = []
    for a, b in zip(robots, robots[1:] + [robots[0] + len(order)], strict=True):
        out.append((order[a], order[b % len(order)], b - a))
    return out


def towards(view: Any, target: Any) -> Any:
    """The first neighbour strictly closer to ``target`` (the frames give the others)."""
    best = view.distance(view.me, target)
    for nb in view.neighbours():
        if view.distance(nb, target) < best:
            return nb
    return view.me


class RingGather:
    name = "ring-gather"
    plane = False  # it reads a finite world's view (view.me, view.neighbours())

    def decide(self, view: Any) -> Any:
        towers = [v for v in view.robots if view.multiplicity(v)]
        if towers:
            if view.me in towers:
                return view.me
            near = min(view.distance(view.me, t) for t in towers)
            closest = [t for t in towers if view.distance(view.me, t) == near]
            return towards(view, closest[0]) if len(closest) == 1 else view.me
        ring = gaps(view)
        if len(ring) < 2:
            return view.me
        smallest = min(g for _, _, g in ring)
        pairs = [k for k, (_, _, g) in enumerate(ring) if g == smallest]
        if len(pairs) != 1:
            return view.me
        k = pairs[0]
        a, b, _ = ring[k]
        behind_a, behind_b = ring[k - 1][2], ring[(k + 1) % len(ring)][2]
        return self.pair_move(view, a, b, behind_a, behind_b)

    def pair_move(self, view: Any, a: Any, b: Any, behind_a: int, behind_b: int) -> Any:
        """The move of the closest pair ``a``, ``b``: the one with more room behind it goes."""
        if view.me == a and behind_a > behind_b:
            return towards(view, b)
        if view.me == b and behind_b > behind_a:
            return towards(view, a)
        return view.me
