"""The algorithm protocol: what a user implements to have it verified.

SEMANTICS.md §3. An algorithm is an object with a ``name`` and a pure
function ``decide(view) -> Node`` answering, in the robot's own frame, the
origin (stay) or one of its four neighbours. Robots are oblivious: the view is
all an algorithm may use. Optionally ``target(configuration)`` names, in
global coordinates, the target meeting node the algorithm heads for; the
explorer then checks that it never changes (target invariance). Optionally
``phase(configuration) -> str | None`` names the rule (phase) the algorithm
applies there; a violation's ``cause`` quotes it.

>>> from gather_verify.algorithms import get_algorithm
>>> algorithm = get_algorithm("go-to-target")
>>> algorithm.name
'go-to-target'
"""

from __future__ import annotations

import os
import sysconfig
import traceback
from collections.abc import Callable
from typing import Protocol, TypeVar, runtime_checkable

from gather_verify.errors import GatherVerifyError, InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.view import View
from gather_verify.watchdog import OverMemory, Overtime, real_interrupt, watched

F = TypeVar("F", bound=Callable[..., object])


@runtime_checkable
class Algorithm(Protocol):
    """What the verifier needs from an algorithm."""

    name: str

    def decide(self, view: View) -> Node:
        """The robot's destination in its own frame: ``(0, 0)`` or a unit step."""
        ...


class Unhandled(GatherVerifyError):
    """The algorithm has no rule for this view (the paper leaves the case open).

    Raise it instead of inventing a move: the explorer reports the state as a
    violation of the ``defined`` property, with the trace that reaches it.

    Cause: an algorithm raised it (or read what its model hides: :class:`HiddenRead`).
    Fix: give the algorithm a rule for the view in the trace, or accept the ``defined``
    violation as the finding.
    """


class AlgorithmError(InvalidInput):
    """The algorithm answered something that is not a move: a bug in the *algorithm* (the
    user's, when it is a plug-in), so exit 2 naming it, not a bug of gather-verify.

    Cause: ``decide`` returned a value that is not a move: on the grid neither ``(0, 0)`` nor
    a unit step, in a finite world neither the robot's node, a neighbour, nor (with lights)
    such a node with a colour in range. It reaches the user wrapped in an
    :class:`AlgorithmCrash`. Fix: the message names the algorithm and the answer; make it
    return a move in the robot's frame."""


_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_LIBRARY = tuple(os.path.abspath(p) + os.sep for p in {
    sysconfig.get_paths()[k] for k in ("stdlib", "platstdlib", "purelib", "platlib")})


class AlgorithmCrash(GatherVerifyError):
    """An exception escaped the algorithm's ``decide`` or ``target``, or ``decide`` answered
    something that is not a move: a bug in the algorithm. The explorer reports the state as
    a violation of the ``crash`` property, with the shortest trace that reaches it.

    Cause: the algorithm's code raised (``exception``, ``frames``). Fix: correct the
    algorithm at the frame it names, replaying the trace to see the view it crashed on.

    Plain data only (it crosses process boundaries): ``call`` (decide or target), the robot's
    ``node`` and its ``view`` (robots and meeting nodes in its frame) for ``decide``, the
    ``exception`` as text and the ``frames`` of the traceback outside gather-verify (the
    algorithm's own file)."""

    def __init__(self, algorithm: str, call: str, error: BaseException,
                 node: Node | None = None, view: View | None = None):
        self.algorithm, self.call, self.node = algorithm, call, node
        frame = getattr(view, "_frame", None)
        self.frame = frame if isinstance(frame, int) else None
        self.view = None if view is None else {
            "robots": [_plain(v) for v in sorted(view.robots)],
            "meeting_nodes": [_plain(v) for v in sorted(view.meeting_nodes)]}
        self.exception = f"{type(error).__name__}: {error}" if str(error) else type(error).__name__
        frames = traceback.extract_tb(error.__traceback__)
        own = [f for f in frames if not f.filename.startswith(_PACKAGE + os.sep)]
        mine = [f for f in own if not f.filename.startswith(_LIBRARY)]
        self.frames = [f"{f.filename}:{f.lineno} in {f.name}: {(f.line or '').strip()}"
                       for f in (mine or own or frames[-3:])]
        where = "" if node is None else f" for the robot at {_shown(node)}"
        self.reason = f"the algorithm crashed in {call}{where}: {self.exception}"
        super().__init__(f"algorithm {algorithm!r} crashed in {call}{where}: {self.exception}")

    def detail(self) -> dict[str, object]:
        """What a ``crash`` trace records under ``detail`` (JSON)."""
        return {"call": self.call, "robot_node": None if self.node is None else _plain(self.node),
                "frame": self.frame, "view": self.view, "exception": self.exception,
                "traceback": self.frames}


def _plain(node: object) -> object:
    """A node as JSON holds it: a pair as a list, a ring's int or a graph's id as it is."""
    return list(node) if isinstance(node, tuple) else node


def _shown(node: object) -> str:
    return str(tuple(node)) if isinstance(node, tuple | list) else repr(node)


def commutes_with_translations(target: F) -> F:
    """Mark an algorithm's ``target`` method as commuting with translations,
    ``target(C + t) == target(C) + t`` for every configuration ``C`` and vector ``t``: the
    union engine of a sweep (:mod:`gather_verify.engine.union`) reads the target on a
    translate of a configuration, so it decides target-invariance from one shared graph only
    for a target so marked; any other is read by each configuration's own search. The mark
    belongs to the function: a subclass that overrides ``target`` has none unless it says so."""
    target.commutes_with_translations = True  # type: ignore[attr-defined]
    return target


def target_commutes_with_translations(algorithm: object) -> bool:
    """Whether ``algorithm`` has no ``target``, or one marked :func:`commutes_with_translations`."""
    target = getattr(algorithm, "target", None)
    return target is None or getattr(target, "commutes_with_translations", False) is True


def target_of(algorithm: object, configuration: Configuration) -> Node | None:
    """The algorithm's target meeting node for ``configuration``, if it exposes one
    (an exception other than :class:`Unhandled` is an :class:`AlgorithmCrash`)."""
    target = getattr(algorithm, "target", None)
    if target is None:
        return None
    try:
        with watched():
            return target(configuration)
    except (Unhandled, Overtime, OverMemory):  # no rule; the watchdog's stop at a limit
        raise
    except BaseException as error:  # SystemExit, KeyboardInterrupt, os._exit too
        if real_interrupt(error):  # only a real Ctrl-C stops the verifier
            raise
        raise AlgorithmCrash(getattr(algorithm, "name", "?"), "target", error) from None


def phase_of(algorithm: object, configuration: Configuration) -> str | None:
    """The algorithm's phase for ``configuration`` if it names one (None when it has no
    ``phase``, no rule there, or its ``phase`` fails: a cause is a label, never a crash).

    >>> from gather_verify.algorithms import get_algorithm
    >>> phase_of(get_algorithm("go-to-target"), None) is None
    True
    """
    phase = getattr(algorithm, "phase", None)
    if phase is None:
        return None
    try:
        with watched():  # (the watchdog's Overtime is no Exception: it goes through)
            got = phase(configuration)
    except Exception:  # noqa: BLE001 - the cause is optional; the search reports crashes
        return None
    return got if isinstance(got, str) else None
