"""Canonical forms of snapshots under translations and D4.

Two snapshots (occupied nodes and meeting nodes, multiplicity left out) that
differ by a grid isometry have one canonical form: the least, over the 8
elements ``g`` of D4, of the image ``g(S)`` translated so its MER starts at the
origin. An algorithm that decides on the canonical form (the paper's does)
answers every one of a robot's 8 frames, and every robot of a configuration,
from one analysis.

:func:`canonical_form` also keeps *every* minimising ``(g, t)``, so the canonical
form of any view of a configuration (the configuration seen from one robot in
one frame) follows from the configuration's own form without a second search
(:meth:`gather_verify.view.View.canonical`).

>>> canonical([(2, 1), (5, 1)], [(3, 1)])  # rot90, then translated
((((0, 0), (0, 3)), ((0, 1),)), 1, (1, -2))
>>> f = canonical_form([(0, 0), (2, 0)], [(1, 0)])
>>> [g for g, _ in f.minimisers]  # the snapshot is symmetric: four elements reach the key
[1, 3, 6, 7]
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import NamedTuple

from gather_verify import geometry
from gather_verify.geometry import Node

Key = tuple[tuple[Node, ...], tuple[Node, ...]]
"""Sorted occupied nodes and sorted meeting nodes of the canonical image."""


class CanonicalForm(NamedTuple):
    """The canonical key and every ``(g, t)`` with ``v -> g(v) + t`` onto it, ``g`` ascending."""

    key: Key
    minimisers: tuple[tuple[int, Node], ...]


def canonical_form(robots: Iterable[Node], meeting_nodes: Iterable[Node],
                   group: Iterable[int] = geometry.ALL) -> CanonicalForm:
    """The canonical form of a snapshot and all the isometries that reach it, over the
    translations and the elements of ``group`` (a subgroup of D4, ascending). Repeated
    robot nodes are kept (a multiset gives a multiset key)."""
    robots, meeting_nodes = tuple(robots), tuple(meeting_nodes)
    best: Key | None = None
    reach: list[tuple[int, Node]] = []
    for g in group:
        a, b, c, d = geometry.MATRICES[g]
        rs = [(a * x + b * y, c * x + d * y) for x, y in robots]
        ms = [(a * x + b * y, c * x + d * y) for x, y in meeting_nodes]
        both = rs + ms
        x0 = min(v[0] for v in both)
        y0 = min(v[1] for v in both)
        key = (tuple(sorted((x - x0, y - y0) for x, y in rs)),
               tuple(sorted((x - x0, y - y0) for x, y in ms)))
        if best is None or key < best:
            best, reach = key, [(g, (-x0, -y0))]
        elif key == best:
            reach.append((g, (-x0, -y0)))
    assert best is not None
    return CanonicalForm(best, tuple(reach))


def canonical(robots: Iterable[Node], meeting_nodes: Iterable[Node]) -> tuple[Key, int, Node]:
    """The canonical key with the first ``(g, t)`` (in D4's order) that maps the snapshot
    onto it."""
    key, reach = canonical_form(robots, meeting_nodes)
    g, t = reach[0]
    return key, g, t
