"""Two robots with lights in the plane: the rules of rendezvous, with no engine
(SEMANTICS.md §13).

Positions in the plane are continuous, but an algorithm that reads only colours, and
whether the robots share a point or are near, cannot use distance: the robots' relative
position (``far``, ``near``, ``same``), each robot's colour and its pending move are an
exact finite abstraction (the public SPIN model of Défago, Heriban, Tixeuil and Wada,
Robotics and Autonomous Systems 163, 2023, is the reference). This module holds that
abstraction and nothing else: the positions, the pending moves, the phases of a cycle,
what a Look decides (:func:`decide`), what an End-Move does to the position and to the
other robot's pending move (:func:`end_move`), the initial states, the goal, and the
published algorithms as tables (:data:`ALGORITHMS`). Schedulers and engines build on it.

>>> alg = get_algorithm("vig-2cols")
>>> alg.answer(WHITE, WHITE, NEAR)  # both white: to the midpoint, turn black
(1, 0)
>>> MOVES[alg.answer(WHITE, BLACK, NEAR)[0]]
'to-other'
>>> POSITIONS[end_move(NEAR, TO_HALF, TO_HALF)[0]], MOVES[end_move(NEAR, TO_HALF, TO_HALF)[1]]
('near', 'to-other')
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from itertools import product
from typing import Any

from gather_verify.errors import InvalidInput

FAR, NEAR, SAME = 0, 1, 2
POSITIONS = ("far", "near", "same")
"""The robots' relative position: ``far`` (a move towards the other may be stopped before
it arrives: non-rigid moves only), ``near`` (a move arrives where it was aimed), ``same``
(one point)."""

STAY, TO_HALF, TO_OTHER, MISS = 0, 1, 2, 3
MOVES = ("stay", "to-half", "to-other", "miss")
"""A pending move: none, to the midpoint of the two positions seen, to the position the
other was seen at, or ``miss``: a move whose target the other robot has left, so it cannot
end at the other's point. An algorithm answers one of the first three; ``miss`` is made by
the rules (:func:`decide`, :func:`end_move`)."""

LOOK, BEGIN_COMPUTE, END_COMPUTE, BEGIN_MOVE, END_MOVE = range(5)
PHASES = ("look", "begin-compute", "end-compute", "begin-move", "end-move")
"""The five steps of a cycle (§13). A robot's phase is the next step it takes: ``look``
is idle. Between Begin-Compute and End-Compute it is *computing* (a Look of the other
robot then reads its light as the read model says); between Begin-Move and End-Move with
a pending move other than ``stay`` it is *moving*."""

BLACK, WHITE, RED, YELLOW, GREEN = range(5)
COLOUR_NAMES = ("black", "white", "red", "yellow", "green")
"""Colour numbers as the SPIN model names them (further colours are numbers)."""

LIGHTS = ("full", "external", "internal")
"""Full lights show both colours; external lights hide the robot's own colour from it;
internal lights hide the other's."""

MOVEMENTS = ("rigid", "non-rigid")
INITIAL_COLOURS = ("all", "same")


def colour_name(c: int) -> str:
    """A colour as the traces write it (the SPIN model's names, then numbers)."""
    return COLOUR_NAMES[c] if c < len(COLOUR_NAMES) else str(c)


def place(position: int) -> tuple[bool, bool]:
    """What a robot sees of the position: (the robots share a point, they are near).
    ``same`` is also near."""
    return position == SAME, position != FAR


def decide(algorithm: RendezvousAlgorithm, own: int, seen: int, position: int,
           other_moving: bool) -> tuple[int, int]:
    """Robot's pending move and new colour after a Look that read ``seen`` for the other's
    light (§13's Cycle): the algorithm's answer, then two rules of the plane. A robot at
    ``same`` whose partner is not moving stays (it is where it would go); one that decides
    to move towards the other (``to-half`` or ``to-other``) while the other is moving gets
    ``miss`` (its target is leaving)."""
    move, colour = algorithm.answer(own, seen, position)
    if position == SAME and not other_moving:
        return STAY, colour
    if other_moving and move in (TO_HALF, TO_OTHER):
        return MISS, colour
    return move, colour


