"""Gathering on a meeting node, written by hand for configurations outside U that the
synthesis search left `unknown` (docs/findings.md, "The paper's characterization, checked
by synthesis"). ``TwoMeet``, for two robots: the robot nearer M walks onto a meeting node
while the other waits; then the other walks to it along a shortest path that steps on no
other meeting node when such a path exists (two robots on two meeting nodes can be
symmetric, and then in U). ``ThreeMeet``, for three: see its docstring.

    gather-verify check --robots "1,1 2,1" --meeting "0,0 0,2" --scheduler async \\
        --algorithm docs/examples/meet_by_hand.py:TwoMeet --no-reduction --force \\
        --property final --property termination

Only one robot moves in each configuration of a run, so a stale ASYNC move cannot happen.
Neither is an algorithm for every configuration: two robots at the same distance from M,
neither on it, wait for ever.
"""

from gather_verify.model.geometry import Node
from gather_verify.model.view import View

STEPS: tuple[Node, ...] = ((1, 0), (-1, 0), (0, 1), (0, -1))


def distance(a: Node, b: Node) -> int:
    """Manhattan distance: the length of a shortest path on Z²."""
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def clear(s: Node, p: Node, avoid: frozenset[Node]) -> bool:
    """Whether some shortest path from ``s`` to ``p`` steps on no node of ``avoid``."""
    if s in avoid:
        return False
    if s == p:
        return True
    return any(clear((s[0] + dx, s[1] + dy), p, avoid) for dx, dy in STEPS
               if distance((s[0] + dx, s[1] + dy), p) < distance(s, p))


class TwoMeet:
    """The robot on a meeting node stays; the other walks to it; before that, the robot
    strictly nearer M walks to M and the farther one waits."""

    name = "two-meet"

    def __init__(self, avoid_meeting: bool = True):
        self.avoid_meeting = avoid_meeting

    def decide(self, view: View) -> Node:
        """The destination, in the robot's frame (the robot is at the origin)."""
        o: Node = (0, 0)
        m = view.meeting_nodes
        others = [r for r in view.robots if r != o]
        if o in m or not others:
            return o
        p = others[0]
        if p in m:
            avoid = m - {p} if self.avoid_meeting else frozenset()
            return min(STEPS, key=lambda s: (distance(s, p), not clear(s, p, avoid), s))

        def near(v: Node) -> int:
            return min(distance(v, x) for x in m)

        if near(o) < near(p):
            return min(STEPS, key=lambda s: (near(s), s))
        return o


class Careless(TwoMeet):
    """The same, walking onto any meeting node on the way: it can end on two meeting nodes
    in a symmetric configuration (a deliberately broken variant, for the tests)."""

    name = "two-meet-careless"

    def __init__(self) -> None:
        super().__init__(avoid_meeting=False)


class ThreeMeet:
    """The target is the meeting node nearest the robots (least sum of distances to the
    occupied nodes) when only one is; every robot walks to it, avoiding the other meeting
    nodes when it can. On a tie, a robot off M walks to its nearest meeting node and one on
    M waits, except a lone robot facing one other occupied meeting node: it walks there (the
    other node then holds the multiplicity, which only its own robots see, and they stay)."""

    name = "three-meet"

    def __init__(self, tie_rule: bool = True):
        self.tie_rule = tie_rule

    def decide(self, view: View) -> Node:
        """The destination, in the robot's frame (the robot is at the origin)."""
        o: Node = (0, 0)
        m = view.meeting_nodes
        if view.multiplicity():
            return o
        score = {x: sum(distance(x, r) for r in view.robots) for x in m}
        best = min(score.values())
        targets = [x for x in m if score[x] == best]
        others = [r for r in view.robots if r != o]
        if len(targets) == 1 or (self.tie_rule and o in m and len(others) == 1
                                      and others[0] in m):
            t = targets[0] if len(targets) == 1 else others[0]
            if o == t:
                return o
            avoid = m - {t}
            return min(STEPS, key=lambda s: (distance(s, t), not clear(s, t, avoid), s))
        if o in m:
            return o
        return min(STEPS, key=lambda s: (min(distance(s, x) for x in m), s))


class ThreeMeetNoTie(ThreeMeet):
    """ThreeMeet without its tie rule: the lone robot waits for ever (a deliberately broken
    variant, for the tests)."""

    name = "three-meet-no-tie"

    def __init__(self) -> None:
        super().__init__(tie_rule=False)
