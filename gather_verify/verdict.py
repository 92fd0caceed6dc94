"""The four verdicts (SEMANTICS.md §5) and the order in which a failing property is named.

>>> combine(violated=[], stopped=None)
'VERIFIED'
>>> combine(violated=["final"], stopped="time")
'VIOLATED'
>>> combine(violated=[], stopped="states")
'INCOMPLETE'
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
