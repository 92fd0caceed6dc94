"""``paper``: the paper's ``Gathering()`` (Algorithms 1-5), oblivious and pluggable.

Paper §4. Every decision is derived from the current snapshot alone, as the
robot sees it under ``local-weak`` multiplicity detection: the occupied nodes,
the meeting nodes and whether the robot's own node is a multiplicity. Labels 3
and 5 of *other* nodes are invisible, so every string, key corner and
symmetry is read with weak labels (3 read as 2, 5 as 4); the snapshot
``view.configuration`` holds one robot per occupied node, where ``l`` and the
weak label agree.

How a snapshot is recognised (``analyse``; the first rule that applies wins;
``dist`` is the distance from ``L ∪ {c}``: ``d(v, phi(v))`` for the reflection
``phi`` of ``M`` with axis ``L``, the Manhattan distance to ``c`` for a
rotation, both in doubled coordinates; ``d1`` is the largest ``dist`` of a
meeting node, and a robot is *outside* when ``dist > d1``):

1. ``Aut(M)`` trivial (I11): every robot steps towards the last node of ``O``
   (robots on it stay), whatever the robots' positions;
2. ``M`` has a single reflection with meeting nodes on ``L`` (I12): towards
   the last node of ``O'``;
3. ``M`` has a rotation with a meeting node on ``c`` (I13): towards it;
4. otherwise (no meeting node on ``L ∪ {c}``), all robots on one meeting node:
   everybody stays (``n1 = 1``: neither Algorithm 3 nor 4 applies);
5. ``n1 = 2``, exactly one of the two positions is a meeting node ``q``, and
   ``q`` is a meeting node closest to the other position (Finalization,
   Algorithm 4; the paper's own argument that the guard's path meets no other
   meeting node needs it, and it survives every step of the guard along a
   shortest path; ``finalize=n1`` drops this last condition, reading the
   pseudo-code's "if n1 = 2" literally): the robots Algorithm 4 line 2 names step
   towards the other position, the others stay (``survivor``, below);
6. the snapshot is symmetric (``SymmetryBreaking()``, Algorithm 5): the robot
   on ``L`` (the axis of ``C``) with the maximum configuration view steps to
   any neighbour off ``L``, or the robot on ``c`` to any neighbour; no robot
   there: the snapshot is in U, ``Unhandled`` (``hidden=infer``: with two positions
   the robot off a multiplicity is the guard, below);
7. asymmetric, a *unique farthest* robot ``g`` that is outside: ``g`` is the
   guard. Not yet on a corner of MER: ``g`` steps towards its closest MER
   corner, by steps that do not bring it nearer ``L ∪ {c}`` (placement; when
   there is none, ``placement=reachable`` takes the closest corner it can approach
   so, ``placement=closest`` has no rule);
   on a corner (guard placed): the target ``m`` is the meeting node closest
   to ``g``, ties by the first in ``O''`` (the lambda scan of MER from
   ``g``'s corner, its lines parallel to the key corner's string direction); the non-guard robots not on ``m``
   closest to ``m`` step towards it along shortest paths (``MakeMultiplicity``); none
   left, every robot on ``g``'s node: everybody stays (``movement=proof``: towards
   ``m``, below);
8. asymmetric otherwise (guard selection): among the robots farthest from
   ``L ∪ {c}`` the unique one, or the one with the maximum configuration view,
   steps away from ``L ∪ {c}``; everybody else stays.

Where the paper leaves a choice open, every allowed step is returned as a set
and the robot answers the first one in ``STEPS`` order in its own frame, so
the union over the 8 frames is the whole set: the adversary chooses.

Options (``READINGS``; each is one ambiguous passage, ``docs/interpretations.md``
names it, and ``gather-verify check --readings all`` runs every combination):
``alpha=mer`` (default, the MER of ``R ∪ M`` as Figure "order1"
shows) or ``alpha=mer_f`` for the strings ``alpha`` behind ``O``/``O'``;
``metric=manhattan`` (default) or ``euclid``: the distance to ``c`` in "farthest from
``L ∪ {c}``" (the distance to ``L`` is the same in both); ``oscan=key`` (default: the
lines of ``O''`` parallel to the key corner's string direction) or ``guard`` (the
guard's corner's own string direction); ``finalize=closest`` (default, rule 5),
``target`` (rule 5, and when the other position is a MER corner, where Algorithm 3
defines the target, ``q`` must be that target: ties by ``O''``), ``n1`` (rule 5 without "closest") or
``literal`` (Algorithm 4 in every asymmetric snapshot with ``n1 = 2``: each robot on
neither a multiplicity nor a meeting node moves towards the other position, and
MakeMultiplicity runs only when ``n1 >= 3``);
``unclassified=break`` (default: a snapshot whose ``M`` is rotational while
``C`` has a single reflection ``L'`` is broken on ``L'``, as the paper's
I32 paragraph says) or ``unclassified=unhandled``; ``outside=distance``
(default: "outside MER_F" read as ``dist > d1``, as the paper's explanation
"there exists at least one robot position at a distance d2 > d1" says) or
``outside=mer_f`` (literally: strictly outside the rectangle MER_F; then
Algorithm 2's "exactly one robot outside MER_F" may pick a robot that is not
the farthest, and it steps away from ``L ∪ {c}`` until it is);
``placement=closest`` (default: Algorithm 2 line 5 "finally towards its closest
corner", only that corner, by steps that keep the guard's distance from ``L ∪ {c}``, as
Lemma 5 needs; no such step: no rule) or ``reachable`` (the closest of the MER corners
it can approach so: the same steps wherever ``closest`` has one, and always a step);
``survivor`` (Algorithm 4 line 2, "the robot that does not lie on a robot multiplicity
node and on a meeting node"): ``neither`` (default: on neither a multiplicity nor a
meeting node), ``not-both`` (not on a node that is both) or ``off-target`` (every robot
not on the target moves, as the prose "the guard moves; the robots on m stay" says),
each seen with the robot's own multiplicity bit only (``Plan.if_multiplicity``);
``hidden=unhandled`` (default: a weak snapshot in U, e.g. after SymmetryBreaking steps
onto an occupied node, has no rule) or ``infer`` (§4 after Algorithm 5: "the robot
that is farthest from L ∪ {c} and does not lie on a multiplicity is selected as the
guard"; the run started outside U and Lemma 7 says it never enters U, so the snapshot
hides a multiplicity; with two positions a robot off a multiplicity knows the other
holds it, is that guard and steps away from ``L ∪ {c}``; with more it cannot tell
where the multiplicity is: no rule);
``movement=algorithm`` (default: GuardMovement only as Algorithm 4 names its robot) or
``proof`` (the proof of Theorem 8: "If there is at most one robot position which is not
on m at time t', then the execution of GuardMovement() is started", the guard moving
towards m; applied only where the pseudo-code has no rule: every robot on the placed
guard's node off M, where Algorithm 3 has no non-guard left to move and Algorithm 4
needs ``n1 = 2``, and, under ``survivor=neither``, the robots on a multiplicity at the
position off the target in Finalization, to whom Algorithm 4 line 2 gives no move: they
step towards the target).

Every ``Unhandled`` message starts with a short label of the rule that has no answer,
up to the first colon (``I2 guard placement``, ``I41-looking snapshot``,
``Finalization``, ...): failures are grouped by it.

>>> from gather_verify.algorithms.moves import move_set
>>> from gather_verify.model.configuration import Configuration
>>> c = Configuration([(0, 0), (4, 1)], [(1, 0), (3, 3), (0, 2)])
>>> PaperAlgorithm().target(c)
(3, 3)
>>> sorted(move_set(PaperAlgorithm(), c, (4, 1)))
[(3, 1), (4, 2)]
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from functools import lru_cache

from gather_verify.algorithms.base import Unhandled, commutes_with_translations
from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.canonical import Key
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, STEPS, Node, manhattan
from gather_verify.model.symmetry import (
    Automorphism,
    configuration_automorphisms,
    meeting_automorphisms,
)
from gather_verify.model.view import View
from gather_verify.paper import strings

READINGS: dict[str, tuple[str, ...]] = {
    "alpha": ("mer", "mer_f"),
    "metric": ("manhattan", "euclid"),
    "oscan": ("key", "guard"),
    "finalize": ("closest", "target", "n1", "literal"),
    "outside": ("distance", "mer_f"),
    "unclassified": ("break", "unhandled"),
    "placement": ("closest", "reachable"),
    "survivor": ("neither", "not-both", "off-target"),
    "hidden": ("unhandled", "infer"),
    "movement": ("algorithm", "proof"),
}
"""Every option of ``paper``: one ambiguous passage of the paper each, its values, the default
(the most charitable reading, or the reading before the switch existed) first.
``docs/interpretations.md`` names the passages."""
DEFAULTS: dict[str, str] = {option: values[0] for option, values in READINGS.items()}
"""The default reading: every option at its first value."""

_HOME = "gather_verify.paper.algorithm"
"""This module's name (a copy under another name asks ``decide`` view by view)."""
CACHE_SIZE = 1 << 17
"""Plans remembered per algorithm instance, one per canonical form of a snapshot."""


