"""Automorphisms of labelled configurations: reflections, rotations, orbits, partitivity.

Paper §2 ("Symmetry", "Partitive automorphism"), SEMANTICS.md §2. An
automorphism is ``v -> A v + t`` with ``A`` in D4 preserving the labels. A
finite labelled set admits no translation or glide, so every non-identity
automorphism is a reflection (with an axis) or a rotation (with a centre).
Centres and axes are kept in doubled coordinates so half-integers stay exact.

>>> m = {(0, 0): 1, (2, 0): 1}
>>> [a.kind for a in automorphisms(m)]
['identity', 'rotation', 'reflection', 'reflection']
>>> reflection = automorphisms(m)[2]
>>> reflection.axis, reflection.axis_through
(('vertical', 2), 'nodes')
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import lru_cache

from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node

Labelled = Mapping[Node, int]


@dataclass(frozen=True, order=True)
class Automorphism:
    """``v -> g(v) + t`` for the D4 element ``g`` (see :mod:`geometry`)."""

    g: int
    t: Node

    def __call__(self, v: Node) -> Node:
        return geometry.add(geometry.apply(self.g, v), self.t)

    def inverse(self) -> Automorphism:
        """``v -> g^-1(v - t)``, as ``g^-1(v) - g^-1(t)``.

        >>> a = Automorphism(1, (3, -2))
        >>> a.inverse()(a((5, 7)))
        (5, 7)
        """
        h = geometry.inverse(self.g)
        x, y = geometry.apply(h, self.t)
        return Automorphism(h, (-x, -y))

    # -- kind -----------------------------------------------------------------
    @property
    def kind(self) -> str:
        """``identity``, ``rotation`` or ``reflection``."""
        if self.g == geometry.IDENTITY:
            return "identity"
        return "rotation" if geometry.is_rotation(self.g) else "reflection"

    @property
    def order(self) -> int:
        """Order of the cyclic group it generates."""
        return {geometry.IDENTITY: 1, geometry.ROT90: 4, geometry.ROT270: 4}.get(self.g, 2)

    @property
    def angle(self) -> int | None:
        """Rotation angle in degrees (counter-clockwise), or None."""
        return {geometry.ROT90: 90, geometry.ROT180: 180, geometry.ROT270: 270}.get(self.g)

    # -- rotation centre --------------------------------------------------------
    @property
    def centre2(self) -> Node | None:
        """Doubled coordinates of the rotation centre ``c`` (solves ``c = A c + t``)."""
        tx, ty = self.t
        if self.g == geometry.ROT180:
            return (tx, ty)
        if self.g == geometry.ROT90:
            return (tx - ty, tx + ty)
        if self.g == geometry.ROT270:
            return (tx + ty, ty - tx)
        return None

    @property
    def centre_kind(self) -> str | None:
        """``node``, ``edge`` (edge midpoint) or ``square`` (centre of a unit square)."""
        c = self.centre2
        if c is None:
            return None
        odd = (c[0] % 2) + (c[1] % 2)
        return ("node", "edge", "square")[odd]

    # -- reflection axis ----------------------------------------------------------
    @property
    def axis(self) -> tuple[str, int] | None:
        """``(orientation, k)``: vertical ``2x = k``, horizontal ``2y = k``,
        diagonal ``x - y = k``, anti-diagonal ``x + y = k``."""
        tx, ty = self.t
        if self.g == geometry.FLIP_X:
            return ("vertical", tx)
        if self.g == geometry.FLIP_Y:
            return ("horizontal", ty)
        if self.g == geometry.FLIP_DIAG:
            return ("diagonal", tx)
        if self.g == geometry.FLIP_ANTI:
            return ("anti-diagonal", tx)
        return None

    @property
    def axis_through(self) -> str | None:
        """``nodes`` or ``edges``: what the reflection axis passes through."""
        axis = self.axis
        if axis is None:
            return None
        orientation, k = axis
        return "edges" if orientation in ("vertical", "horizontal") and k % 2 else "nodes"

    # -- fixed nodes and orbits -------------------------------------------------------
    def fixes(self, v: Node) -> bool:
        """True when ``v`` is a fixed node (on the axis, or the centre)."""
        return self(v) == v

    def orbit(self, v: Node) -> tuple[Node, ...]:
        """The orbit ``H(v)`` of ``v`` under the cyclic group ``H`` it generates."""
        out = [v]
        w = self(v)
        while w != v:
            out.append(w)
            w = self(w)
        return tuple(out)

    def is_partitive_on(self, nodes: Iterable[Node]) -> bool:
        """Paper §2: ``|H(u)| = k > 1`` for every ``u`` in ``nodes``."""
        k = self.order
        return k > 1 and all(len(self.orbit(u)) == k for u in nodes)

    @property
    def fixed_set(self) -> str:
        """Description of the nodes with an orbit smaller than ``k``: the paper's V'."""
        if self.kind == "reflection":
            return "axis" if self.axis_through == "nodes" else "none"
        if self.kind == "rotation":
            return "centre" if self.centre_kind == "node" else "none"
        return "all"

    def describe(self) -> str:
        """Human-readable summary, e.g. ``reflection, vertical axis 2x=3 through edges``."""
        if self.kind == "identity":
            return "identity"
        if self.kind == "rotation":
            c = self.centre2
            assert c is not None
            return f"rotation {self.angle} about ({_half(c[0])}, {_half(c[1])}) [{self.centre_kind}]"
        orientation, k = self.axis  # type: ignore[misc]
        equation = {
            "vertical": f"x = {_half(k)}",
            "horizontal": f"y = {_half(k)}",
            "diagonal": f"x - y = {k}",
            "anti-diagonal": f"x + y = {k}",
        }[orientation]
        return f"reflection, {orientation} axis {equation} through {self.axis_through}"

    def to_json(self) -> dict[str, object]:
        out: dict[str, object] = {"kind": self.kind, "matrix": geometry.NAMES[self.g],
                                  "t": list(self.t)}
        if self.kind == "rotation":
            out.update(angle=self.angle, centre2=list(self.centre2 or ()),
                       centre_kind=self.centre_kind)
        if self.kind == "reflection":
            orientation, k = self.axis  # type: ignore[misc]
            out.update(axis=orientation, axis_k=k, axis_through=self.axis_through)
        out["describe"] = self.describe()
        return out


def _half(doubled: int) -> str:
    return str(doubled // 2) if doubled % 2 == 0 else f"{doubled / 2:g}"


IDENTITY_AUT = Automorphism(geometry.IDENTITY, (0, 0))
_SWAPS_SIDES = frozenset({geometry.ROT90, geometry.ROT270, geometry.FLIP_DIAG, geometry.FLIP_ANTI})


def automorphisms(labelled: Labelled) -> list[Automorphism]:
    """All automorphisms of a finite labelled node set (identity first).

    ``labelled`` maps each node with a non-zero label to its label. The
    translation part is fixed by the lexicographically smallest node, which
    any translation preserves.

    >>> [a.describe() for a in automorphisms({(0, 0): 1, (1, 1): 1})]
    ['identity', 'rotation 180 about (0.5, 0.5) [square]', 'reflection, diagonal axis x - y = 0 through nodes', 'reflection, anti-diagonal axis x + y = 1 through nodes']
    """
    if not labelled:
        raise ValueError("automorphisms of an empty node set are not finite")
    lowest = min(labelled)
    x0, y0, x1, y1 = geometry.bounding_box(labelled)
    # a quarter turn or a diagonal flip swaps the sides of the bounding box
    square = x1 - x0 == y1 - y0
    out = []
    for g in geometry.ALL:
        if not square and g in _SWAPS_SIDES:
            continue
        image = {geometry.apply(g, v): label for v, label in labelled.items()}
        low = min(image)
        t = (lowest[0] - low[0], lowest[1] - low[1])
        if all(labelled.get((v[0] + t[0], v[1] + t[1])) == label for v, label in image.items()):
            out.append(Automorphism(g, t))
    return out


@lru_cache(maxsize=1 << 12)
def _meeting_automorphisms(meeting_nodes: frozenset[Node]) -> tuple[Automorphism, ...]:
    return tuple(automorphisms(dict.fromkeys(meeting_nodes, 1)))


def meeting_automorphisms(configuration: Configuration) -> list[Automorphism]:
    """``Aut(M)``: automorphisms of the meeting nodes alone (labels ``lambda``); remembered
    per ``M``, which a search or a sweep class keeps fixed."""
    return list(_meeting_automorphisms(configuration.meeting_nodes))


def configuration_automorphisms(
    configuration: Configuration, *, weak: bool = False
) -> list[Automorphism]:
    """``Aut(C, l)``; with ``weak=True`` multiplicities are not told apart (labels 3->2, 5->4).

    A label tells whether its node is a meeting node, so ``Aut(C) ⊆ Aut(M)``: the elements
    of ``Aut(M)`` (same order) that map every robot's node onto a node whose label is the
    same: one robot onto one robot, several onto several (the labels do not count them);
    with ``weak``, onto a robot's node. That is :func:`automorphisms` of the labels."""
    counts = configuration.counts
    if not configuration.meeting_nodes:
        labelled = configuration.labelled
        if weak:
            labelled = {v: configuration.weak_label(v) for v in labelled}
        return automorphisms(labelled)
    out = []
    for a in _meeting_automorphisms(configuration.meeting_nodes):
        (ma, mb, mc, md), (tx, ty) = geometry.MATRICES[a.g], a.t
        if weak:
            if all((ma * x + mb * y + tx, mc * x + md * y + ty) in counts for x, y in counts):
                out.append(a)
        elif all(min(counts.get((ma * x + mb * y + tx, mc * x + md * y + ty), 0), 2) == min(k, 2)
                 for (x, y), k in counts.items()):  # labels tell one robot from several, no more
            out.append(a)
    return out


def is_symmetric(labelled: Labelled) -> bool:
    return len(automorphisms(labelled)) > 1


def symmetry_defect(phi: Automorphism, c: Configuration) -> str | None:
    """Why ``c`` breaks the invariant of Theorem 1's adversary under ``phi`` (None when it
    holds): ``phi`` maps the meeting nodes and the robots (with their multiplicities) onto
    themselves, and the robots on each node ``phi`` fixes (``V'``) are a multiple of its
    order ``k``. The synthesis' certificates check it too, hence here."""
    if {phi(m) for m in c.meeting_nodes} != c.meeting_nodes:
        return "phi does not map the meeting nodes onto themselves"
    image = Counter(phi(r) for r in c.robots)
    if image != Counter(c.counts):
        moved = sorted(v for v in set(image) | set(c.counts) if image[v] != c.counts.get(v, 0))
        return ("phi does not map the robots onto themselves (counts differ at "
                f"{[list(v) for v in moved]})")
    k = phi.order
    for w, count in sorted(c.counts.items()):
        if phi(w) == w and count % k:
            return f"{count} robots on {list(w)} in V' (not a multiple of k = {k})"
    return None
