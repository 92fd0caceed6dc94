"""Move sets: how disorientation becomes the adversary's choice.

SEMANTICS.md §3. A robot's move set is the union, over the frames it may hold,
of the algorithm's answer mapped back to global coordinates. With all 8
frames (the paper's disoriented robots) an algorithm that answers "any step
closer" yields every such step; a common compass keeps the identity frame,
common chirality the 4 rotations.

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)])
>>> sorted(move_sets(get_algorithm("go-to-target"), c)[(1, 4)])
[(1, 3), (2, 4)]
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from gather_verify.algorithms.base import Algorithm, AlgorithmCrash, AlgorithmError, Unhandled
from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, STEPS, Node
from gather_verify.model.view import (
    FRAME_SETS,
    LightHidden,
    Lights,
    LuminousView,
    MultiplicityHidden,
    View,
    check_detection,
)
from gather_verify.watchdog import OverMemory, Overtime, real_interrupt, watched

ANSWERS = frozenset((ORIGIN, *STEPS))
MAPPED_BACK = tuple({answer: geometry.apply(geometry.inverse(g), answer) for answer in ANSWERS}
                    for g in geometry.ALL)
"""Per frame, each legal answer as a step in global coordinates."""


class HiddenRead(Unhandled, MultiplicityHidden):
    """The algorithm read multiplicity its detection model hides: it has no rule its robots
    could follow (the explorer reports it as a ``defined`` violation, with a trace).

    Cause and fix: those of :class:`~gather_verify.model.view.MultiplicityHidden`, raised
    from a move set; an :class:`~gather_verify.algorithms.base.Unhandled` as well, so the
    explorer treats it as a missing rule."""


def frames_for(name: str) -> tuple[int, ...]:
    """The frames of a frame-set name (``all``, ``chirality``, ``compass``)."""
    if name not in FRAME_SETS:
        raise InvalidInput(f"unknown frames {name!r}: use one of {', '.join(FRAME_SETS)}")
    return FRAME_SETS[name]


MULTIPLICITY = ((MultiplicityHidden,), "multiplicity its robots cannot see")
"""What an oblivious robot's view can hide (:func:`ask`'s ``hidden``)."""
HIDDEN = ((MultiplicityHidden, LightHidden), "what its robots cannot see")
"""What a luminous robot's view can hide: a multiplicity or a light."""


def ask(algorithm: Algorithm, decide: Callable[[Any], Any], seen: Any, where: Any,
        hidden: tuple[tuple[type[Exception], ...], str] = HIDDEN) -> Any:
    """The answer of ``decide`` (the algorithm's) in the view ``seen`` of the robots at
    ``where``: a read the view hides is no rule (:class:`HiddenRead`); no rule and the
    watchdog's stop at the time limit go through; anything else it raises, SystemExit and
    ``os._exit`` too, is a crash (:class:`AlgorithmCrash`), but a real Ctrl-C stops the
    verifier."""
    try:
        return decide(seen)
    except hidden[0] as error:
        raise HiddenRead(f"algorithm {algorithm.name!r} reads {hidden[1]}: {error}") from None
    except (Unhandled, Overtime, OverMemory):
        raise
    except BaseException as error:
        if real_interrupt(error):
            raise
        raise AlgorithmCrash(algorithm.name, "decide", error, where, seen) from None


def move_set(
    algorithm: Algorithm,
    configuration: Configuration,
    node: Node,
    detection: str = "local-weak",
    frames: Iterable[int] = geometry.ALL,
) -> frozenset[Node]:
    """Global destinations the robots on ``node`` may take (``node`` itself = stay).

    An algorithm that reads multiplicity its detection model hides has no rule its
    robots could follow there: :class:`HiddenRead`, an :class:`Unhandled` (the ``defined``
    property fails)."""
    check_detection(detection)
    if node not in configuration.counts:
        raise ValueError(f"no robot at {node} to take a view from")
    out = set()
    decide, (x, y), view = algorithm.decide, node, View.trusted
    with watched():  # an endless decide ends with the time limit (the watchdog)
        for g in frames:
            seen = view(configuration, node, g, detection)
            answer = ask(algorithm, decide, seen, node, MULTIPLICITY)
            try:
                dx, dy = MAPPED_BACK[g][answer]  # the answer, mapped back to global coordinates
            except (KeyError, TypeError):
                wrong = AlgorithmError(
                    f"algorithm {algorithm.name!r} answered {answer!r}: a move must be (0, 0) "
                    "or a unit step (1, 0), (0, 1), (-1, 0), (0, -1) in the robot's frame")
                raise AlgorithmCrash(algorithm.name, "decide", wrong, node, seen) from None
            out.add((x + dx, y + dy))
    return frozenset(out)


