"""The four verdicts (SEMANTICS.md §5) and the order in which a failing property is named.

>>> combine(violated=[], stopped=None)
'VERIFIED'
>>> combine(violated=["final"], stopped="time")
'VIOLATED'
>>> combine(violated=[], stopped="states")
'INCOMPLETE'
>>> named_first(["final", "move-bound", "termination"])
['final', 'termination', 'move-bound']
"""

from __future__ import annotations

from collections.abc import Sequence

VERIFIED, VIOLATED, INCOMPLETE, NOT_APPLICABLE = "VERIFIED", "VIOLATED", "INCOMPLETE", "NOT-APPLICABLE"
VERDICTS = (VERIFIED, VIOLATED, INCOMPLETE, NOT_APPLICABLE)


def combine(violated: Sequence[str], stopped: str | None) -> str:
    """VIOLATED when a property has a concrete counterexample (a real execution, even if the
    search stopped early); else INCOMPLETE when a limit stopped the search; else VERIFIED."""
    if violated:
        return VIOLATED
    if stopped:
        return INCOMPLETE
    return VERIFIED


def named_first(failing: Sequence[str]) -> list[str]:
    """``failing`` (in verdict order) with the property a check is named by first: the first
    in verdict order, except that a livelock is named ``termination``. Where termination fails
    on a fair cycle that moves, move-bound fails too (a cycle with moves has no bound; one
    that changes only colours leaves it bounded): termination is what fails, move-bound is
    how the same cycle shows in the count of moves. A run over the bound while termination is not decided (the search stopped, e.g. a
    run that walks away) stays ``move-bound``: that is what its finite trace proves.

    >>> named_first(["move-bound", "termination"])
    ['termination', 'move-bound']
    >>> named_first(["move-bound"])
    ['move-bound']
    """
    out = list(failing)
    if "termination" in out and "move-bound" in out:
        out.remove("termination")
        out.insert(out.index("move-bound"), "termination")
    return out