@dataclass(frozen=True)
class Plan:
    """What every occupied node of a snapshot does.

    ``moves[v]`` is the set of allowed destinations of the robots on ``v``
    (``{v}`` = stay); ``if_multiplicity[v]``, when present, replaces it for
    robots that see their own node as a multiplicity (Algorithm 4 only).
    ``proof_moves[v]``, when present, replaces ``if_multiplicity[v]`` under
    ``movement=proof``: the robots on a multiplicity off the target, to whom
    Algorithm 4 line 2 gives no move, go towards the target as the proof of
    Theorem 8 has GuardMovement do (:meth:`PaperAlgorithm.allowed` reads the
    option only when such a robot is met).
    """

    phase: str
    target: Node | None
    moves: dict[Node, frozenset[Node]]
    if_multiplicity: dict[Node, frozenset[Node]] = field(default_factory=dict)
    guard: Node | None = None
    proof_moves: dict[Node, frozenset[Node]] = field(default_factory=dict)


class Reading(Mapping[str, str]):
    """One reading (a value per option of ``READINGS``) that records which options were read.

    ``analyse`` reads every option through this mapping, and only where a rule needs it
    (:meth:`PaperAlgorithm.allowed` reads ``movement`` so, when a robot decides), so
    ``consulted`` is every option a plan or a robot's move depended on: two readings equal
    on the options consulted over a run give the same plans and moves, hence the same run
    (:mod:`gather_verify.paper.readings`, the dynamic covering).

    >>> r = Reading({**DEFAULTS, "finalize": "n1"})
    >>> r["finalize"], sorted(r.consulted)
    ('n1', ['finalize'])
    """

    def __init__(self, values: Mapping[str, str], consulted: set[str] | None = None) -> None:
        self.values = dict(values)
        self.consulted: set[str] = set() if consulted is None else consulted

    def __getitem__(self, option: str) -> str:
        self.consulted.add(option)
        return self.values[option]

    def __iter__(self) -> Iterator[str]:
        return iter(self.values)

    def __len__(self) -> int:
        return len(self.values)


