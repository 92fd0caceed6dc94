"""The one check: the phases every world's check goes through (SEMANTICS.md §5), TLC's one
checker behind every front-end.

A world supplies a :class:`Checker`: how it searches its state space (the paper's Z² with
its region growth, :mod:`gather_verify.plane_check`; a finite world,
:mod:`gather_verify.world_check`), how it decides its properties on what it found, and the
report it writes when the watchdog stops the user's code. :func:`run` drives it: the search
and the decisions under the watchdog (the user's code that does not return ends the check
with INCOMPLETE, reason ``time``, never a crash and never VERIFIED). What both worlds ask of
a request before it runs is here too, written once: the user's files imported within the
time limit (:func:`user_code`), the initial colours (:func:`check_colours`), the bulk
engine or the reference (:func:`engine_plan`).

>>> class Counting:
...     def search(self, watch): return 3
...     def decide(self, found): return {"verdict": "VERIFIED", "states": found}
...     def overtime(self, seconds, watch): return {"verdict": "INCOMPLETE"}
>>> run(Counting(), max_seconds=10)
{'verdict': 'VERIFIED', 'states': 3}
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

from gather_verify.errors import InvalidInput
from gather_verify.progress import PROGRESS
from gather_verify.watchdog import Overtime, allowance, deadline

T = TypeVar("T")
Report = TypeVar("Report", covariant=True)
ENGINES = ("auto", "reference", "bulk")
"""The search ``--engine`` names: the bulk engine (numpy and compiled kernels), the reference
(:func:`~gather_verify.engine.bfs.breadth_first`), or ``auto``: the bulk one when it can."""


@dataclass
class Watch:
    """What the watchdog saw: the searches that returned (the last one's counts go into an
    overtime report), and how many seconds into the check it stopped the user's code (None:
    it did not)."""

    searched: list[Any] = field(default_factory=list)
    overtime: float | None = None


class Checker(Protocol[Report]):
    """What a world supplies to the one check: its search, its decisions and its report
    when the user's code ran past the time limit."""

    def search(self, watch: Watch) -> Any:
        """The search (several, where the world grows its region), each recorded in
        ``watch.searched`` as it returns."""
        ...

    def decide(self, found: Any) -> Report:
        """The verdict, every requested property's result and the counterexample's trace."""
        ...

    def overtime(self, seconds: float, watch: Watch) -> Report:
        """The INCOMPLETE report (reason ``time``) of a check the watchdog stopped."""
        ...


def run(checker: Checker[Report], max_seconds: float) -> Report:
    """The check: ``checker``'s search and decisions under the watchdog (its
    :func:`~gather_verify.watchdog.allowance` of ``max_seconds``)."""
    with watchdog(max_seconds) as watch:
        return checker.decide(checker.search(watch))
    assert watch.overtime is not None
    return checker.overtime(watch.overtime, watch)


@contextmanager
def watchdog(max_seconds: float) -> Iterator[Watch]:
    """A block under a :func:`deadline` of the :func:`~gather_verify.watchdog.allowance` of
    ``max_seconds``: the engines read their clock first, and the alarm only stops the user's
    code that does not return (:mod:`gather_verify.watchdog`). When it does, the block ends
    and the :class:`Watch` it yields says so."""
    watch = Watch()
    PROGRESS.states = 0
    try:
        with deadline(allowance(max_seconds)):
            yield watch
    except Overtime as stopped:
        watch.overtime = stopped.seconds


def overtime_reason(seconds: float) -> str:
    """The reason of a check the watchdog stopped, ``seconds`` into it."""
    return f"time (the watchdog stopped your code: still running {seconds:g} s into the check)"


def user_code(max_seconds: float, load: Callable[[], T]) -> T:
    """``load()`` (the algorithm's file, a property's file) within the time limit: a file that
    does not import in time is one line (InvalidInput), not a hang."""
    with deadline(allowance(max_seconds)):
        return load()


def check_colours(colours: Sequence[object] | None, n: int, k: int | None) -> None:
    """InvalidInput (one line) unless ``colours`` gives each of the ``n`` robots a colour of
    the lights' ``k`` (None: no lights given, so no colour may be)."""
    if colours is None:
        return
    if k is None or len(colours) != n or any(
            isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < k for c in colours):
        raise InvalidInput(f"initial colours {list(colours)}: give --lights, and one per robot, "
                           f"each in 0..{(k or 1) - 1}")


def engine_plan(engine: str, unsupported: Callable[[], str | None]) -> tuple[bool, str | None]:
    """Whether the bulk engine runs this check, and why not when ``auto`` falls back to the
    reference: ``reference`` never runs it (and asks nothing), ``bulk`` must (InvalidInput,
    one line, when ``unsupported()`` gives a reason), ``auto`` runs it when
    ``unsupported()`` gives none."""
    if engine not in ENGINES:
        raise InvalidInput(f"unknown engine {engine!r}: use one of {', '.join(ENGINES)}")
    if engine == "reference":
        return False, None
    why = unsupported()
    if engine == "bulk" and why is not None:
        raise InvalidInput(f"the bulk engine cannot run this check: {why} (use --engine auto "
                           "or reference)")
    return why is None, why
