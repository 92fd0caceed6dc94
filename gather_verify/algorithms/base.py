"""The algorithm protocol: what a user implements to have it verified.

SEMANTICS.md §3. An algorithm is an object with a ``name`` and a pure
function ``decide(view) -> Node`` answering, in the robot's own frame, the
origin (stay) or one of its four neighbours. Robots are oblivious: the view is
all an algorithm may use. Optionally ``target(configuration)`` names, in
global coordinates, the target meeting node the algorithm heads for; the
explorer then checks that it never changes (target invariance).

>>> from gather_verify.algorithms import get_algorithm
>>> algorithm = get_algorithm("go-to-target")
>>> algorithm.name
'go-to-target'
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.view import View


@runtime_checkable
class Algorithm(Protocol):
    """What the verifier needs from an algorithm."""

    name: str

    def decide(self, view: View) -> Node:
        """The robot's destination in its own frame: ``(0, 0)`` or a unit step."""
        ...


class Unhandled(Exception):
    """The algorithm has no rule for this view (the paper leaves the case open).

    Raise it instead of inventing a move: the explorer reports the state as a
    violation of the ``defined`` property, with the trace that reaches it.
    """


class AlgorithmError(InvalidInput):
    """The algorithm answered something that is not a move: a bug in the *algorithm* (the
    user's, when it is a plug-in), so exit 2 naming it, not a bug of gather-verify."""


def target_of(algorithm: object, configuration: Configuration) -> Node | None:
    """The algorithm's target meeting node for ``configuration``, if it exposes one."""
    target = getattr(algorithm, "target", None)
    return None if target is None else target(configuration)