def end_move(position: int, mover: int, other: int) -> tuple[int, int]:
    """The End-Move of a robot whose pending move is ``mover`` (not ``stay``): the new
    position and the other robot's new pending move (§13).

    - from ``far`` it ends ``near``, and the other's pending move (if not ``stay``) becomes
      ``miss``;
    - ``to-other`` ends ``same``; the other's becomes ``miss`` unless it was ``stay`` or
      they were already ``same``;
    - ``to-half`` keeps the position (``near`` stays near, halved); against ``to-half`` it
      turns the other's into ``to-other`` (its midpoint is where this robot now stands);
      against ``stay`` nothing changes; against anything else the other's becomes ``miss``;
    - ``miss`` ends ``near``, and the other's pending move (if not ``stay``) becomes ``miss``.

    >>> [(POSITIONS[p], MOVES[o]) for p, o in (end_move(FAR, TO_OTHER, TO_HALF),
    ...                                       end_move(NEAR, TO_OTHER, STAY),
    ...                                       end_move(SAME, MISS, STAY))]
    [('near', 'miss'), ('same', 'stay'), ('near', 'stay')]
    """
    if mover == STAY:
        raise ValueError("end_move of a robot that is not moving")
    keep = other == STAY
    if position == FAR:
        return NEAR, other if keep else MISS
    if mover == MISS:
        return NEAR, other if keep else MISS
    if mover == TO_OTHER:
        return SAME, other if keep or position == SAME else MISS
    if other == TO_HALF:
        return position, TO_OTHER
    return position, other if keep else MISS


def initial_positions(movement: str) -> tuple[int, ...]:
    """Where the robots may start: ``near`` or ``same`` under rigid moves; also ``far``
    under non-rigid moves (a move may be stopped before its target)."""
    if movement not in MOVEMENTS:
        raise InvalidInput(f"unknown movement {movement!r}: use rigid or non-rigid")
    return (NEAR, SAME) if movement == "rigid" else (FAR, NEAR, SAME)


def initial_colour_pairs(colours: int, initial: str) -> tuple[tuple[int, int], ...]:
    """The robots' initial colours: every pair (``all``) or one colour for both (``same``)."""
    if initial not in INITIAL_COLOURS:
        raise InvalidInput(f"unknown initial colours {initial!r}: use all or same")
    if initial == "same":
        return tuple((c, c) for c in range(colours))
    return tuple((a, b) for a in range(colours) for b in range(colours))


def gathered(position: int, pending: Sequence[int]) -> bool:
    """The goal of ``rendezvous``: one point, nothing pending. Once there, the robots stay
    (a Look at ``same`` with the other not moving answers ``stay``)."""
    return position == SAME and all(p == STAY for p in pending)


ANY = None
"""In a rule: matches every value of that input."""
Rule = tuple[tuple[int | None, int | None, int | None], tuple[int, int]]
"""``((own colour, other's colour, position), (move, new colour))``; ``ANY`` in a key
matches every value. An algorithm's rules are tried in order; the first match answers."""


