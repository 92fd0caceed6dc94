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
(:meth:`gather_verify.model.view.View.canonical`).

>>> canonical([(2, 1), (5, 1)], [(3, 1)])  # rot90, then translated
((((0, 0), (0, 3)), ((0, 1),)), 1, (1, -2))
>>> f = canonical_form([(0, 0), (2, 0)], [(1, 0)])
>>> [g for g, _ in f.minimisers]  # the snapshot is symmetric: four elements reach the key
[1, 3, 6, 7]
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import NamedTuple

from gather_verify.model import geometry
from gather_verify.model.geometry import Node

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
    xs = [v[0] for v in robots] + [v[0] for v in meeting_nodes]
    ys = [v[1] for v in robots] + [v[1] for v in meeting_nodes]
    lo, hi = (min(xs), min(ys)), (max(xs), max(ys))
    width = max(hi[0] - lo[0], hi[1] - lo[1]) + 1
    # Nodes as integers x * width + y (0 <= y < width after the shift): sorting and comparing
    # them is sorting and comparing the nodes, at a fraction of the cost of tuples.
    best: tuple[list[int], list[int]] | None = None
    reach: list[tuple[int, Node]] = []
    for g in group:
        a, b, c, d = geometry.MATRICES[g]
        # the image's MER starts at (ox, oy): each row of the matrix picks one coordinate
        ox = a * (lo[0] if a > 0 else hi[0]) + b * (lo[1] if b > 0 else hi[1])
        oy = c * (lo[0] if c > 0 else hi[0]) + d * (lo[1] if d > 0 else hi[1])
        rs = sorted((a * x + b * y - ox) * width + c * x + d * y - oy for x, y in robots)
        if best is not None and rs > best[0]:
            continue
        ms = sorted((a * x + b * y - ox) * width + c * x + d * y - oy for x, y in meeting_nodes)
        key = (rs, ms)
        if best is None or key < best:
            best, reach = key, [(g, (-ox, -oy))]
        elif key == best:
            reach.append((g, (-ox, -oy)))
    assert best is not None
    return CanonicalForm((tuple(divmod(v, width) for v in best[0]),
                          tuple(divmod(v, width) for v in best[1])), tuple(reach))


def moved_form(form: CanonicalForm, h: int, s: Node) -> CanonicalForm:
    """The canonical form (over all of D4) of the image of a snapshot under ``v -> h(v) + s``,
    from the snapshot's own ``form``, with no search: the image has the same key, and
    ``(g, t)`` reaches it from the snapshot exactly when ``(g h^-1, t - g h^-1 (s))`` reaches
    it from the image.

    >>> f = canonical_form([(0, 0), (2, 1)], [(1, 0)])
    >>> moved_form(f, 1, (5, -3)) == canonical_form([(5, -3), (4, -1)], [(5, -2)])
    True
    """
    back = geometry.inverse(h)
    reach = []
    for g, t in form.minimisers:
        k = geometry.compose(g, back)
        u = geometry.apply(k, s)
        reach.append((k, (t[0] - u[0], t[1] - u[1])))
    reach.sort()
    return CanonicalForm(form.key, tuple(reach))


def canonical(robots: Iterable[Node], meeting_nodes: Iterable[Node]) -> tuple[Key, int, Node]:
    """The canonical key with the first ``(g, t)`` (in D4's order) that maps the snapshot
    onto it."""
    key, reach = canonical_form(robots, meeting_nodes)
    g, t = reach[0]
    return key, g, t