# -- small geometric helpers --------------------------------------------------------


def closer_steps(v: Node, target: Node) -> frozenset[Node]:
    """Neighbours of ``v`` on a shortest path to ``target`` (``{v}`` when there)."""
    (x, y), (tx, ty) = v, target
    if v == target:
        return frozenset({v})
    out = []  # one step along each axis on which target differs
    if tx != x:
        out.append((x + (1 if tx > x else -1), y))
    if ty != y:
        out.append((x, y + (1 if ty > y else -1)))
    return frozenset(out)


def distance_function(symmetry: Automorphism, metric: str = "manhattan"):
    """``dist`` from ``L ∪ {c}`` in doubled units (see the module docstring).

    For a reflection ``d(v, phi(v))`` is twice the distance to ``L`` in every metric
    (the Euclidean distance to a diagonal axis is it divided by ``2·sqrt 2``), so
    ``metric`` only changes the distance to a centre ``c``: ``euclid`` compares squared
    Euclidean distances (exact integers, the same order).

    >>> from gather_verify.model.symmetry import meeting_automorphisms
    >>> c = Configuration([(0, 0)], [(3, 0), (3, 1)])
    >>> rotation = meeting_automorphisms(c)[1]
    >>> [distance_function(rotation)(v) for v in [(0, 0), (2, 3)]]
    [7, 7]
    >>> [distance_function(rotation, "euclid")(v) for v in [(0, 0), (2, 3)]]
    [37, 29]
    """
    if symmetry.kind == "reflection":
        return lambda v: manhattan(v, symmetry(v))
    cx, cy = symmetry.centre2
    if metric == "euclid":
        return lambda v: (2 * v[0] - cx) ** 2 + (2 * v[1] - cy) ** 2
    return lambda v: abs(2 * v[0] - cx) + abs(2 * v[1] - cy)


def _stay_all(c: Configuration) -> dict[Node, frozenset[Node]]:
    return {v: frozenset({v}) for v in c.occupied}


def _everyone_to(c: Configuration, phase: str, target: Node) -> Plan:
    return Plan(phase, target, {v: closer_steps(v, target) for v in c.occupied})


# -- the analysis of one snapshot (weak labels, one robot per occupied node) -------------


