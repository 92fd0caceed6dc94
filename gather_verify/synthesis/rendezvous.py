"""Synthesis on the rendezvous world: does some algorithm with K colours make two robots
with lights meet under a synchrony model (SEMANTICS.md §12, §13)?

An algorithm is a table from a view (own colour, other's colour, as far as the lights show
them; the relative position) to a move and a colour. The search assigns a view's answer
only when a reachable state needs it (lazily, depth first), and after each assignment
explores what the table decides so far, going on from what its parent reached: a state
that needs an unassigned view is *open*, and only its steps that read no unassigned view
are taken (every completion of the table has them). A fair strongly connected component
of these known steps outside the goal (both robots step in it, it never gathers) is in the
state graph of every completion, so the whole subtree fails there. A table with no open
state and no such component is a witness, which
the ordinary check (:func:`~gather_verify.rendezvous_check.run_rendezvous_check`) then
verifies. When every branch fails, the answer is ``none`` with a certificate: the case
split (a view, and a subtree per answer) down to each refuted partial table, which
:func:`verify` re-checks without searching.

Colours are names: renaming them in an algorithm renames its states, so a table and its
renamings succeed or fail together (:meth:`Setting.renamings` says which renamings keep the
initial states; every one of them does for ``all`` and ``same``). The search therefore
skips a partial table whose renaming it has already searched to the end with no witness;
the certificate marks such a node ``renamed`` and :func:`verify` re-checks that an
earlier subtree, already verified, holds a renaming of its table. Such a node's failure
reads what its twin's reads, renamed, so a split above it may still backjump.

>>> synthesize(1, "full", "fsync", "rigid", "all")["answer"]
'exists'
>>> r = synthesize(1, "full", "async", "rigid", "all")
>>> r["answer"], verify(r["certificate"])
('none', True)
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from itertools import permutations, product
from typing import Any, cast

from gather_verify.errors import GatherVerifyError, InvalidInput
from gather_verify.properties.graph import components_of
from gather_verify.rendezvous_check import phase_model, run_rendezvous_check
from gather_verify.worlds.rendezvous import Rendezvous, State
from gather_verify.worlds.rendezvous_rules import (
    INITIAL_COLOURS,
    LIGHTS,
    MOVEMENTS,
    POSITIONS,
    STAY,
    TO_HALF,
    TO_OTHER,
    RendezvousAlgorithm,
)
from schedulers.phases import phase_events

View = tuple[int | None, int | None, int]
"""(own colour or None, other's colour or None, position): what a robot sees."""
Answer = tuple[int, int]
"""(move, new colour)."""
Renaming = tuple[int, ...]
"""A permutation of the colours: colour c becomes renaming[c]."""
Canon = tuple[tuple[tuple[int, int, int], Answer], ...]
"""The least of a table's renamings, as sorted rows (a hidden colour written -1)."""


@dataclass
class Partial:
    """A table being built, as the rendezvous world asks an algorithm: each view asked is
    appended to ``asked`` and answered by ``given``."""

    colours: int
    lights: str
    asked: list[View] = field(default_factory=list)
    given: Callable[[View], Answer] = lambda view: (STAY, 0)

    def view(self, own: int, other: int, position: int) -> View:
        return (None if self.lights == "external" else own,
                None if self.lights == "internal" else other, position)

    def answer(self, own: int, other: int, position: int) -> Answer:
        key = self.view(own, other, position)
        self.asked.append(key)
        return self.given(key)


def views(colours: int, lights: str) -> list[View]:
    """Every view a robot may have under these lights."""
    own = [None] if lights == "external" else list(range(colours))
    other = [None] if lights == "internal" else list(range(colours))
    return [(a, b, p) for a, b, p in product(own, other, range(len(POSITIONS)))]


UNASSIGNED: Answer = (STAY, -1)
"""The answer a partial table's Look gets for a view it does not give: colour -1 marks
the successor as unknown (:meth:`Setting._steps` drops it)."""


def answers(colours: int) -> list[Answer]:
    return [(m, c) for m in (STAY, TO_HALF, TO_OTHER) for c in range(colours)]


@dataclass(frozen=True)
class Setting:
    """What is synthesized for: K colours, the lights, the model, movement, initial colours."""

    colours: int
    lights: str
    scheduler: str
    movement: str
    initial_colours: str
    _memo: dict[State, tuple[tuple[View, ...], dict[tuple[Answer | None, ...], list[tuple[
        State, int]]]]] = field(default_factory=dict, compare=False, repr=False)

    def explore(self, table: dict[View, Answer], below: Explored | None = None
                ) -> tuple[bool, View | None, Explored]:
        """What ``table`` decides so far: whether a fair run of known steps never gathers
        (refuted), the first view an open state needs (None: every state decided), and the
        states it reaches by known steps (an open state's steps that read no unassigned
        view). ``below``: what a sub-table of ``table`` reached, from which the search goes
        on (a state has the same known successors as long as no view its Looks read is
        added, so only the open states that read an added view are stepped again; the
        reached states are those of a search from scratch)."""
        if below is None:
            graph = Explored.of(self.starts())
            work = list(range(len(graph.states)))
            graph.open = []
        else:
            graph = below.copy()
            added = table.keys() - below.given
            work, graph.open = [], []
            for v in below.open:
                again = not added.isdisjoint(self._memo[graph.states[v]][0])
                (work if again else graph.open).append(v)
        graph.given = frozenset(table)
        since = None if below is None or below.fair is not None else work  # grows below
        at = 0
        while at < len(work):
            v = work[at]
            at += 1
            out, missing = self._steps(graph.states[v], table)
            if missing is not None:
                graph.open.append(v)
            targets = []
            for succ, _ in out:
                w = graph.index.get(succ)
                if w is None:
                    w = graph.add(succ)
                    work.append(w)
                targets.append(w)
            graph.edges[v], graph.masks[v] = targets, [mask for _, mask in out]
        graph.open.sort()
        need = self._steps(graph.states[graph.open[0]], table)[1] if graph.open else None
        graph.fair = _fair_outside_goal(graph, since)
        return graph.fair is not None, need, graph

    def _steps(self, state: State, table: dict[View, Answer]
               ) -> tuple[list[tuple[State, int]], View | None]:
        """A state's known successors with the robots of each step (those of its steps that
        read no view ``table`` leaves unassigned), and the first view its Looks need that
        ``table`` does not give (None: all its steps are known). A Look of an unassigned
        view chooses colour -1, which stays in the successor to the event's end, and such
        successors are dropped. Remembered per state and per answer to the views its Looks
        read (which the state alone fixes: asserted), so that a state is stepped once per
        answer in the whole search."""
        memo = self._memo.get(state)
        if memo is None:
            asked: list[View] = []
            self._stepped(state, asked, lambda view: (STAY, 0))
            memo = self._memo[state] = (tuple(asked), {})
        needed, known = memo
        key = tuple(table.get(view) for view in needed)
        if key not in known:
            asked = []
            known[key] = [(succ, mask) for succ, mask in self._stepped(
                state, asked, lambda view: table.get(view, UNASSIGNED)) if min(
                    succ[1][1], succ[1][2], succ[2][1], succ[2][2]) >= 0]
            assert tuple(asked) == needed, "a state's Looks read views the state does not fix"
        return known[key], next((view for view in needed if view not in table), None)

    def _stepped(self, state: State, asked: list[View], answer: Callable[[View], Answer]
                 ) -> list[tuple[State, int]]:
        alg = Partial(self.colours, self.lights, asked, answer)
        return [(succ, sum(1 << i for i in event.robots)) for event, succ in phase_events(
            phase_model(self.scheduler), Rendezvous(cast(RendezvousAlgorithm, alg)), state)]

    def starts(self) -> list[State]:
        """The initial states (all robots idle; no view asked)."""
        return Rendezvous(cast(RendezvousAlgorithm, Partial(self.colours, self.lights))
                          ).starts(self.movement, self.initial_colours)

    def core(self, graph: Explored, table: dict[View, Answer]) -> frozenset[View]:
        """The views a refuted table's refutation reads: those ``table`` gives of the states
        on a shortest path from an initial state into its fair component, and of the
        component's states. A known step depends only on the answers to the given views its
        Look read, so every table that answers these views alike reaches the same component
        by the same steps and is refuted too."""
        assert graph.fair is not None
        inside = set(graph.fair)
        parent: dict[int, int | None] = dict.fromkeys(range(graph.starts))
        end = next((v for v in range(graph.starts) if v in inside), None)
        queue = deque(range(graph.starts))
        while end is None:
            v = queue.popleft()
            for w in graph.edges[v]:
                if w not in parent:
                    parent[w] = v
                    queue.append(w)
                    if w in inside:
                        end = w
                        break
        path: list[int] = []
        at: int | None = end
        while at is not None:
            path.append(at)
            at = parent[at]
        return frozenset(view for v in (*path, *graph.fair)
                         for view in self._memo[graph.states[v]][0] if view in table)

    def renamings(self) -> list[Renaming]:
        """The renamings of colours that map the set of initial states onto itself. The
        rules of the plane and the reads (atomic, regular, and a safe read's every colour)
        name no colour, so under such a renaming a table's state graph is its renaming's,
        state for state, and the verdict is the same. Up to 5 colours (120 renamings);
        beyond, the identity alone."""
        if self.colours > 5:
            return [tuple(range(self.colours))]
        starts = self.starts()
        kept = set(starts)
        return [r for r in permutations(range(self.colours))
                if {_renamed_state(s, r) for s in starts} == kept]

    def least(self, table: dict[View, Answer], renamings: list[Renaming]
              ) -> tuple[Canon, Renaming]:
        """One name for a table and all its renamings, the least renamed table, and the first
        renaming that gives it."""
        return min((tuple(sorted(((_name(v[0], r), _name(v[1], r), v[2]), (a[0], r[a[1]]))
                                 for v, a in table.items())), r) for r in renamings)


def _sorted_views(views: frozenset[View]) -> list[list[int | None]]:
    return sorted((list(v) for v in views), key=lambda v: [-1 if x is None else x for x in v])


def _renamed_views(views: frozenset[View], renaming: Renaming, back: bool = False
                   ) -> frozenset[View]:
    """Views with their colours renamed (``back``: by the inverse renaming)."""
    r = tuple(sorted(range(len(renaming)), key=renaming.__getitem__)) if back else renaming
    return frozenset((None if a is None else r[a], None if b is None else r[b], p)
                     for a, b, p in views)


def _name(colour: int | None, renaming: Renaming) -> int:
    return -1 if colour is None else renaming[colour]


def _renamed_state(state: State, renaming: Renaming) -> State:
    position, *robots = state
    return cast(State, (position, *((phase, renaming[c], renaming[n], pending)
                                    for phase, c, n, pending in robots)))


@dataclass
class Explored:
    """The states a partial table reaches: per state its known successors and the robots of
    each edge (an open state, which needs a view the table does not give, has those of its
    steps that read no such view), whether it is gathered, and the open states."""

    states: list[State]
    index: dict[State, int]
    edges: list[list[int]]
    masks: list[list[int]]
    gathered: list[bool]
    open: list[int]
    starts: int = 0
    given: frozenset[View] = frozenset()
    """The views of the table explored."""
    fair: list[int] | None = None
    """A fair component of known steps outside the goal, if any (the table is refuted)."""

    @staticmethod
    def of(starts: list[State]) -> Explored:
        graph = Explored([], {}, [], [], [], [], len(starts))
        for state in starts:
            graph.add(state)
        return graph

    def add(self, state: State) -> int:
        self.index[state] = len(self.states)
        self.states.append(state)
        self.edges.append([])
        self.masks.append([])
        self.gathered.append(Rendezvous.goal(state))
        return len(self.states) - 1

    def copy(self) -> Explored:
        """A copy to go on from (a state's lists are replaced when it is stepped again,
        never changed)."""
        return Explored(self.states.copy(), self.index.copy(), self.edges.copy(),
                        self.masks.copy(), self.gathered.copy(), self.open.copy(), self.starts,
                        self.given)


def _fair_outside_goal(graph: Explored, stepped: list[int] | None = None) -> list[int] | None:
    """A strongly connected component of known steps, none of its states gathered, with an
    edge of each robot inside it; None if there is none. ``stepped``: the states stepped
    since a graph that had none (the others' steps unchanged): a new one has one of them,
    so only the states they reach are searched."""
    edges, masks, gathered = graph.edges, graph.masks, graph.gathered
    inside: Callable[[int], bool] = lambda v: not gathered[v]  # noqa: E731
    if stepped is not None:
        reached = {v for v in stepped if not gathered[v]}
        work = list(reached)
        while work:
            for w in edges[work.pop()]:
                if w not in reached and not gathered[w]:
                    reached.add(w)
                    work.append(w)
        inside = reached.__contains__
    for comp in components_of(len(edges), edges.__getitem__, inside):
        members = set(comp)
        robots = 0
        for v in comp:
            for w, mask in zip(edges[v], masks[v], strict=True):
                if w in members:
                    robots |= mask
        if robots == 3:
            return comp
    return None


class Found(GatherVerifyError):
    """The case split met a witness: ``table`` verifies. Cause: control flow of the search,
    never shown to a user (caught by the search that raised it); fix: none needed."""

    def __init__(self, table: dict[View, Answer]):
        super().__init__()
        self.table = dict(table)


class OutOfTime(GatherVerifyError):
    """The case split passed its time budget. Cause: control flow of the search, caught
    where it becomes the answer ``unknown``; fix: a larger --max-seconds."""


@dataclass
class Search:
    """One case split: its setting, deadline, the renamings it may skip by (none: every
    table searched), the renamed tables already searched to the end with no witness, and
    whether it backjumps (:meth:`split`)."""

    setting: Setting
    deadline: float
    renamings: list[Renaming]
    backjump: bool = True
    tables: int = 0
    done: dict[Canon, frozenset[View]] = field(default_factory=dict)
    """Per renamed table searched to the end, the views its failure reads, renamed as the
    table is to its canonical name."""
    failures: dict[tuple[View, Answer], list[tuple[tuple[View, Answer], ...]]] = field(
        default_factory=dict)
    """The answers a refuted table's failure reads (:meth:`Setting.core`), under each of
    them: any table that gives them all is refuted, unexplored."""
    learned: int = 0

    def below(self, table: dict[View, Answer], reached: Explored | None = None,
              last: tuple[View, Answer] | None = None) -> tuple[dict[str, Any], frozenset[View]]:
        """The case split below ``table`` (raises :class:`Found` at a witness) and the views
        its failure reads (every table that answers them as ``table`` does fails);
        ``reached``: what the parent's table reached; ``last``: the answer it added."""
        if time.perf_counter() > self.deadline:
            raise OutOfTime
        canon, renaming = self.setting.least(table, self.renamings) if self.renamings else (
            None, ())
        if canon is not None and canon in self.done:  # its twin's reads, renamed back
            return {"renamed": True}, _renamed_views(self.done[canon], renaming, back=True)
        self.tables += 1
        known = self.known(table, last)
        if known is not None:
            node: dict[str, Any] = {"refuted": True, "reads": _sorted_views(known)}
            core = known
        else:
            refuted, need, graph = self.setting.explore(table, reached)
            if refuted:
                core = self.setting.core(graph, table)
                self.learn(table, core)
                node = {"refuted": True, "reads": _sorted_views(core)}
            elif need is None:
                raise Found(table)
            else:
                node, core = self.split(table, need, graph)
        if canon is not None:
            self.done[canon] = _renamed_views(core, renaming)
        return node, core

    def learn(self, table: dict[View, Answer], reads: frozenset[View]) -> None:
        """Remember the answers a refuted table's failure reads."""
        if self.backjump:
            failure = tuple((view, table[view]) for view in reads)
            for given in failure:
                self.failures.setdefault(given, []).append(failure)

    def known(self, table: dict[View, Answer], last: tuple[View, Answer] | None
              ) -> frozenset[View] | None:
        """The views of a failure remembered by :meth:`learn` that ``table`` gives, with its
        ``last`` answer (the others it gave were no failure), or None."""
        for failure in self.failures.get(last, ()) if last is not None else ():
            if all(table.get(view) == answer for view, answer in failure):
                self.learned += 1
                return frozenset(view for view, _ in failure)
        return None

    def split(self, table: dict[View, Answer], need: View, graph: Explored
              ) -> tuple[dict[str, Any], frozenset[View]]:
        """One child per answer to ``need``. Backjumping: as soon as a child's failure does
        not read ``need``, the table fails whatever ``need`` answers, and the split ends
        there (``"jump": true``; the children before stay, a renamed leaf may stand on
        them)."""
        children: list[dict[str, Any]] = []
        core: set[View] = set()
        for answer in answers(self.setting.colours):
            table[need] = answer
            child, reads = self.below(table, graph, (need, answer))
            del table[need]
            children.append(child)
            if self.backjump and need not in reads:
                return {"view": list(need), "children": children, "jump": True}, reads
            core |= reads - {need}
        return {"view": list(need), "children": children}, frozenset(core)


def algorithm_of(setting: Setting, table: dict[View, Answer], name: str) -> RendezvousAlgorithm:
    """The witness as an algorithm (views no run reaches answer stay, colour 0)."""
    rules = tuple(((v[0], v[1], v[2]), table.get(v, (STAY, 0)))
                  for v in views(setting.colours, setting.lights))
    return RendezvousAlgorithm(name, setting.colours, rules, lights=setting.lights)


def synthesize(colours: int, lights: str, scheduler: str, movement: str = "non-rigid",
               initial_colours: str = "all", max_seconds: float = 600.0,
               symmetry: bool = True, backjump: bool = True) -> dict[str, Any]:
    """``exists`` (with the witness's table, verified by the ordinary check), ``none`` (with a
    certificate) or ``unknown`` (the time ran out). ``symmetry=False`` searches every table,
    renamings included; ``backjump=False`` splits every view over every answer."""
    if lights not in LIGHTS or not 1 <= colours <= 8:
        raise InvalidInput(f"lights {colours}:{lights}: 1 to 8 colours, full, external or "
                           "internal")
    setting = Setting(colours, lights, scheduler, movement, initial_colours)
    phase_model(scheduler)  # an unknown model: one line
    search = Search(setting, time.perf_counter() + max_seconds,
                    setting.renamings() if symmetry else [], backjump)
    head = {"world": "rendezvous", "colours": colours, "lights": lights,
            "scheduler": scheduler, "movement": movement, "initial_colours": initial_colours}
    try:
        tree = search.below({})[0]
    except Found as found:
        witness = algorithm_of(setting, found.table, f"synthesized-{colours}-{lights}")
        check = run_rendezvous_check(witness, scheduler, movement=movement,
                                     initial_colours=initial_colours)
        if check["verdict"] != "VERIFIED":  # pragma: no cover - the search and check agree
            raise AssertionError(f"the witness fails the check: {check['reason']}") from None
        return {**head, "answer": "exists", "tables": search.tables,
                "witness": [[list(v), list(a)] for v, a in sorted(
                    found.table.items(), key=lambda x: [(-1 if y is None else y) for y in x[0]])],
                "witness_verdict": check["verdict"]}
    except OutOfTime:
        return {**head, "answer": "unknown", "reason": f"time ({max_seconds:g} s)",
                "tables": search.tables}
    return {**head, "answer": "none", "tables": search.tables,
            "certificate": {**head, "tree": tree}}


def verify(certificate: dict[str, Any]) -> bool:
    """Whether a ``none`` certificate holds: every inner node splits on one view over every
    answer, or (``jump``) over the first answers up to one whose subtree's failure does not
    read the view (the views a failure reads are worked out here again, from the refuted
    leaves up); every ``refuted`` leaf's partial table is refuted (a fair run that never
    gathers), and every ``renamed`` leaf's table is a renaming (one that keeps the initial
    states) of a table whose subtree, earlier in the tree, already holds (its failure reads
    what that subtree's reads, renamed)."""
    try:
        setting = Setting(certificate["colours"], certificate["lights"],
                          certificate["scheduler"], certificate["movement"],
                          certificate["initial_colours"])
        assert type(setting.colours) is int and 1 <= setting.colours <= 8
        assert setting.lights in LIGHTS and setting.movement in MOVEMENTS
        assert setting.initial_colours in INITIAL_COLOURS
        phase_model(str(setting.scheduler))
        renamings = setting.renamings()
    except (KeyError, TypeError, AssertionError):
        raise InvalidInput("bad certificate: a rendezvous certificate names colours (1 to 8), "
                           "lights, scheduler, movement and initial_colours") from None
    try:
        return _Verifier(setting, renamings).holds(certificate.get("tree"), {}) is not None
    except (TypeError, ValueError, RecursionError):
        return False  # a tree that is no case split holds nothing


@dataclass
class _Verifier:
    """A certificate's tree read against its setting: :meth:`holds` gives the views a
    node's failure reads, or None where the node does not hold."""

    setting: Setting
    renamings: list[Renaming]
    done: dict[Canon, frozenset[View]] = field(default_factory=dict)

    def holds(self, node: Any, table: dict[View, Answer]) -> frozenset[View] | None:
        if not isinstance(node, dict):
            return None
        canon, renaming = self.setting.least(table, self.renamings)
        if node.get("renamed") is True:
            twin = self.done.get(canon)
            return None if twin is None else _renamed_views(twin, renaming, back=True)
        if node.get("refuted") is True:
            reads = self.refuted(node, table)
        else:
            reads = self.split(node, table)
        if reads is not None:
            self.done[canon] = _renamed_views(reads, renaming)
        return reads

    def refuted(self, node: dict[str, Any], table: dict[View, Answer]) -> frozenset[View] | None:
        """A refuted leaf: the table answering only the views the leaf says its failure
        reads (all of them, if it says none) is refuted, so every table that answers them
        alike is."""
        if "reads" not in node:
            refuted, _, graph = self.setting.explore(table)
            return self.setting.core(graph, table) if refuted else None
        reads = frozenset(tuple(v) for v in node["reads"])
        if not reads <= table.keys():
            return None
        return reads if self.setting.explore({v: table[v] for v in reads})[0] else None

    def view(self, node: dict[str, Any], table: dict[View, Answer]) -> View | None:
        """The node's view, if it is one of the setting's and the table does not answer it."""
        view = tuple(node.get("view", ()))
        known = view in views(self.setting.colours, self.setting.lights)
        return cast(View, view) if known and view not in table else None

    def split(self, node: dict[str, Any], table: dict[View, Answer]) -> frozenset[View] | None:
        """Every answer's child holds; or (``jump``) the children hold up to one whose
        failure does not read the view, which then stands for every answer."""
        view, children = self.view(node, table), node.get("children")
        jump, every = node.get("jump") is True, answers(self.setting.colours)
        if view is None or not isinstance(children, list) or not (
                1 <= len(children) <= len(every) if jump else len(children) == len(every)):
            return None
        reads: set[View] = set()
        below: frozenset[View] | None = None
        for answer, child in zip(every, children, strict=False):
            table[view] = answer
            below = self.holds(child, table)
            del table[view]
            if below is None:
                return None
            reads |= below - {view}
        if jump:
            return below if below is not None and view not in below else None
        return frozenset(reads)
