"""A naive, independent referee for two robots with lights in the plane (SEMANTICS.md §13).

A plain breadth-first search over §13's states, for every synchrony model of §13, and a
fair-component analysis for the task ``rendezvous``. It is written from §13 alone: it takes
the algorithms' tables from :mod:`gather_verify.worlds.rendezvous_rules` (data) and nothing
else of the project, so that the rules module and, later, the world in the pipeline can be
checked against it.

A state is ``(position, robot A, robot B)``; a robot is ``(phase, colour, next colour,
pending move)``: its phase is the next step it takes (0 Look .. 4 End-Move), ``next
colour`` the colour its Compute chose (kept from its Look to its End-Compute, else equal
to its colour), its pending move one of stay, to-half, to-other, miss. An event is one
atomic step of the model: one robot's group of phases, or a joint step of both robots.

Two notions of fairness:

- ``fair`` (§13, the literature's): every robot completes infinitely many cycles. A
  component of the state graph (self-loops included) is fair when both robots step on
  some edge inside it.
- ``bounded`` (the SPIN model's): no robot takes more than ``(1 + K) x steps per cycle``
  consecutive steps (a joint step resets the count); the count is part of the state,
  every infinite run is then fair, and a gathered state ends the run (the model's
  scheduler stops there).

And two goals: ``gathered`` (§13: the robots at one point with nothing pending, and they
stay) and ``same`` (the SPIN model's LTL property ``<>[] position == SAME``).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass

from gather_verify.worlds.rendezvous_rules import RendezvousAlgorithm

FAR, NEAR, SAME = 0, 1, 2
STAY, HALF, OTHER, MISS = 0, 1, 2, 3
L, BC, EC, BM, EM = range(5)
POS = ("far", "near", "same")
MOVE = ("stay", "to-half", "to-other", "miss")
STEP = ("look", "begin-compute", "end-compute", "begin-move", "end-move")

WHOLE = ((L, BC, EC, BM, EM),)


@dataclass(frozen=True)
class Model:
    """A synchrony model: the cycle cut into atomic groups, whether one robot steps at a
    time (``single``) and whether both may do their first group together (``joint``), how
    a Look reads a light being changed, and the SPIN model's steps per cycle."""

    groups: tuple[tuple[int, ...], ...]
    single: bool = True
    joint: bool = False
    reads: str = "atomic"
    spin_steps: int = 5


MODELS = {
    "centralized": Model(WHOLE, spin_steps=1),
    "fsync": Model(WHOLE, single=False, joint=True, spin_steps=1),
    "ssync": Model(WHOLE, joint=True, spin_steps=1),
    "async": Model(((L,), (BC,), (EC,), (BM,), (EM,))),
    "async-regular": Model(((L,), (BC,), (EC,), (BM,), (EM,)), reads="regular"),
    "async-safe": Model(((L,), (BC,), (EC,), (BM,), (EM,)), reads="safe"),
    "async-lc-atomic": Model(((L, BC, EC), (BM,), (EM,)), joint=True, spin_steps=3),
    "async-lc-strict": Model(((L, BC, EC), (BM,), (EM,)), spin_steps=3),
    "async-cm-atomic": Model(((L,), (BC, EC, BM, EM)), spin_steps=3),
    "async-move-atomic": Model(((L,), (BC,), (EC,), (BM, EM)), spin_steps=4),
    "async-move-regular": Model(((L,), (BC,), (EC,), (BM, EM)), reads="regular", spin_steps=4),
    "async-move-safe": Model(((L,), (BC,), (EC,), (BM, EM)), reads="safe", spin_steps=4),
}
"""§13's synchrony models, as the SPIN model names them (lower case, hyphens)."""


def group_of(model: Model, phase: int) -> tuple[int, ...]:
    return next(g for g in model.groups if g[0] == phase)


