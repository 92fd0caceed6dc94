"""Views read as gap rules: one algorithm for every ring size (docs/howto/rings.md).

A view's key here is not the view itself (which names the ring's size) but what a gap rule
(:mod:`gather_verify.algorithms.gap_rules`) can read of it: each gap below the cap ``T``
exactly, the gaps of ``T`` or more only by how they compare with each other, and the marks
the detection model shows. The same key occurs on rings of every size, so one table of keys
is one algorithm for all of them, and it is written as gap rules, one per key and reading
direction (:func:`rules_of`).

The key is the least of the two readings (the two directions of the robot's frames); a key
that reads the same both ways has two options (stay, or step, the adversary picking the
direction), the others three (stay, forward, back, in the key's reading). A table of these
keys is a coarser function of the view than a table of views: an ``exists`` found here is a
witness like any other (the checker verifies it at every size); no table found here proves
nothing about algorithms that are no gap rules.

>>> abstract((1, 4, 5), (0, 0, 0), 3)
((1, 3, 3), (0, 1, 2), (0, 0, 0))
>>> abstract((1, 5, 5), (0, 0, 0), 3) == abstract((1, 9, 9), (0, 0, 0), 3)
True
>>> rule_of(abstract((1, 4, 5), (0, 0, 0), 3), "forward", marks=False)
Rule('1 3+ 3+', 'forward', where='b<c')
"""

from __future__ import annotations

import json
from collections import Counter

from gather_verify.algorithms.gap_rules import LETTERS, MIRROR, Rule, gaps_of, occupied
from gather_verify.errors import InvalidInput
from gather_verify.model.view import MultiplicityHidden
from gather_verify.synthesis.views import Instance, Seen, Views
from gather_verify.worlds.view import WorldView

Abstract = tuple[tuple[int, ...], tuple[int, ...], tuple[int, ...]]
"""A reading as a gap rule sees it: the gaps capped at T, the ranks of the gaps of T or more
among themselves (0 for the others), the marks (1 tower, 0 one robot, -1 not shown)."""


def abstract(gaps: tuple[int, ...], marks: tuple[int, ...], cap: int) -> Abstract:
    """What a gap rule with cap ``cap`` reads of the reading (``gaps``, ``marks``)."""
    large = sorted({g for g in gaps if g >= cap})
    return (tuple(min(g, cap) for g in gaps),
            tuple(large.index(g) + 1 if g >= cap else 0 for g in gaps), tuple(marks))


def mirror(a: Abstract) -> Abstract:
    """The same view read the other way round: the gaps reversed, the robot's own mark first
    and the others reversed."""
    caps, ranks, marks = a
    return caps[::-1], ranks[::-1], marks[:1] + marks[1:][::-1]


def rule_of(a: Abstract, then: str, marks: bool = True) -> Rule:
    """The gap rule that matches exactly the readings with the abstract form ``a``."""
    caps, ranks, shown = a
    tokens = [f"{c}+" if r else str(c) for c, r in zip(caps, ranks, strict=True)]
    large = sorted((r, j) for j, r in enumerate(ranks) if r)
    where = [f"{LETTERS[j]}{'<' if r < r2 else '='}{LETTERS[j2]}"
             for (r, j), (r2, j2) in zip(large, large[1:], strict=False)]
    text = "".join("*" if m < 0 else "T" if m else "." for m in shown) if marks else ""
    return Rule(" ".join(tokens), then, where=", ".join(where), marks=text)


class GapViews(Views):
    """The views of one ring size, keyed by what gap rules with cap ``cap`` read (share one
    table between sizes with :meth:`share`)."""

    def __init__(self, inst: Instance, cap: int):
        w = inst.world
        if w.kind != "ring":
            raise InvalidInput(f"gap rules are ring algorithms: {w.name} is no ring")
        if inst.visibility is not None or inst.lights.colours > 1 or inst.meeting:
            raise InvalidInput("gap rules read the gaps of the whole ring: no --visibility, "
                               "no --lights, no meeting nodes")
        super().__init__(inst)
        self.cap = cap
        self.abstracts: list[Abstract] = []

    def _compute(self, seen: Seen, node: int, colour: int
                 ) -> tuple[int, tuple[frozenset[tuple[int, int]], ...]]:
        inst, world = self.inst, self.world
        counts = Counter(v for v, _ in seen)
        readings = []
        for frame in world.frames(node, None, inst.frames):
            view = WorldView(world, counts, inst.meeting, node, frame, inst.detection)
            readings.append((frame, abstract(gaps_of(view), _marks(view), self.cap)))
        key = min(a for _, a in readings)
        text = json.dumps(["gaps", self.cap, *key], separators=(",", ":"))
        k = self.index.get(text)
        if k is None:
            k = len(self.texts)
            self.texts.append(text)
            self.index[text] = k
            answers = ["stay", "forward"] + ([] if mirror(key) == key else ["back"])
            self.options.append([(a, None) for a in answers])
            self._labels.append([[a] for a in answers])
            self.still.append([0])  # "stay"
            self.abstracts.append(key)
            self.first.append((self.part, seen, node, colour))
        acts = []
        for answer, _ in self.options[k]:
            dests = set()
            for frame, a in readings:
                said = str(answer) if a == key else MIRROR[str(answer)]
                label = {"stay": 0, "forward": 1, "back": world.size - 1}[said]
                dests.add(frame.inverse[label])
            acts.append(frozenset((d, colour) for d in dests))
        return k, tuple(acts)

    def share(self, other: Views, part: int) -> None:
        super().share(other, part)
        if isinstance(other, GapViews):
            self.abstracts = other.abstracts

    def key_abstract(self, k: int) -> Abstract:
        """The abstract reading of key ``k`` (its least reading)."""
        _, _, caps, ranks, marks = json.loads(self.texts[k])
        return tuple(caps), tuple(ranks), tuple(marks)