def analyse(c: Configuration, reading: Mapping[str, str] | None = None, **options: str) -> Plan:
    """The plan of ``Gathering()`` for snapshot ``c`` (robots on distinct nodes) under
    ``reading`` (a :class:`Reading`, or option values; ``options`` override it, the
    others are at their defaults).

    >>> c = strings.from_string("001001400004000000000000404000400401000000100", 5)
    >>> analyse(c).phase
    'I2 guard selection'
    >>> analyse(c, finalize="n1").phase
    'I2 guard selection'
    """
    if not isinstance(reading, Reading) or options:
        reading = Reading({**DEFAULTS, **(reading or {}), **options})
    aut_m = meeting_automorphisms(c)[1:]
    if not aut_m:
        order = strings.ordering_O(c, reading["alpha"])
        if order is None:
            raise Unhandled("I11: the leading corner is not unique, O is not defined")
        return _everyone_to(c, "I11", order[-1])
    rotations = [a for a in aut_m if a.kind == "rotation"]
    symmetry = min(rotations, key=lambda a: a.order == 2) if rotations else aut_m[0]
    on_symmetry = sorted(m for m in c.meeting_nodes if symmetry.fixes(m))
    if not rotations and on_symmetry:
        order = strings.ordering_O_prime(c, on_symmetry, reading["alpha"])
        if order is None:
            raise Unhandled("I12: the leading corners order the meeting nodes on L differently")
        return _everyone_to(c, "I12", order[-1])
    if rotations and on_symmetry:
        return _everyone_to(c, "I13", on_symmetry[0])
    return _gathering_asym(c, symmetry, reading)


def _finalization(c: Configuration, o: Mapping[str, str]) -> Plan | None:
    """Algorithm 4 (``GuardMovement``): ``n1 = 2``, one position ``q`` a meeting node,
    and (``finalize=closest``) ``q`` a meeting node closest to the other position ``p``;
    ``finalize=target`` adds: when ``p`` stands on a corner of MER (a placed guard,
    where Algorithm 3 defines the target) and several meeting nodes are closest, ``q``
    is the first of them in ``O''`` (once the guard walks off its corner, ``O''`` is no
    longer defined and the closest condition alone remains). Who moves is
    :func:`_survivors`."""
    if len(c.occupied) != 2:
        return None
    on_meeting = [v for v in c.occupied if v in c.meeting_nodes]
    if len(on_meeting) != 1:
        return None
    target = on_meeting[0]
    (other,) = c.occupied - {target}
    nearest = min(manhattan(other, m) for m in c.meeting_nodes)
    finalize = o["finalize"]
    if finalize in ("closest", "target") and manhattan(other, target) > nearest:
        return None
    tied = sum(manhattan(other, m) == nearest for m in c.meeting_nodes) > 1
    if finalize == "target" and tied and other in strings.corners(c.mer()) and \
            target_meeting_node(c, other, o) != target:  # p placed: O'' breaks the tie
        return None
    moves, if_multiplicity, proof = _survivors(c, target, o)
    return Plan("I2 finalization", target, moves, if_multiplicity, guard=other,
                proof_moves=proof)


Moves = dict[Node, frozenset[Node]]


def _survivors(c: Configuration, target: Node | None, o: Mapping[str, str]
               ) -> tuple[Moves, Moves, Moves]:
    """Algorithm 4 lines 2-3 with ``n1 = 2``: "Let r be the robot that does not lie on a
    robot multiplicity node and on a meeting node; r moves towards the other robot
    position", as the robots on each position do it, seeing their own multiplicity bit,
    the occupied nodes and the meeting nodes (``target``: the occupied meeting node when
    exactly one position is one). ``survivor=neither``: r is on neither a multiplicity nor
    a meeting node; ``not-both``: r is not on a node that is both; ``off-target``: every
    robot not on the target moves (the prose: "the guard moves; the robots on m stay"),
    and with no target (no position a meeting node) every robot moves.
    ``if_multiplicity`` is what the robots that see their own node as a multiplicity do;
    the third map, what they do under ``movement=proof`` where ``survivor=neither`` leaves
    every robot on the position off the target without a move (the proof of Theorem 8:
    "If there is at most one robot position which is not on m at time t', then the
    execution of GuardMovement() is started", the guard moving towards m)."""
    a, b = sorted(c.occupied)
    moves = _stay_all(c)
    if_multiplicity: dict[Node, frozenset[Node]] = {}
    survivor = o["survivor"]
    if survivor == "off-target" and target is None and all(v in c.meeting_nodes for v in (a, b)):
        raise Unhandled("Finalization (survivor=off-target): both positions are meeting nodes, "
                        "no target tells which robots stay")
    for v, w in ((a, b), (b, a)):
        on_meeting = v in c.meeting_nodes
        if survivor == "off-target":
            moves[v] = frozenset({v}) if v == target else closer_steps(v, w)
        elif survivor == "not-both" or not on_meeting:
            moves[v] = closer_steps(v, w)
            if survivor == "neither" or on_meeting:
                if_multiplicity[v] = frozenset({v})
    if survivor == "neither" and all(v in c.meeting_nodes for v in (a, b)):
        raise Unhandled("Finalization: no survivor: both positions are meeting nodes, no robot "
                        "qualifies as r (survivor=neither)")
    proof = {} if target is None or survivor != "neither" else {
        v: closer_steps(v, target) for v in (a, b) if v not in c.meeting_nodes}
    return moves, if_multiplicity, proof