class Referee:
    """The state graph of one algorithm under one model, from every initial state."""

    def __init__(self, alg: RendezvousAlgorithm, model: str, movement: str = "non-rigid",
                 colours: str = "all", fairness: str = "fair", limit: int | None = None):
        self.alg, self.model, self.name = alg, MODELS[model], model
        self.k = alg.colours
        self.bounded = fairness == "bounded"
        self.limit = (1 + self.k) * self.model.spin_steps if limit is None else limit
        pos = (NEAR, SAME) if movement == "rigid" else (FAR, NEAR, SAME)
        pairs = [(a, b) for a in range(self.k) for b in range(self.k)
                 if colours == "all" or a == b]
        self.starts = [self._tag((p, (L, a, a, STAY), (L, b, b, STAY)), None)
                       for p in pos for a, b in pairs]

    # --- one robot's steps ------------------------------------------------------------
    def reads(self, state: tuple, i: int) -> tuple[int, ...]:
        """The colours robot i's Look may read for the other's light."""
        ph, colour, nxt, _ = state[2 - i]
        if ph != EC:  # not between its Begin-Compute and End-Compute
            return (colour,)
        if self.model.reads == "regular":
            return tuple(sorted({colour, nxt}))
        if self.model.reads == "safe":
            return tuple(range(self.k))
        return (colour,)

    def step(self, state: tuple, i: int, read: int | None) -> tuple:
        """Robot i takes its next step (its Look reads ``read``)."""
        pos = state[0]
        robots = [state[1], state[2]]
        ph, colour, nxt, pending = robots[i]
        other = robots[1 - i]
        if ph == L:
            other_moving = other[0] == EM and other[3] != STAY
            move, new = self.alg.answer(colour, read, pos)
            if pos == SAME and not other_moving:
                move = STAY
            elif other_moving and move in (HALF, OTHER):
                move = MISS
            robots[i] = (BC, colour, new, move)
        elif ph == BC:
            robots[i] = (EC, colour, nxt, pending)
        elif ph == EC:
            robots[i] = (BM, nxt, nxt, pending)
        elif ph == BM:
            robots[i] = (EM, colour, nxt, pending)
        else:
            if pending != STAY:
                pos, theirs = self.land(pos, pending, other[3])
                robots[1 - i] = other[:3] + (theirs,)
            robots[i] = (L, colour, colour, STAY)
        return (pos, robots[0], robots[1])

    @staticmethod
    def land(pos: int, mine: int, theirs: int) -> tuple[int, int]:
        """§13's End-Move: the new position and the other's pending move."""
        if pos == FAR:
            return NEAR, (STAY if theirs == STAY else MISS)
        if mine == MISS:
            return NEAR, (STAY if theirs == STAY else MISS)
        if mine == OTHER:
            return SAME, (theirs if theirs == STAY or pos == SAME else MISS)
        if theirs == HALF:
            return pos, OTHER
        return pos, (STAY if theirs == STAY else MISS)

    def run_group(self, state: tuple, i: int, phases: tuple[int, ...]) -> Iterator[tuple]:
        """Robot i's group of steps, one successor per colour its Look may read."""
        if phases[0] == L:
            for read in self.reads(state, i):
                s = self.step(state, i, read)
                for _ in phases[1:]:
                    s = self.step(s, i, None)
                yield s
        else:
            s = state
            for _ in phases:
                s = self.step(s, i, None)
            yield s

    # --- the model's events -----------------------------------------------------------
    def events(self, tagged: tuple) -> Iterator[tuple[int, str, tuple]]:
        """(robots mask, label, successor) of every event from a (tagged) state."""
        state, tag = tagged[:3], tagged[3]
        if self.bounded and self.goal(state):  # the SPIN model's scheduler stops there
            return
        m = self.model
        if m.single:
            for i in (0, 1):
                if self.bounded and tag is not None and tag[0] == i and tag[1] >= self.limit:
                    continue
                group = group_of(m, state[1 + i][0])
                label = "AB"[i] + ": " + "+".join(STEP[p] for p in group)
                count = tag[1] + 1 if tag is not None and tag[0] == i else 1
                for s in self.run_group(state, i, group):
                    yield 1 << i, label, self._tag(s, (i, count))
        if m.joint and state[1][0] == L and state[2][0] == L:
            group = m.groups[0]
            a = self.step(state, 0, state[2][1])
            ab = self.step(a, 1, state[1][1])  # A has looked, not computed: B reads A's old colour
            for _ in group[1:]:
                ab = self.step(ab, 0, None)
            for _ in group[1:]:
                ab = self.step(ab, 1, None)
            yield 3, "A+B: " + "+".join(STEP[p] for p in group), self._tag(ab, None)

    def _tag(self, state: tuple, tag: tuple[int, int] | None) -> tuple:
        return (*state, tag if self.bounded else None)

    @staticmethod
    def goal(state: tuple) -> bool:
        return state[0] == SAME and state[1][3] == STAY and state[2][3] == STAY


    # --- the search ---------------------------------------------------------------------
    def explore(self) -> None:
        """Breadth-first search from every initial state: ids, edges, parents."""
        self.index: dict[tuple, int] = {}
        self.states: list[tuple] = []
        self.edges: list[list[tuple[int, int, str]]] = []
        self.parent: list[tuple[int, str] | None] = []
        for s in self.starts:
            if s not in self.index:
                self.index[s] = len(self.states)
                self.states.append(s)
                self.parent.append(None)
        queue = deque(range(len(self.states)))
        while queue:
            v = queue.popleft()
            out = []
            for mask, label, succ in self.events(self.states[v]):
                w = self.index.get(succ)
                if w is None:
                    w = self.index[succ] = len(self.states)
                    self.states.append(succ)
                    self.parent.append((v, label))
                    queue.append(w)
                out.append((w, mask, label))
            self.edges.append(out)
        self.transitions = sum(len(e) for e in self.edges)