@dataclass(frozen=True)
class RendezvousAlgorithm:
    """An algorithm for two robots with lights: a table from what a robot sees (its own
    colour, the other's, the relative position, as far as its lights show them) to a move
    and a new colour (§13's Algorithm). ``rules`` in order, first match; :meth:`answer`
    hides what the light kind hides before matching, and construction refuses a table that
    reads a hidden input or leaves a view without an answer."""

    name: str
    colours: int
    rules: tuple[Rule, ...]
    lights: str = "full"
    cite: str = ""
    spin: str = ""
    """The SPIN model's name for it (``ALGO_VIG_2COLS``), or empty."""
    aliases: tuple[str, ...] = ()
    note: str = ""
    table: Mapping[tuple[int, int, int], tuple[int, int]] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.lights not in LIGHTS:
            raise InvalidInput(f"{self.name}: unknown lights {self.lights!r}: use "
                               f"{', '.join(LIGHTS)}")
        table = {}
        for own, other, position in product(range(self.colours), range(self.colours),
                                            range(len(POSITIONS))):
            table[own, other, position] = self._match(own, other, position)
        object.__setattr__(self, "table", table)

    def _match(self, own: int, other: int, position: int) -> tuple[int, int]:
        hide_own, hide_other = self.lights == "external", self.lights == "internal"
        for (r_own, r_other, r_pos), (move, colour) in self.rules:
            if (r_own is not ANY and hide_own) or (r_other is not ANY and hide_other):
                raise InvalidInput(f"{self.name}: a rule reads a colour its {self.lights} "
                                   f"lights hide")
            if move not in (STAY, TO_HALF, TO_OTHER) or not 0 <= colour < self.colours:
                raise InvalidInput(f"{self.name}: answer {(move, colour)} is not a move "
                                   f"(stay, to-half, to-other) and one of its "
                                   f"{self.colours} colours")
            if r_own in (ANY, own) and r_other in (ANY, other) and r_pos in (ANY, position):
                return move, colour
        raise InvalidInput(f"{self.name}: no rule answers own colour {own}, other's "
                           f"{other}, {POSITIONS[position]}")

    def answer(self, own: int, other: int, position: int) -> tuple[int, int]:
        """(move, new colour) for a robot of colour ``own`` that read ``other`` for the
        other robot's light, at ``position``."""
        return self.table[own, other, position]

    def rows(self) -> Iterator[tuple[int | None, int | None, int, tuple[int, int]]]:
        """The table as a robot sees it: one row per distinct view (hidden inputs None)."""
        seen = set()
        for (own, other, position), answer in self.table.items():
            key = (None if self.lights == "external" else own,
                   None if self.lights == "internal" else other, position)
            if key not in seen:
                seen.add(key)
                yield (*key, answer)


def _colour_blind(name: str, colours: int, by_other: Mapping[int, tuple[int, int]],
                  **kw: Any) -> RendezvousAlgorithm:
    """An external-light algorithm: the answer depends on the other's colour only."""
    rules = tuple(((ANY, c, ANY), answer) for c, answer in by_other.items())
    return RendezvousAlgorithm(name, colours, rules, lights="external", **kw)


def _full(name: str, colours: int, by_pair: Mapping[tuple[int, int | None], tuple[int, int]],
          first: tuple[Rule, ...] = (), **kw: Any) -> RendezvousAlgorithm:
    """A full-light algorithm: the answer depends on both colours (after the rules in
    ``first``, which may read the position)."""
    rules = first + tuple(((own, other, ANY), answer) for (own, other), answer in by_pair.items())
    return RendezvousAlgorithm(name, colours, rules, **kw)


B, W, R, Y, G = BLACK, WHITE, RED, YELLOW, GREEN
SPIN_PAPER = ("Défago, Heriban, Tixeuil, Wada: Using model checking to formally verify "
              "rendezvous algorithms for robots with lights in Euclidean space, Robotics and "
              "Autonomous Systems 163 (2023) 104378; the table of its public SPIN model")
VIGLIETTA = ("Viglietta: Rendezvous of two robots with visible bits, ALGOSENSORS 2013, "
             "LNCS 8243 (arXiv:1211.6039)")
OWD = ("Okumura, Wada, Défago: Optimal rendezvous L-algorithms for asynchronous mobile "
       "robots with external-lights, OPODIS 2018, LIPIcs 125 (arXiv:1804.01368)")