def move_sets(
    algorithm: Algorithm,
    configuration: Configuration,
    detection: str = "local-weak",
    frames: Iterable[int] = geometry.ALL,
) -> dict[Node, frozenset[Node]]:
    """Move set of every occupied node (robots on one node share their view).

    An algorithm may compute them itself, at once for every robot and frame: an optional
    method ``move_sets(configuration, detection, frames)`` returning this dict, or None
    where it cannot (then every view is asked, as :func:`move_set` does). It must equal
    the union of ``decide`` over the frames; the paper's algorithm's is tested against
    it on whole boxes (``tests/test_planned_moves.py``)."""
    frames = tuple(frames)
    planned = getattr(algorithm, "move_sets", None)
    if planned is not None:  # the algorithm computes the union over the frames itself
        try:
            with watched():
                out = planned(configuration, detection, frames)
        except (Unhandled, Overtime, OverMemory):  # no rule; the watchdog's stop at a limit
            raise
        except BaseException as error:  # SystemExit, KeyboardInterrupt, os._exit too
            if real_interrupt(error):  # only a real Ctrl-C stops the verifier
                raise
            raise AlgorithmCrash(algorithm.name, "move_sets", error) from None
        if out is not None:
            return out
    return {v: move_set(algorithm, configuration, v, detection, frames) for v in configuration.counts}


Action = tuple[Node, int]
"""What a luminous robot may do (§10): go to (or stay on) a node, and set its colour."""
LitRobots = tuple[tuple[Node, int], ...]
"""A luminous configuration: every robot's (node, colour), sorted."""


def luminous_actions(algorithm: Algorithm, configuration: Configuration,
                     colours: dict[Node, Counter[int]], node: Node, colour: int,
                     detection: str, frames: Iterable[int], lights: Lights) -> frozenset[Action]:
    """The actions ``(global destination, colour)`` of the robots on ``node`` whose light is
    ``colour``: the union over the frames of the algorithm's answer, mapped back (§3, §10).

    An answer is a move (keep the colour) or ``(move, colour)``, as on a finite world. Reading
    a light or a multiplicity the model hides is no rule (:class:`HiddenRead`); an answer that
    is not a move, or a colour outside ``0..K-1``, is a crash."""
    out = set()
    decide, (x, y) = algorithm.decide, node
    with watched():
        for g in frames:
            seen = LuminousView.luminous(configuration, node, g, detection, lights, colours,
                                         colour)
            answer = ask(algorithm, decide, seen, node)
            back, new = MAPPED_BACK[g], colour
            step = _lookup(back, answer)
            if step is None and isinstance(answer, tuple) and len(answer) == 2:
                step, new = _lookup(back, answer[0]), answer[1]
            problem = None
            if step is None:
                problem = (f"answered {answer!r}: a move must be (0, 0) or a unit step (1, 0), "
                           "(0, 1), (-1, 0), (0, -1) in the robot's frame, or such a move with "
                           "a colour, (move, colour)")
            elif isinstance(new, bool) or not isinstance(new, int) or \
                    not 0 <= new < lights.colours:
                problem = f"answered colour {new!r}: the lights have colours 0..{lights.colours - 1}"
            if problem is not None:
                wrong = AlgorithmError(f"algorithm {algorithm.name!r} {problem}")
                raise AlgorithmCrash(algorithm.name, "decide", wrong, node, seen) from None
            assert step is not None and isinstance(new, int)
            out.add(((x + step[0], y + step[1]), new))
    return frozenset(out)


def _lookup(back: dict[Node, Node], answer: object) -> Node | None:
    try:
        return back.get(answer)  # type: ignore[call-overload]
    except TypeError:  # unhashable
        return None


def luminous_table(algorithm: Algorithm, robots: LitRobots, meeting: frozenset[Node],
                   detection: str, frames: Sequence[int],
                   lights: Lights) -> dict[tuple[Node, int], frozenset[Action]]:
    """The actions of every robot of the luminous configuration ``robots`` (sorted (node,
    colour) pairs), by (node, colour): robots on one node with one colour see one view."""
    configuration = Configuration.trusted(tuple(v for v, _ in robots), meeting)
    colours: dict[Node, Counter[int]] = {}
    for v, c in robots:
        colours.setdefault(v, Counter())[c] += 1
    return {(v, c): luminous_actions(algorithm, configuration, colours, v, c, detection,
                                     frames, lights)
            for v, c in dict.fromkeys(robots)}
