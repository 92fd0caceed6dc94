"""Deliberately broken algorithms: each makes one property fail (for tests and demos).

They are not in the default registry: :func:`gather_verify.algorithms.get_algorithm`
adds them (``BROKEN``) on first use of a ``broken-*`` name, so the tests,
``gather-verify check --algorithm broken-stay`` and ``replay`` of their traces
all find them. All assume one meeting node unless said otherwise.

>>> sorted(BROKEN)[:3]
['broken-answer', 'broken-away', 'broken-beacon']
"""

from __future__ import annotations

from typing import Any

from gather_verify.algorithms.base import Unhandled, commutes_with_translations
from gather_verify.algorithms.beacon import Beacon
from gather_verify.algorithms.go_to_target import GoToTarget, nearest, step_towards
from gather_verify.algorithms.inchworm import RingInchworm, other, towards
from gather_verify.algorithms.ring_exploration import RingExplore
from gather_verify.algorithms.ring_gathering import RingGather
from gather_verify.algorithms.ring_gathering import towards as towards_on_ring
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, Node, manhattan
from gather_verify.model.view import View


def _away(target: Node) -> Node:
    """A unit step that increases the distance to ``target``."""
    for step in ((1, 0), (0, 1), (-1, 0), (0, -1)):
        if manhattan(step, target) > manhattan(ORIGIN, target):
            return step
    raise AssertionError("some step always gets farther")


class Away(GoToTarget):
    """Steps away from the target at odd distance, towards it at even distance: walks in a
    cycle forever (termination and move-bound fail)."""

    name = "broken-away"

    def decide(self, view: View) -> Node:
        target = nearest(view.meeting_nodes, ORIGIN)
        if target is None or target == ORIGIN:
            return ORIGIN
        return _away(target) if manhattan(ORIGIN, target) % 2 else step_towards(target)


class Stay(GoToTarget):
    """Stops one step short of the target: a deadlock (final fails)."""

    name = "broken-stay"

    def decide(self, view: View) -> Node:
        target = nearest(view.meeting_nodes, ORIGIN)
        if target is None or manhattan(ORIGIN, target) <= 1:
            return ORIGIN
        return step_towards(target)


class Drift(GoToTarget):
    """Walks to the nearest meeting node, but names as target the meeting node nearest to
    the lowest robot: the target changes as robots move (target-invariance fails)."""

    name = "broken-drift"

    @commutes_with_translations
    def target(self, configuration: Configuration) -> Node | None:
        low = min(configuration.robots, key=lambda v: (v[1], v[0]))
        return min(configuration.meeting_nodes, key=lambda m: (manhattan(m, low), m))


class Wander(GoToTarget):
    """Every robot off a meeting node steps anywhere: reaches U from outside U
    (no-ungatherable fails)."""

    name = "broken-wander"

    def decide(self, view: View) -> Node:
        return ORIGIN if ORIGIN in view.meeting_nodes else (1, 0)


class Undefined(GoToTarget):
    """Has no rule one step from the target (raises Unhandled: ``defined`` fails)."""

    name = "broken-undefined"

    def decide(self, view: View) -> Node:
        target = nearest(view.meeting_nodes, ORIGIN)
        if target is not None and manhattan(ORIGIN, target) == 1:
            raise Unhandled("one step from the target")
        return super().decide(view)


class Crash(GoToTarget):
    """Divides by zero one step from the target (a bug: ``crash`` fails)."""

    name = "broken-crash"

    def decide(self, view: View) -> Node:
        target = nearest(view.meeting_nodes, ORIGIN)
        if target is not None and manhattan(ORIGIN, target) == 1:
            return (1 // (manhattan(ORIGIN, target) - 1), 0)
        return super().decide(view)


class BadAnswer(GoToTarget):
    """Answers a jump of two nodes one step from the target (not a move: ``crash`` fails)."""

    name = "broken-answer"

    def decide(self, view: View) -> Node:
        target = nearest(view.meeting_nodes, ORIGIN)
        if target is not None and manhattan(ORIGIN, target) == 1:
            return (2 * target[0], 2 * target[1])
        return super().decide(view)


class CrashTarget(GoToTarget):
    """Its ``target`` fails with a KeyError once a robot is one step from a meeting node."""

    name = "broken-crash-target"

    @commutes_with_translations
    def target(self, configuration: Configuration) -> Node | None:
        if any(manhattan(v, m) == 1 for v in configuration.robots
               for m in configuration.meeting_nodes):
            raise KeyError("no plan for a robot next to a meeting node")
        return super().target(configuration)


class RingGatherBoth(RingGather):
    """``ring-gather`` whose closest pair both step towards each other: at an odd gap they
    cross over and on (under FSYNC they swap for ever: termination fails)."""

    name = "broken-ring-gather"

    def pair_move(self, view: Any, a: Any, b: Any, behind_a: int, behind_b: int) -> Any:
        if view.me in (a, b):
            return towards_on_ring(view, b if view.me == a else a)
        return view.me


class RingExploreBlind(RingExplore):
    """``ring-explore`` that steps forward even onto a robot (exclusivity fails)."""

    name = "broken-ring-explore"

    def decide(self, view: Any) -> Any:
        return self.forward(view)


class InchwormEager(RingInchworm):
    """``ring-inchworm`` whose tail steps after the head even when they are side by side:
    onto the head's node (exclusivity fails)."""

    name = "broken-ring-inchworm"

    def decide(self, view: Any) -> Any:
        mate = other(view)
        if mate is not None and view.light == 0:
            return towards(view, mate)
        return super().decide(view)


class BeaconDark(Beacon):
    """``beacon`` that never turns its light on: robots nearest to different meeting nodes
    stop on both (``final`` fails)."""

    name = "broken-beacon"

    def decide(self, view: Any) -> Any:
        answer = super().decide(view)
        return answer[0] if isinstance(answer[0], tuple) else answer


BROKEN = {cls.name: cls for cls in (Away, Stay, Drift, Wander, Undefined, Crash, BadAnswer,
                                    CrashTarget, RingGatherBoth, RingExploreBlind,
                                    InchwormEager, BeaconDark)}