def _regular(name: str, colours: int, rows: Mapping[int, Mapping[int, tuple[int, int]]]
             ) -> RendezvousAlgorithm:
    """One of the SPIN model's algorithms for regular reads (``REGULAR4/5/6``): per own
    colour, the answers to some colours of the other; to any other colour it stays and
    keeps its colour."""
    rules: list[Rule] = []
    for own, answers in rows.items():
        rules += [((own, other, ANY), answer) for other, answer in answers.items()]
        rules.append(((own, ANY, ANY), (STAY, own)))
    return RendezvousAlgorithm(name, colours, tuple(rules), cite=SPIN_PAPER,
                               spin="ALGO_" + name.upper(),
                               note="three colours A, B, C in a cycle, and primed colours "
                                    "that hand on to the next one")


def _regular_algorithms() -> tuple[RendezvousAlgorithm, ...]:
    """REGULAR4 (colours A A' B C), REGULAR5 (A A' B B' C), REGULAR6 (A A' B B' C C'), as
    the SPIN model numbers their colours."""
    a, a1, b, c = range(4)
    four = {a1: {x: (STAY, b) for x in range(4)},
            a: {a: (TO_HALF, a1), b: (TO_OTHER, a)}, b: {b: (STAY, c), c: (TO_OTHER, b)},
            c: {c: (STAY, a), a: (TO_OTHER, c)}}
    a, a1, b, b1, c = range(5)
    five = {a1: {x: (STAY, b) for x in range(5)}, b1: {x: (STAY, c) for x in range(5)},
            a: {a: (TO_HALF, a1), b: (TO_OTHER, a)}, b: {b: (STAY, b1), c: (TO_OTHER, b)},
            c: {c: (STAY, a), a: (TO_OTHER, c)}}
    a, a1, b, b1, c, c1 = range(6)
    six = {a1: {x: (STAY, b) for x in range(6)}, b1: {x: (STAY, c) for x in range(6)},
           c1: {x: (STAY, a) for x in range(6)},
           a: {a: (TO_HALF, a1), b: (TO_OTHER, a)}, b: {b: (STAY, b1), c: (TO_OTHER, b)},
           c: {c: (STAY, c1), a: (TO_OTHER, c)}}
    return _regular("regular4", 4, four), _regular("regular5", 5, five), \
        _regular("regular6", 6, six)