def _literal_finalization(c: Configuration, o: Mapping[str, str]) -> Plan:
    """Algorithm 4 read literally (``finalize=literal``), whenever ``n1 = 2``: the robots
    :func:`_survivors` names move towards the other position."""
    on_meeting = sorted(v for v in c.occupied if v in c.meeting_nodes)
    target = on_meeting[0] if len(on_meeting) == 1 else None
    moves, if_multiplicity, proof = _survivors(c, target, o)
    movers = sorted(v for v in c.occupied if moves[v] != {v})
    return Plan("I2 finalization (literal)", target, moves, if_multiplicity,
                guard=movers[0] if len(movers) == 1 else None, proof_moves=proof)


def _gathering_asym(c: Configuration, symmetry: Automorphism, o: Mapping[str, str]) -> Plan:
    if len(c.occupied) == 1 and c.robots[0] in c.meeting_nodes:
        return Plan("I2 gathered", c.robots[0], _stay_all(c))
    literal = o["finalize"] == "literal"
    final = None if literal else _finalization(c, o)
    if final is not None:
        return final
    # the distance to L is d(v, phi(v)) in every metric: metric is read for a rotation only
    metric = o["metric"] if symmetry.kind == "rotation" else "manhattan"
    dist = distance_function(symmetry, metric)
    aut_c = configuration_automorphisms(c)[1:]
    if aut_c:
        return _symmetry_breaking(c, symmetry, aut_c, dist, o)
    if literal and len(c.occupied) == 2:
        return _literal_finalization(c, o)
    d1 = max(dist(m) for m in c.meeting_nodes)
    far = max(dist(r) for r in c.occupied)
    farthest = sorted(r for r in c.occupied if dist(r) == far)
    x0, y0, x1, y1 = c.mer_f()

    def is_outside(v: Node) -> bool:
        if o["outside"] == "distance":
            return dist(v) > d1
        return not (x0 <= v[0] <= x1 and y0 <= v[1] <= y1)

    if len(farthest) == 1 and is_outside(farthest[0]):
        return _guard_placed_or_placing(c, farthest[0], dist, o)
    outs = [r for r in c.occupied if is_outside(r)]
    if outs:  # Algorithm 2, first branch: the farthest of the robots outside MER_F
        top = max(dist(r) for r in outs)
        farthest = sorted(r for r in outs if dist(r) == top)
    guard = farthest[0] if len(farthest) == 1 else strings.max_view(c, farthest, weak=True)
    if guard is None:
        raise Unhandled("I2 guard selection: the key corner is not unique")
    moves = _stay_all(c)
    moves[guard] = _away(guard, dist)
    return Plan("I2 guard selection", None, moves, guard=guard)


def _away(v: Node, dist) -> frozenset[Node]:
    """Algorithm 2: the neighbours of ``v`` farther from ``L ∪ {c}``."""
    return frozenset(u for u in geometry.neighbours(v) if dist(u) > dist(v))


