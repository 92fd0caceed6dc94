"""The paper's theory: its strings, classes and U, its ``Gathering()``, its readings and
Theorem 1's adversary, and what it registers for the generic layers.

- :mod:`~gather_verify.paper.strings`: corner strings, key and leading corners, orderings (§2, §4);
- :mod:`~gather_verify.paper.classes`: the classes I11 ... I42, UNCLASSIFIED and U (§3.1, §3.2);
- :mod:`~gather_verify.paper.algorithm`: ``Gathering()`` (§4), the algorithm ``paper``;
- :mod:`~gather_verify.paper.readings`: the readings of its passages, and their robustness;
- :mod:`~gather_verify.paper.impossibility`: Theorem 1's adversary on U.

Importing this package registers, in :mod:`gather_verify.theory`, the facts ``class`` and
``in_U``, the precondition of check (NOT-APPLICABLE in U or UNCLASSIFIED, for robots
with no common orientation), the scope of ``no-ungatherable`` (U is Theorem 1's: for
oblivious robots with no common orientation) and its words (U and its classes I41/I42).
The generic layers look them up there and
never import this package (``lint-imports``).

>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
>>> class_of(c), in_u(c), not_applicable(c, "all") is None
('I13', False, True)
"""

from __future__ import annotations

from collections.abc import Sequence

from gather_verify import theory
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import Automorphism
from gather_verify.paper.classes import CLASS_NAMES, classification, never_in_u


@theory.fact("class", values=CLASS_NAMES)
def class_of(c: Configuration, aut_m_all: Sequence[Automorphism] | None = None) -> str:
    """The configuration's class (§3.1)."""
    return classification(c, aut_m_all).name


@theory.fact("class_reason")
def class_reason(c: Configuration, aut_m_all: Sequence[Automorphism] | None = None) -> str:
    """Why the configuration is of its class (its symmetries, what lies on L or c)."""
    return classification(c, aut_m_all).reason


@theory.fact("in_U", never=never_in_u, symmetric_only=True)
def in_u(c: Configuration, aut_m_all: Sequence[Automorphism] | None = None) -> bool:
    """Whether the configuration is in U (§3.2): ungatherable by Theorem 1."""
    return classification(c, aut_m_all).in_U


@theory.precondition("in U or unclassified: the impossibility checks apply",
                     legend="NOT-APPLICABLE: in U or UNCLASSIFIED, where the impossibility "
                            "checks apply (--force checks them)")
def not_applicable(c: Configuration, frames: str) -> str | None:
    """Why check does not apply to ``c``: in U or UNCLASSIFIED, for robots with no common
    orientation (all 8 frames); with a common compass or chirality the paper's U and
    partition say nothing, and such a configuration is checked like any other."""
    if frames != "all":
        return None
    cls = classification(c)
    if cls.in_U or cls.name == "UNCLASSIFIED":
        return f"initial configuration is {cls.name}: use the impossibility checks (or --force)"
    return None


NO_UNGATHERABLE_SCOPE = theory.scope(
    "no-ungatherable",
    frames=("all",),
    frames_why="U (Theorem 1) is for robots with no common orientation",
    oblivious=True,
    lights_why="U (Theorem 1) is where oblivious robots cannot gather: robots on its nodes "
               "with different colours are not symmetric, so a luminous algorithm may pass "
               "through it")
"""Where ``no-ungatherable`` applies: U is Theorem 1's, where robots with no common
orientation and no lights cannot gather; a common compass or chirality may gather there,
and so may robots whose colours break U's symmetry."""

NO_UNGATHERABLE_WORDS = theory.words(
    "no-ungatherable",
    message="a configuration in U (I41/I42) is reached from one outside U",
    vacuous="initial configuration is in U",
    doc="from an initial configuration outside U, no reachable configuration is in U")
"""What ``no-ungatherable`` says, in the paper's terms: U (§3.2), which holds the classes
I41 and I42, is where Theorem 1 makes gathering impossible."""