ALGORITHMS: dict[str, RendezvousAlgorithm] = {a.name: a for a in (
    RendezvousAlgorithm("no-move", 1, (((ANY, ANY, ANY), (STAY, B)),), lights="external",
                        spin="ALGO_NO_MOVE", aliases=("stay",), cite=SPIN_PAPER,
                        note="never moves: fails wherever the robots start apart"),
    RendezvousAlgorithm("to-half", 1, (((ANY, ANY, ANY), (TO_HALF, B)),), lights="external",
                        spin="ALGO_TO_HALF", aliases=("midpoint",), cite=SPIN_PAPER,
                        note="the trivial move to the midpoint: solves FSYNC only"),
    RendezvousAlgorithm("to-other", 1, (((ANY, ANY, ANY), (TO_OTHER, B)),), lights="external",
                        spin="ALGO_TO_OTHER", aliases=("go-to-other",), cite=SPIN_PAPER,
                        note="the trivial move to the other: fails FSYNC (the robots swap)"),
    _full("vig-2cols", 2, {(B, B): (STAY, W), (B, W): (STAY, B), (W, B): (TO_OTHER, W),
                           (W, W): (TO_HALF, B)},
          spin="ALGO_VIG_2COLS", aliases=("viglietta-2",), cite=VIGLIETTA,
          note="2 full-light colours: rendezvous in SSYNC, non-rigid"),
    _full("vig-3cols", 3, {(B, B): (TO_HALF, W), (B, W): (TO_OTHER, B), (B, R): (STAY, B),
                           (W, B): (STAY, W), (W, W): (STAY, R), (W, R): (TO_OTHER, W),
                           (R, B): (TO_OTHER, R), (R, W): (STAY, R), (R, R): (STAY, B)},
          spin="ALGO_VIG_3COLS", aliases=("viglietta-3",), cite=VIGLIETTA,
          note="3 full-light colours: rendezvous in ASYNC, non-rigid"),
    _full("optimal", 2, {(B, B): (STAY, W), (B, W): (STAY, B), (W, B): (TO_OTHER, W),
                         (W, W): (TO_HALF, B)},
          first=(((W, ANY, SAME), (STAY, W)),),
          spin="ALGO_OPTIMAL", aliases=("heriban-2",),
          cite="Heriban, Défago, Tixeuil: Optimally gathering two robots, ICDCN 2018 "
               "(arXiv:1708.06183)",
          note="vig-2cols, but a white robot at the other's point stays: 2 colours in "
               "ASYNC for robots that tell zero from non-zero distance"),
    _colour_blind("flo-algo3ext", 3, {B: (TO_HALF, W), W: (STAY, R), R: (TO_OTHER, B)},
                  spin="ALGO_FLO_ALGO3EXT", aliases=("flocchini-3-external",),
                  cite="Flocchini, Santoro, Viglietta, Yamashita: Rendezvous with constant "
                       "memory, Theoretical Computer Science 621 (2016) (arXiv:1306.1956)",
                  note="3 external-light colours (the finite-communication robots)"),
    _colour_blind("flo-algo3ext-prime", 3, {B: (TO_HALF, W), W: (TO_OTHER, R), R: (STAY, B)},
                  spin="ALGO_FLO_ALGO3EXT_PRIME", cite=SPIN_PAPER,
                  note="flo-algo3ext with the move to the other one colour earlier"),
    _colour_blind("3ext-nonqss", 3, {B: (TO_HALF, W), W: (STAY, R), R: (TO_OTHER, W)},
                  spin="ALGO_3EXT_NONQSS", cite=SPIN_PAPER,
                  note="3 external colours; after the move to the other it turns white, "
                       "not black"),
    _colour_blind("wada-4ext", 4, {B: (TO_HALF, W), W: (STAY, R), R: (TO_OTHER, Y),
                                   Y: (STAY, B)},
                  spin="ALGO_WADA_4EXT", aliases=("okumura-4-external",), cite=OWD,
                  note="4 external-light colours"),
    _colour_blind("wada-5ext", 5, {B: (TO_HALF, W), W: (STAY, R), R: (TO_OTHER, Y),
                                   Y: (STAY, G), G: (STAY, B)},
                  spin="ALGO_WADA_5EXT", aliases=("okumura-5-external",), cite=OWD,
                  note="5 external-light colours"),
    _full("tixeuil-extra", 4, {(B, B): (STAY, Y), (B, R): (STAY, Y), (B, W): (STAY, B),
                               (B, Y): (STAY, B), (W, B): (TO_OTHER, W),
                               (W, W): (TO_HALF, R), (W, R): (TO_HALF, R),
                               (W, Y): (TO_OTHER, W), (R, ANY): (STAY, B),
                               (Y, ANY): (TO_OTHER, W)},
          first=(((W, ANY, SAME), (STAY, W)),),
          spin="ALGO_TIXEUIL_EXTRA", cite=SPIN_PAPER,
          note="optimal with two more colours (red: white's to-half under way, yellow: "
               "black turning white)"),
    *_regular_algorithms(),
)}
"""The published algorithms, by the SPIN model's name in lower case with hyphens
(``ALGO_VIG_2COLS`` is ``vig-2cols``); :data:`ALIASES` has our other names."""

ALIASES = {alias: a.name for a in ALGORITHMS.values() for alias in a.aliases}


def get_algorithm(name: str) -> RendezvousAlgorithm:
    """A built-in algorithm by name or alias (one line naming the known ones if unknown)."""
    key = ALIASES.get(name, name)
    if key not in ALGORITHMS:
        raise InvalidInput(f"unknown rendezvous algorithm {name!r}: use one of "
                           f"{', '.join(ALGORITHMS)}")
    return ALGORITHMS[key]