def _guard_placed_or_placing(c: Configuration, guard: Node, dist, o: Mapping[str, str]
                             ) -> Plan:
    """Algorithm 2 line 5 ("finally towards its closest corner") and Algorithm 3. The guard
    approaches its closest MER corner by steps that do not bring it nearer ``L ∪ {c}`` (it
    stays the unique farthest robot, Lemma 5). When no such step exists,
    ``placement=reachable`` takes the closest of the corners it can approach so; the two
    readings agree wherever the closest corner has such a step (``placement`` is read
    only when it has none)."""
    corners = strings.corners(c.mer())
    moves = _stay_all(c)
    if guard not in corners:

        def keeping(k: Node) -> frozenset[Node]:  # steps towards k that keep dist
            return frozenset(u for u in closer_steps(guard, k) if dist(u) >= dist(guard))

        best = min(manhattan(guard, k) for k in corners)
        steps = frozenset().union(*(keeping(k) for k in corners if manhattan(guard, k) == best))
        if not steps and o["placement"] == "reachable":
            reachable = [k for k in corners if keeping(k)]
            if not reachable:
                raise Unhandled("I2 guard placement (reachable): no MER corner can be "
                                "approached without getting nearer L ∪ {c}")
            best = min(manhattan(guard, k) for k in reachable)
            steps = frozenset().union(*(keeping(k) for k in reachable
                                        if manhattan(guard, k) == best))
        if not steps:
            raise Unhandled("I2 guard placement: the guard cannot approach its closest MER "
                            "corner without getting nearer L ∪ {c} (placement=closest)")
        moves[guard] = steps
        return Plan("I2 guard placement", None, moves, guard=guard)
    target = target_meeting_node(c, guard, o)
    others = [r for r in c.occupied if r != guard and r != target]
    if c.occupied == {guard} and o["movement"] == "proof":
        # every robot on the guard's node, off M: Algorithm 3 has no non-guard left to move
        # and Algorithm 4 needs n1 = 2; the proof of Theorem 8 starts GuardMovement here
        # ("at most one robot position which is not on m"): the guard's node goes to m
        moves[guard] = closer_steps(guard, target)
        return Plan("I2 guard movement (proof of Theorem 8)", target, moves, guard=guard)
    if others:
        nearest = min(manhattan(r, target) for r in others)
        for r in others:
            if manhattan(r, target) == nearest:
                moves[r] = closer_steps(r, target)
    return Plan("I2 make multiplicity", target, moves, guard=guard)


def target_meeting_node(c: Configuration, guard: Node,
                        reading: Mapping[str, str] | None = None) -> Node:
    """Algorithm 3: the meeting node closest to the placed guard, ties by ``O''``."""
    best = min(manhattan(guard, m) for m in c.meeting_nodes)
    closest = [m for m in c.meeting_nodes if manhattan(guard, m) == best]
    if len(closest) == 1:
        return closest[0]
    oscan = DEFAULTS["oscan"] if reading is None else reading["oscan"]
    return min(closest, key=ordering_O_second(c, guard, oscan).index)


def ordering_O_second(c: Configuration, guard: Node, oscan: str = "key") -> tuple[Node, ...]:
    """``O''``: the meeting nodes in the lambda scan of MER from the guard's corner,
    its grid lines parallel to the string direction (paper §4) of the key corner
    (``oscan=key``) or of the guard's own corner (``oscan=guard``). The two differ only
    on a square MER, where a corner's string direction is that of its larger string."""
    if oscan == "guard":
        mine = [s for s in strings.representations(c.mer(), c.weak_label, c.labelled)
                if s.corner == guard]
        along_x = {s.fast[0] != 0 for s in mine}
        if len(along_x) != 1:
            raise Unhandled("I2 target O'' (oscan=guard): the guard's corner has two equal "
                            "strings, its string direction is not defined")
    else:
        keys = strings.key_scans(c, weak=True)
        along_x = {s.fast[0] != 0 for s in keys}
        if len(along_x) != 1:
            raise Unhandled("I2 target O'' (oscan=key): the key corners' string directions "
                            "differ, O'' is not defined")
    horizontal = along_x.pop()
    (scan,) = [s for s in strings.all_scans(c.mer(), c.lam, c.meeting_nodes)
               if s.corner == guard and (s.fast[0] != 0) == horizontal]
    return strings.meeting_order(scan, c.meeting_nodes)


def _hidden_multiplicity(c: Configuration, dist, o: Mapping[str, str], looks: str,
                         why: str) -> Plan:
    """A weak snapshot in U (``looks`` like I41 or I42; ``why`` no rule applies). By default
    (``hidden=unhandled``) there is no rule. ``hidden=infer`` reads §4 after Algorithm 5
    ("Suppose a robot multiplicity is created during the execution of SymmetryBreaking().
    In that case, the robot that is farthest from L ∪ {c} and does not lie on a
    multiplicity is selected as the guard ... such a robot position always exists"): the
    run started outside U and never enters it (Lemma 7), so a robot seeing this snapshot
    infers a hidden multiplicity. With two positions a robot that is not on a
    multiplicity knows the other one holds it: it is the only robot off a multiplicity,
    hence the guard, and steps away from ``L ∪ {c}`` (Algorithm 2); robots on the
    multiplicity stay. With three or more positions a robot off a multiplicity cannot
    tell which position holds it (its mirror image looks as it does), so still no rule."""
    if o["hidden"] != "infer":
        raise Unhandled(f"{looks} snapshot: {why} (hidden=unhandled)")
    if len(c.occupied) != 2:
        raise Unhandled(f"{looks} snapshot (hidden=infer): a multiplicity is hidden, but with "
                        f"{len(c.occupied)} positions a robot off it cannot tell where")
    moves = {v: _away(v, dist) for v in c.occupied}
    return Plan(f"{looks} snapshot: hidden multiplicity, guard selection", None, moves,
                {v: frozenset({v}) for v in c.occupied})


