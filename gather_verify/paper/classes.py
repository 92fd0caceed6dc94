"""The paper's partition of initial configurations into I11 ... I42 (and what it misses).

Paper §3.1 ("Partitioning of the initial configuration") and Corollary 1,
exactly as SEMANTICS.md §2 defines them:

- I11: ``Aut(M)`` trivial.
- ``M`` has one reflection (axis L, no rotation): I12 if a meeting node is on
  L; else I21 if ``Aut(C)`` is trivial; else I31 if a robot is on L, else I41.
- ``M`` has a rotation (centre c): I13 if a meeting node is on c; else I22 if
  ``Aut(C)`` is trivial; else, when ``Aut(C)`` holds a rotation, I32 with a
  robot on c and I42 without.
- UNCLASSIFIED: ``M`` has a rotation, no meeting node on c, and ``Aut(C)`` is a
  single reflection.

``in_U`` is a flag beside the class, as the end of the paper's §3.2 describes U
(SEMANTICS.md §2): ``Aut(C)`` is a single reflection whose axis holds no robot
and no meeting node, or holds a rotation whose centre holds neither. I41 and
I42 are in U, and so is an UNCLASSIFIED configuration whose axis is empty
(Theorem 1 makes it ungatherable); one whose axis holds a meeting node is not.

>>> classify([(0, 1), (2, 1)], [(0, 0), (2, 0)]).name
'UNCLASSIFIED'
>>> classify([(0, 1), (2, 1)], [(0, 0), (2, 0)]).in_U  # the axis x = 1 holds nothing
True
>>> classify([(0, 0), (2, 2)], [(0, 2), (2, 0), (1, 1)]).in_U  # a meeting node on c: I13
False
>>> classify([(0, 1)], [(0, 0), (3, 0), (1, 1), (2, 1)]).name
'I21'
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.symmetry import (
    Automorphism,
    configuration_automorphisms,
    meeting_automorphisms,
)
from gather_verify.paper import strings

CLASS_NAMES = ("I11", "I12", "I13", "I21", "I22", "I31", "I32", "I41", "I42", "UNCLASSIFIED")
UNGATHERABLE = frozenset({"I41", "I42"})
"""The classes wholly in U; UNCLASSIFIED configurations are in U when their axis is empty."""


@dataclass(frozen=True)
class Classification:
    """The class of an initial configuration and why."""

    name: str
    reason: str
    symmetry: Automorphism | None = None  # the symmetry of M the class is about (L or c)
    configuration_symmetries: tuple[Automorphism, ...] = field(default=())
    meeting_on: tuple[Node, ...] = ()  # meeting nodes on L or c
    robots_on: tuple[Node, ...] = ()  # robot nodes on L or c
    in_U: bool = False
    """In U as §3.2 describes it (:func:`in_U_of`): ungatherable by Theorem 1."""

    @property
    def group(self) -> str:
        """``I1``, ``I2``, ``I3``, ``I4`` or ``UNCLASSIFIED``."""
        return self.name if self.name == "UNCLASSIFIED" else self.name[:2]

    def to_json(self) -> dict[str, object]:
        return {
            "class": self.name,
            "in_U": self.in_U,
            "reason": self.reason,
            "symmetry": self.symmetry.to_json() if self.symmetry else None,
            "configuration_symmetries": [a.describe() for a in self.configuration_symmetries],
            "meeting_nodes_on_symmetry": [list(v) for v in self.meeting_on],
            "robots_on_symmetry": [list(v) for v in self.robots_on],
        }


def in_U_of(c: Configuration, aut_c: Sequence[Automorphism]) -> bool:
    """U as the end of the paper's §3.2 describes it, per configuration (full labels):
    ``Aut(C)`` (without the identity: ``aut_c``) is a unique line of symmetry whose axis
    holds no robot and no meeting node, or holds a rotation whose centre holds neither."""
    if not aut_c:
        return False
    marked = c.occupied | c.meeting_nodes
    rotation = next((a for a in aut_c if a.kind == "rotation"), None)
    if rotation is not None:  # every rotation of a finite group has the same centre
        return not any(rotation.fixes(v) for v in marked)
    return len(aut_c) == 1 and not any(aut_c[0].fixes(v) for v in marked)


def classify_configuration(
    c: Configuration, *, aut_m_all: Sequence[Automorphism] | None = None
) -> Classification:
    """Classify a configuration by the symmetries of ``M`` and of ``C``.

    ``aut_m_all`` may pass ``meeting_automorphisms(c)`` already computed (the
    census reuses it across configurations with the same ``M``).
    """
    aut_m = list(meeting_automorphisms(c) if aut_m_all is None else aut_m_all)[1:]
    aut_c = tuple(configuration_automorphisms(c)[1:])
    if not aut_m:
        return Classification("I11", "M is asymmetric")
    rotations = [a for a in aut_m if a.kind == "rotation"]
    if not rotations:
        if len(aut_m) != 1:  # two reflections compose to a rotation
            raise AssertionError(f"M has reflections but no rotation: {aut_m}")
        mirror = aut_m[0]
        meeting_on = tuple(sorted(m for m in c.meeting_nodes if mirror.fixes(m)))
        robots_on = tuple(sorted(r for r in c.occupied if mirror.fixes(r)))
        where = f"M has one reflection ({mirror.describe()})"
        if meeting_on:
            name, why = "I12", "a meeting node lies on L"
        elif not aut_c:
            name, why = "I21", "no meeting node on L and C is asymmetric"
        elif robots_on:
            name, why = "I31", "C is symmetric about L, a robot lies on L, no meeting node"
        else:
            name, why = "I41", "C is symmetric about L with no robot or meeting node on L"
        return Classification(name, f"{where}: {why}", mirror, aut_c, meeting_on, robots_on,
                              in_U_of(c, aut_c))
    rotation = min(rotations, key=lambda a: a.order == 2)  # prefer the 90-degree one
    centre = rotation.centre2
    assert centre is not None
    meeting_on = tuple(m for m in c.meeting_nodes if rotation.fixes(m))
    robots_on = tuple(r for r in c.occupied if rotation.fixes(r))
    where = f"M has a {rotation.describe()}"
    if meeting_on:
        name, why = "I13", "a meeting node lies on the centre c"
    elif not aut_c:
        name, why = "I22", "no meeting node on c and C is asymmetric"
    elif any(a.kind == "rotation" for a in aut_c):
        if robots_on:
            name, why = "I32", "C is rotationally symmetric with a robot on c"
        else:
            name, why = "I42", "C is rotationally symmetric with no robot or meeting node on c"
    else:
        name = "UNCLASSIFIED"
        why = (
            f"C has only a reflection ({aut_c[0].describe()}) while M is rotationally "
            "symmetric with no meeting node on c: the paper's partition misses this case"
        )
    return Classification(name, f"{where}: {why}", rotation, aut_c, meeting_on, robots_on,
                          in_U_of(c, aut_c))


_LAST: tuple[Configuration | None, Classification | None] = (None, None)


def classification(c: Configuration, aut_m_all: Sequence[Automorphism] | None = None
                   ) -> Classification:
    """:func:`classify_configuration`, remembered for the last configuration object asked:
    check asks for the class and the precondition (:mod:`gather_verify.paper`) of one."""
    global _LAST
    last, known = _LAST
    if last is c and known is not None:
        return known
    got = classify_configuration(c, aut_m_all=aut_m_all)
    _LAST = (c, got)
    return got


def never_in_u(aut_m: Sequence[Automorphism], meeting: Iterable[Node]) -> bool:
    """Whether no configuration over these meeting nodes is in U: U needs a symmetry of C
    (an element of Aut(M)) whose axis or centre holds no meeting node (:func:`in_U_of`),
    and here every element of Aut(M) but the identity fixes a meeting node (its axis or
    centre holds one)."""
    meeting = list(meeting)
    return all(any(a.fixes(m) for m in meeting) for a in aut_m[1:])


def classify(robots: Iterable[Node], meeting_nodes: Iterable[Node]) -> Classification:
    """Classify an initial configuration (robots on distinct nodes).

    >>> classify([(0, 0), (3, 1), (1, 4)], [(2, 2)]).name
    'I13'
    """
    return classify_configuration(Configuration(robots, meeting_nodes, initial=True))


def describe_views(c: Configuration, region: strings.AlphaRegion = "mer") -> dict[str, object]:
    """Key corner, key string and leading corner(s) of a configuration, for reports."""
    keys = strings.key_scans(c)
    leads = strings.leading_scans(c, region)
    return {
        "key_corner": [list(v) for v in sorted({s.corner for s in keys})],
        "key_string": keys[0].text,
        "leading_corner": [list(v) for v in sorted({s.corner for s in leads})],
        "alpha_string": leads[0].text,
    }