def components(edges: list[list[tuple[int, int, str]]]) -> list[list[int]]:
    """Tarjan's strongly connected components, iteratively."""
    n = len(edges)
    index, low, on = [-1] * n, [0] * n, [False] * n
    stack: list[int] = []
    out: list[list[int]] = []
    counter = 0
    for root in range(n):
        if index[root] >= 0:
            continue
        work = [(root, 0)]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on[root] = True
        while work:
            v, k = work[-1]
            if k < len(edges[v]):
                work[-1] = (v, k + 1)
                w = edges[v][k][0]
                if index[w] < 0:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on[w] = True
                    work.append((w, 0))
                elif on[w]:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on[w] = False
                    comp.append(w)
                    if w == v:
                        break
                out.append(comp)
    return out


@dataclass
class Verdict:
    verdict: str  # "PASS" or "FAIL"
    states: int
    transitions: int
    prefix: list[tuple[str, tuple]] | None = None  # (event label, state) from a start
    cycle: list[tuple[str, tuple]] | None = None


def check(alg: RendezvousAlgorithm, model: str, movement: str = "non-rigid",
          colours: str = "all", fairness: str = "fair", goal: str = "gathered",
          limit: int | None = None) -> Verdict:
    """The verdict of ``rendezvous`` (``goal`` gathered: §13's; same: the SPIN model's
    ``<>[] position == SAME``) under ``fairness`` (fair: §13's; bounded: the SPIN model's),
    with a counterexample: a prefix from an initial state and a cycle that stays out of the
    goal (a fair one: both robots step in it). ``limit``: the bounded fairness's most
    consecutive steps of one robot (default the SPIN model's, ``(1 + K) x steps``)."""
    ref = Referee(alg, model, movement, colours, fairness, limit)
    ref.explore()
    bad = (lambda s: s[0] != SAME) if goal == "same" else (lambda s: not Referee.goal(s))
    for comp in sorted(components(ref.edges), key=min):
        members = set(comp)
        inner = [(v, w, mask) for v in comp for w, mask, _ in ref.edges[v] if w in members]
        if not inner:
            continue
        masks = 0
        for _, _, mask in inner:
            masks |= mask
        if fairness == "fair" and masks != 3:
            continue
        targets = [v for v in comp if bad(ref.states[v])]
        if targets:
            start = min(targets)
            return Verdict("FAIL", len(ref.states), ref.transitions, prefix_to(ref, start),
                           fair_cycle(ref, members, start, fairness == "fair"))
    return Verdict("PASS", len(ref.states), ref.transitions)


