"""Gap rules: a ring algorithm written on the gaps between robots, the same at every ring
size (``--world ring:N``; docs/howto/rings.md).

A robot reads the ring from its own node in the direction of its frame: the *gaps*, the
hops from one occupied node to the next, starting with the gap ahead of it (``a``) and
ending with the gap behind it (the last letter). With k robots on distinct nodes there are
k gaps and they add up to the ring's size. Where the detection model shows it, each
occupied node carries a mark: ``.`` one robot, ``T`` a tower (the robot's own node first).

A rule is a pattern on those gaps and an answer:

- ``gaps``: one token per gap, ``2`` (exactly 2), ``3+`` (at least 3) or ``*`` (any);
- ``where``: relations between gaps by letter, ``a<c``, ``b=c``, ``a>=b`` (comma-separated);
- ``marks``: one character per occupied node, ``.``, ``T`` or ``*`` (empty: any);
- ``one_way``: match the reading only as it is (for robots that share a direction,
  ``--frames chirality``; by default a rule reads the view both ways round, below);
- ``then``: ``stay``, ``forward`` (a step towards the gap ``a``) or ``back`` (towards the
  last gap).

A rule reads the view both ways round: it matches the reading as it is (then it answers
``then``) or read from the other end (then forward and back swap). The first rule that
matches answers; a view no rule matches answers :attr:`GapRules.otherwise` (``stay``). The
frames do the rest, as for every algorithm (SEMANTICS.md §9): the robot is handed its view in
both directions and its move set is the union of the answers, so a view that one rule
matches both ways round (one that reads the same both ways, for one) gives the adversary the
choice of direction.

>>> r = Rule("1 3+ 3+", "forward", where="b<c")
>>> r.matches((1, 4, 5), ()), r.matches((1, 5, 4), ()), r.matches((2, 4, 5), ())
(True, False, False)
>>> str(r)
'1 3+ 3+  where b<c  -> forward'
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from gather_verify.errors import InvalidInput

ANSWERS = ("stay", "forward", "back")
MIRROR = {"stay": "stay", "forward": "back", "back": "forward"}
"""An answer read the other way round."""
LETTERS = "abcdefghijklmnopqrstuvwxyz"
RELATIONS = {"<": lambda x, y: x < y, "<=": lambda x, y: x <= y, "=": lambda x, y: x == y,
             ">=": lambda x, y: x >= y, ">": lambda x, y: x > y}
_RELATION = re.compile(r"^([a-z])(<=|>=|<|=|>)([a-z])$")


@dataclass(frozen=True)
class Token:
    """One gap of a pattern: exactly ``low`` (``exact``), at least ``low``, or any (low 0)."""

    low: int
    exact: bool

    def holds(self, gap: int) -> bool:
        return gap == self.low if self.exact else gap >= self.low

    def __str__(self) -> str:
        if self.exact:
            return str(self.low)
        return "*" if self.low <= 1 else f"{self.low}+"


@dataclass(frozen=True, init=False)
class Rule:
    """A pattern on the gaps (and marks) of a reading, and the answer where it holds."""

    tokens: tuple[Token, ...]
    relations: tuple[tuple[int, str, int], ...]
    marks: str
    then: str
    one_way: bool

    def __init__(self, gaps: str, then: str, *, where: str = "", marks: str = "",
                 one_way: bool = False):
        object.__setattr__(self, "tokens", tuple(_token(t) for t in gaps.split()))
        object.__setattr__(self, "relations", tuple(_relation(r, len(self.tokens))
                                                    for r in re.split(r"[,\s]+", where)
                                                    if r))
        if any(c not in ".T*" for c in marks) or marks and len(marks) != len(self.tokens):
            raise InvalidInput(f"gap rule marks {marks!r}: one of . T * per occupied node "
                               f"({len(self.tokens)})")
        if then not in ANSWERS:
            raise InvalidInput(f"gap rule answer {then!r}: use one of {', '.join(ANSWERS)}")
        object.__setattr__(self, "marks", marks)
        object.__setattr__(self, "then", then)
        object.__setattr__(self, "one_way", bool(one_way))

    def matches(self, gaps: Sequence[int], marks: Sequence[int] | Callable[[int], int]) -> bool:
        """Whether the reading (``gaps``, and ``marks``: per occupied node 1 for a tower, 0
        for one robot, or a function that reads node ``j``'s) fits the pattern. A mark is
        read only where the pattern names one."""
        if len(gaps) != len(self.tokens):
            return False
        if not all(t.holds(g) for t, g in zip(self.tokens, gaps, strict=True)):
            return False
        if not all(RELATIONS[op](gaps[x], gaps[y]) for x, op, y in self.relations):
            return False
        read = marks if callable(marks) else marks.__getitem__
        return all(c == "*" or read(j) == (c == "T") for j, c in enumerate(self.marks))

    def __repr__(self) -> str:
        gaps = " ".join(map(str, self.tokens))
        where = ", ".join(f"{LETTERS[x]}{op}{LETTERS[y]}" for x, op, y in self.relations)
        return (f"Rule({gaps!r}, {self.then!r}" + (f", where={where!r}" if where else "")
                + (f", marks={self.marks!r}" if self.marks else "")
                + (", one_way=True" if self.one_way else "") + ")")

    def __str__(self) -> str:
        where = ", ".join(f"{LETTERS[x]}{op}{LETTERS[y]}" for x, op, y in self.relations)
        return (" ".join(map(str, self.tokens)) + (f"  where {where}" if where else "")
                + (f"  marks {self.marks}" if self.marks else "")
                + ("  (this way only)" if self.one_way else "") + f"  -> {self.then}")


def _token(text: str) -> Token:
    if text == "*":
        return Token(0, False)
    try:
        if text.endswith("+"):
            return Token(int(text[:-1], 10), False)
        return Token(int(text, 10), True)
    except ValueError:
        raise InvalidInput(f"gap rule token {text!r}: write a gap as 2, 3+ or *") from None


def _relation(text: str, count: int) -> tuple[int, str, int]:
    m = _RELATION.match(text.strip())
    if not m or LETTERS.index(m[1]) >= count or LETTERS.index(m[3]) >= count:
        raise InvalidInput(f"gap rule relation {text!r}: write it as a<b, a=b, a>=b ... "
                           f"between the letters of its {count} gaps")
    return LETTERS.index(m[1]), m[2], LETTERS.index(m[3])


def occupied(view: Any) -> list[int]:
    """The occupied nodes of a ring view, from the robot's own (label 0) in the direction of
    the frame (labels ascending)."""
    me = view.me
    n = len(view.graph)
    return sorted(view.robots, key=lambda label: (label - me) % n)


def gaps_of(view: Any) -> tuple[int, ...]:
    """The gaps of a ring view in its frame's direction, the gap ahead first (:mod:`doc
    <gather_verify.algorithms.gap_rules>`). The view must show the whole ring."""
    if getattr(getattr(view, "world", None), "kind", "ring") != "ring":
        raise InvalidInput("gap rules read a ring's view (--world ring:N)")
    n = len(view.graph)
    if view.graph.number_of_edges() != n:
        raise InvalidInput("gap rules read the whole ring: drop --visibility")
    where = [(label - view.me) % n for label in occupied(view)]
    ahead = [p for p in where if p != 0] + [n]
    return tuple(b - a for a, b in zip([0, *ahead], ahead, strict=False))


def step(view: Any, answer: str) -> Any:
    """The node an answer names in the view's frame: the robot's own, or its neighbour ahead
    (forward) or behind (back)."""
    n = len(view.graph)
    if answer == "stay":
        return view.me
    return (view.me + (1 if answer == "forward" else -1)) % n


class GapRules:
    """A ring algorithm written as gap rules (subclass it, or build it with ``rules``)."""

    name = "gap-rules"
    plane = False  # it reads a finite world's view
    rules: Sequence[Rule] = ()
    otherwise = "stay"

    def __init__(self, rules: Sequence[Rule] | None = None, otherwise: str | None = None):
        if rules is not None:
            self.rules = tuple(rules)
        if otherwise is not None:
            self.otherwise = otherwise
        if self.otherwise not in ANSWERS:
            raise InvalidInput(f"gap rules: otherwise {self.otherwise!r} is not an answer")

    def answer(self, view: Any) -> str:
        """The answer of the first rule that matches the view, as it reads or the other way
        round (then mirrored); :attr:`otherwise` when none does."""
        gaps = gaps_of(view)
        nodes = occupied(view)
        back = gaps[::-1]
        for rule in self.rules:
            if rule.matches(gaps, lambda j: int(view.multiplicity(nodes[j]))):
                return rule.then
            if not rule.one_way and rule.matches(
                    back, lambda j: int(view.multiplicity(nodes[-j if j else 0]))):
                return MIRROR[rule.then]
        return self.otherwise

    def decide(self, view: Any) -> Any:
        return step(view, self.answer(view))

    def describe(self) -> list[str]:
        """The rules as a person reads them, one a line, then the default."""
        return [str(r) for r in self.rules] + [f"any other view  -> {self.otherwise}"]