def _marks(view: WorldView) -> tuple[int, ...]:
    """Per occupied node from the robot's own, in the frame's direction: 1 a tower, 0 one
    robot, -1 where the detection model does not show it."""
    out = []
    for label in occupied(view):
        try:
            out.append(int(view.multiplicity(label)))
        except MultiplicityHidden:
            out.append(-1)
    return tuple(out)


def rules_of(views: GapViews, table: dict[int, int]) -> list[Rule]:
    """The table as gap rules: one per key whose answer moves (a rule reads the view both
    ways round, so the key's reading says it all). Marks are written only where some key
    shows a tower (otherwise the rules read no multiplicity at all). Staying is the rules'
    default, so the keys that stay need no rule."""
    towers = any(1 in views.key_abstract(k)[2] for k in table)
    out = []
    for k in sorted(table, key=lambda k: views.key_abstract(k)):
        answer = views.options[k][table[k]][0]
        if answer == "stay":
            continue
        out.append(rule_of(views.key_abstract(k), str(answer), marks=towers))
    return out


def exact_rules(views: Views, table: dict[int, int]) -> list[Rule] | None:
    """An exact table of a ring (views keyed whole, :mod:`.viewkey`) as gap rules with exact
    gaps: the same algorithm at that size, written as a person reads it; None where gap rules
    cannot say it (lights, limited visibility, meeting nodes, another world)."""
    inst = views.inst
    if inst.world.kind != "ring" or inst.visibility is not None or inst.lights.colours > 1 \
            or inst.meeting:
        return None
    n, strong = inst.world.size, inst.detection.endswith("strong")
    towers = False
    readings: list[tuple[Abstract, str]] = []
    for k in sorted(table):
        label, _ = views.options[k][table[k]]
        me, _own, nodes = json.loads(views.texts[k])
        if me != 0:  # pragma: no cover - a ring's key reads the robot as node 0
            return None
        where = sorted(lb for lb, (_m, occ, _c, _l) in nodes if occ and lb != 0)
        shown = {lb: (-1 if c < 0 else int(c > 1) if strong else c)
                 for lb, (_m, occ, c, _l) in nodes if occ}
        gaps = tuple(b - a for a, b in zip([0, *where], [*where, n], strict=True))
        marks = tuple(shown[lb] for lb in [0, *where])
        towers = towers or 1 in marks
        answer = "stay" if label == 0 else "forward" if label == 1 else "back"
        readings.append(((gaps, (0,) * len(gaps), marks), answer))
    return [rule_of(a, answer, marks=towers) for a, answer in readings if answer != "stay"]


TEMPLATE = '''"""Gap rules synthesised by gather-verify synthesize (docs/howto/rings.md).

{summary}

Read a rule as: the gaps from the robot to the next occupied nodes, the gap ahead first
(a, b, c, ...); "3+" is a gap of 3 or more, "where b<c" compares two gaps; forward is a step
towards the gap a, back towards the last one. A rule also matches the view read from the
other end, and then forward and back swap. The first rule that matches answers; any other
view stays. A view that reads the same both ways lets the adversary choose the direction.
"""

from gather_verify.algorithms.gap_rules import GapRules, Rule

RULES = [
{rules}]


class {name}(GapRules):
    name = "synthesized-gap-rules"
    rules = RULES
'''


def write_rules(path: str, rules: list[Rule], summary: str, name: str = "Synthesized") -> str:
    """Write gap rules as an algorithm file; returns the ``--algorithm`` spec that loads it."""
    from pathlib import Path
    from textwrap import fill

    text = TEMPLATE.format(summary=fill(summary, 88), name=name,
                           rules="".join(f"    {r!r},\n" for r in rules))
    Path(path).write_text(text, encoding="utf-8")
    return f"{path}:{name}"