def prefix_to(ref: Referee, v: int) -> list[tuple[str, tuple]]:
    path = [("start", ref.states[v])]
    while ref.parent[v] is not None:
        u, label = ref.parent[v]  # type: ignore[misc]
        path[-1] = (label, ref.states[v])
        path.append(("start", ref.states[u]))
        v = u
    return path[::-1]


def fair_cycle(ref: Referee, members: set[int], start: int, both: bool
               ) -> list[tuple[str, tuple]]:
    """A cycle from ``start`` inside the component, through an edge of A and one of B when
    ``both`` (a fair cycle), as (event label, state) steps."""
    walk: list[tuple[str, tuple]] = [("start", ref.states[start])]
    here = start
    for need in ((1, 2) if both else (3,)):
        here = _walk(ref, members, here, lambda mask, need=need: mask & need, walk)
    _walk(ref, members, here, None, walk, goal=start)
    return walk


def _walk(ref: Referee, members: set[int], frm: int, edge_ok, walk, goal: int | None = None
          ) -> int:
    """Shortest path inside ``members`` from ``frm`` ending with an edge that ``edge_ok``
    accepts (or at ``goal``); appends its steps to ``walk``; returns where it ends."""
    parent: dict[int, tuple[int, str] | None] = {frm: None}
    queue = deque([frm])
    end = None
    if goal is not None and frm == goal and len(walk) > 1:
        return frm
    while queue and end is None:
        v = queue.popleft()
        for w, mask, label in ref.edges[v]:
            if w not in members:
                continue
            if edge_ok is not None and edge_ok(mask):
                end = (v, w, label)
                break
            if goal is not None and w == goal:
                end = (v, w, label)
                break
            if w not in parent:
                parent[w] = (v, label)
                queue.append(w)
    assert end is not None, "no such path inside the component"
    v, w, label = end
    steps = [(label, ref.states[w])]
    while parent[v] is not None:
        u, lab = parent[v]  # type: ignore[misc]
        steps.append((lab, ref.states[v]))
        v = u
    walk.extend(steps[::-1])
    return w


def show(state: tuple) -> str:
    """A state as one line: ``near | A: end-compute black->white to-half | B: ...``."""
    parts = [POS[state[0]]]
    for name, (ph, colour, nxt, pending) in zip("AB", state[1:3], strict=True):
        light = f"{colour}->{nxt}" if nxt != colour else f"{colour}"
        parts.append(f"{name}: next {STEP[ph]}, light {light}, {MOVE[pending]}")
    if state[3] is not None:
        parts.append(f"last {'AB'[state[3][0]]} x{state[3][1]}")
    return " | ".join(parts)


def render(steps: list[tuple[str, tuple]]) -> list[str]:
    return [f"{label:32} {show(state)}" for label, state in steps]


def starvation_needed(alg: RendezvousAlgorithm, model: str, movement: str = "non-rigid",
                      colours: str = "all") -> int | None:
    """The fewest consecutive steps of one robot that a bounded scheduler must allow for a
    counterexample to exist (None when there is none even under §13's fairness): the
    SPIN model finds every counterexample exactly when this is at most its bound."""
    if check(alg, model, movement, colours).verdict == "PASS":
        return None
    lo, hi = 1, (1 + alg.colours) * MODELS[model].spin_steps
    while check(alg, model, movement, colours, "bounded", limit=hi).verdict == "PASS":
        lo, hi = hi + 1, 2 * hi
    while lo < hi:
        mid = (lo + hi) // 2
        if check(alg, model, movement, colours, "bounded", limit=mid).verdict == "FAIL":
            hi = mid
        else:
            lo = mid + 1
    return lo