def _symmetry_breaking(c: Configuration, symmetry: Automorphism,
                       aut_c: list[Automorphism], dist, o: Mapping[str, str]) -> Plan:
    moves = _stay_all(c)
    rotation = next((a for a in aut_c if a.kind == "rotation"), None)
    if rotation is not None:
        centre = [r for r in c.occupied if rotation.fixes(r)]
        if not centre:
            return _hidden_multiplicity(
                c, dist, o, "I42-looking", "C is rotationally symmetric with no robot or "
                "meeting node on c (ungatherable, Theorem 1)")
        moves[centre[0]] = frozenset(geometry.neighbours(centre[0]))
        return Plan("I3 symmetry breaking (c)", None, moves, guard=None)
    mirror = aut_c[0]
    if symmetry.kind == "rotation" and o["unclassified"] != "break":
        raise Unhandled("UNCLASSIFIED snapshot (unclassified=unhandled): M is rotational with "
                        "no meeting node on c and C has a single reflection")
    on_axis = [r for r in c.occupied if mirror.fixes(r)]
    if not on_axis and symmetry.kind == "rotation":
        if any(mirror.fixes(m) for m in c.meeting_nodes):  # not in U: no inference
            raise Unhandled("UNCLASSIFIED snapshot, no robot on the axis: M is rotational "
                            "with no meeting node on c and C has a single reflection whose "
                            "axis holds meeting nodes and no robot: the paper has no rule")
        return _hidden_multiplicity(
            c, dist, o, "UNCLASSIFIED-in-U", "M is rotational and C has a single reflection "
            "whose axis holds no robot and no meeting node (in U, Theorem 1)")
    if not on_axis:
        return _hidden_multiplicity(c, dist, o, "I41-looking", "C is symmetric about L with "
                                    "no robot or meeting node on L (ungatherable, Theorem 1)")
    r = strings.max_view(c, on_axis, weak=True)
    if r is None:
        raise Unhandled("I3 symmetry breaking (L): the key corners disagree on the robot of "
                        "the axis with the maximum view")
    moves[r] = frozenset(u for u in geometry.neighbours(r) if not mirror.fixes(u))
    return Plan("I3 symmetry breaking (L)", None, moves)


# -- canonical forms and the algorithm object ----------------------------------------


def first_step(allowed: Iterable[Node]) -> Node:
    """The robot's answer: stay, or the first allowed step in ``STEPS`` order."""
    allowed = set(allowed)
    for step in STEPS:
        if step in allowed:
            return step
    if allowed == {ORIGIN}:
        return ORIGIN
    raise Unhandled(f"Move rule: no step among destinations {sorted(allowed)}")  # pragma: no cover


@lru_cache(maxsize=CACHE_SIZE)
def _answer(allowed: frozenset[Node], me: Node, g: int) -> Node:
    """The answer in the robot's frame: ``first_step`` of the allowed destinations (canonical
    coordinates, the robot at ``me``) mapped back by ``g``'s inverse."""
    back = geometry.inverse(g)
    return first_step(geometry.apply(back, geometry.sub(a, me)) for a in allowed)


@lru_cache(maxsize=CACHE_SIZE)
def _global_answer(relative: frozenset[Node], g: int) -> Node:
    """The step, in global coordinates, of a robot in frame ``g`` whose allowed steps are
    ``relative`` (global coordinates, the robot at the origin)."""
    answer = first_step(geometry.apply(g, d) for d in relative)
    return geometry.apply(geometry.inverse(g), answer)


class PaperAlgorithm:
    """The paper's ``Gathering()``; see the module docstring for the phases."""

    def __init__(self, alpha: str = "mer", unclassified: str = "break",
                 outside: str = "distance", finalize: str = "closest",
                 metric: str = "manhattan", oscan: str = "key", placement: str = "closest",
                 survivor: str = "neither", hidden: str = "unhandled",
                 movement: str = "algorithm") -> None:
        given = {"alpha": alpha, "metric": metric, "oscan": oscan, "finalize": finalize,
                 "outside": outside, "unclassified": unclassified, "placement": placement,
                 "survivor": survivor, "hidden": hidden, "movement": movement}
        for option, value in given.items():
            if value not in READINGS[option]:
                raise InvalidInput(f"bad option {option}={value!r}: use "
                                 f"{' or '.join(READINGS[option])}")
        self.reading = {option: given[option] for option in READINGS}
        self.consulted: set[str] = set()
        """Every option read by a plan this instance computed (a plan comes from the cache
        only if this instance computed it) or by one of its robots' moves (``allowed``):
        the dynamic covering of the readings."""
        self.name = "paper"
        self._plan = lru_cache(maxsize=CACHE_SIZE)(self._plan_uncached)

    def _plan_uncached(self, key: Key) -> Plan | Unhandled:
        robots, meeting = key
        try:
            return analyse(Configuration.trusted(robots, frozenset(meeting)),
                           Reading(self.reading, self.consulted))
        except Unhandled as error:
            return error

    def plan(self, configuration: Configuration) -> Plan:
        """The plan for a configuration in global coordinates (multiplicities read weakly)."""
        key, reach = configuration.canonical_form
        g, t = reach[0]
        plan = self._plan(key)
        if isinstance(plan, Unhandled):
            raise Unhandled(str(plan))
        back = geometry.inverse(g)

        def unmap(v: Node) -> Node:
            return geometry.apply(back, geometry.sub(v, t))

        def unmap_all(moves: dict[Node, frozenset[Node]]) -> dict[Node, frozenset[Node]]:
            return {unmap(v): frozenset(map(unmap, a)) for v, a in moves.items()}

        return Plan(plan.phase, None if plan.target is None else unmap(plan.target),
                    unmap_all(plan.moves), unmap_all(plan.if_multiplicity),
                    None if plan.guard is None else unmap(plan.guard),
                    unmap_all(plan.proof_moves))

    def move_sets(self, configuration: Configuration, detection: str,
                  frames: tuple[int, ...]) -> dict[Node, frozenset[Node]] | None:
        """Every robot's move set from one plan, without a view per robot and frame: the
        robot on ``v`` in frame ``F`` answers ``first_step(F(A - v))`` for its allowed
        destinations ``A``, so its move set is the union of ``v + F^-1`` of those answers
        (what :func:`~gather_verify.algorithms.moves.move_set` collects from
        :meth:`decide`). None under detection ``none`` (the plan may read a multiplicity
        that model hides, and only :meth:`decide` says so), for a subclass with its own
        ``decide``, and in a copy of this module (``tools/mutants.py`` edits ``decide``):
        there ``decide`` is asked view by view."""
        if detection == "none" or __name__ != _HOME or type(self).decide is not PaperAlgorithm.decide:
            return None  # also a subclass, or a copy of this module with its code edited (mutants)
        plan = self.plan(configuration)
        counts = configuration.counts
        out = {}
        for v in counts:
            allowed = self.allowed(plan, v, counts[v] > 1)
            relative = frozenset((x - v[0], y - v[1]) for x, y in allowed)
            out[v] = frozenset((v[0] + dx, v[1] + dy)
                               for dx, dy in (_global_answer(relative, g) for g in frames))
        return out

    def allowed(self, plan: Plan, v: Node, multiplicity: bool) -> frozenset[Node]:
        """The destinations of a robot on ``v`` that sees its own node as a multiplicity
        (``multiplicity``) or not. ``movement`` is read here, and only when such a robot is
        on a node of ``plan.proof_moves``: a run that never meets one stands for both
        values (the dynamic covering, :mod:`gather_verify.paper.readings`)."""
        if not multiplicity or v not in plan.if_multiplicity:
            return plan.moves[v]
        if v in plan.proof_moves and \
                Reading(self.reading, self.consulted)["movement"] == "proof":
            return plan.proof_moves[v]
        return plan.if_multiplicity[v]

    def decide(self, view: View) -> Node:
        key, g, t = view.canonical()
        plan = self._plan(key)
        if isinstance(plan, Unhandled):
            raise Unhandled(str(plan))
        me = t  # the robot is at the origin of its view: g(0) + t = t
        return _answer(self.allowed(plan, me, view.multiplicity()), me, g)

    def phase(self, configuration: Configuration) -> str | None:
        """The phase of the plan for ``configuration`` (None where there is no rule)."""
        key, _ = configuration.canonical_form
        plan = self._plan(key)
        return None if isinstance(plan, Unhandled) else plan.phase

    @commutes_with_translations
    def target(self, configuration: Configuration) -> Node | None:
        """The target meeting node (global coordinates) where the phase defines one."""
        key, reach = configuration.canonical_form
        plan = self._plan(key)
        if isinstance(plan, Unhandled) or plan.target is None:
            return None
        g, t = reach[0]
        return geometry.apply(geometry.inverse(g), geometry.sub(plan.target, t))
