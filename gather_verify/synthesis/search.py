"""The search for an algorithm: counterexample-guided, with a SAT solver proposing tables
(SEMANTICS.md §12).

An algorithm is a table: one option per view (:mod:`gather_verify.synthesis.views`). A
Boolean variable says "view k takes option o"; exactly one holds per view. The loop:

1. the solver proposes a table (views not met yet take their first option);
2. the ordinary search (:func:`~gather_verify.engine.world_search.search`) explores every
   execution of that table from each initial configuration and the task's tests judge them:
   the safety parts as states are expanded (the search stops soon after the first
   violation), the liveness parts with every reduction off (§5, §11), in stages: a fair
   component among the first states is one of the whole space (:func:`staged`). A start
   a recent candidate passed with the same answers on the views it read is skipped;
3. all pass: the table is the witness (``exists``). A part fails: its counterexample is
   replayed (:func:`~gather_verify.synthesis.certificate.replay`) into the literals it
   relies on, and the clause "not all of these" is added. Every table with those literals
   has that execution, so no algorithm that works is ever excluded;
4. no table is left (the solver says unsatisfiable): ``none``, and the clauses become the
   certificate's decision tree, or where that outgrows ``max_tree`` nodes, a resolution
   proof (:mod:`~gather_verify.synthesis.refute`).

A limit (time, candidates, states of one exploration) stops the loop with ``unknown``,
naming it; a truncated search never answers ``none``.

The solver is CaDiCaL through python-sat (``pip install 'gather-verify[synth]'``): an
incremental CDCL solver, so the clauses it learns survive from one candidate to the next.

The time budget holds everywhere (:func:`budget`): CaDiCaL ignores ``interrupt()``, so each
call runs in slices of :data:`SAT_SLICE` conflicts with the clock read between them
(:func:`solve_within`), and the watchdog's alarm ends whatever else runs past the budget
(an exploration's graph analyses, clause building, the certificate's tree) with ``unknown``.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import Any

from gather_verify.engine.encoding import DEFAULT_MAX_MEMORY_MB, Limits, Stop
from gather_verify.engine.world_search import Halt, WorldSearch, search
from gather_verify.errors import InvalidInput
from gather_verify.synthesis.certificate import (
    LIVENESS,
    SAFETY_FINAL,
    TreeTooLarge,
    apply_event,
    build_tree,
    event_from_json,
    event_to_json,
    prune,
    replay,
    tree_size,
)
from gather_verify.synthesis.lift import rungs
from gather_verify.synthesis.refute import Refutation, refutation
from gather_verify.synthesis.restart import restart
from gather_verify.synthesis.views import Instance, Views
from gather_verify.tasks import Context, Finding
from gather_verify.tasks.base import components, fair
from gather_verify.watchdog import OverMemory, Overtime, deadline, watched

DEFAULT_MAX_SECONDS = 600.0
DEFAULT_MAX_CANDIDATES = 1_000_000
DEFAULT_MAX_STATES = 2_000_000
DEFAULT_MAX_TREE = 100_000
"""Nodes of a certificate's decision tree, past which it is a resolution proof instead
(measured: six robots on ring:11 under SSYNC, 14,455 counterexamples, reach 2,000,000 nodes in
150 s and no tree below 10,000,000; their proof takes 10 s to find and 37 s to trim, and a
tree this large is no more readable than a proof)."""
SAT_SLICE = 10_000
"""Conflicts of one slice of a SAT call: the clock is read between slices (CaDiCaL, as
python-sat ships it, ignores ``interrupt()``). A call that ends within its first slice is
the same call as one without a limit."""
CUT_GRACE = 1.0
"""Seconds past the budget at which the watchdog's alarm cuts the search (its own clock
checks end it first, at the budget)."""
TIME_LIMIT = "max-seconds"


def solve_within(solver: Any, until: float, assumptions: Sequence[int] = ()) -> bool | None:
    """``solver.solve()`` (under ``assumptions``), in slices of :data:`SAT_SLICE` conflicts
    until ``until`` (a ``time.perf_counter()`` value) has passed: True (a model), False
    (unsatisfiable), or None (the time ran out first)."""
    while True:
        solver.conf_budget(SAT_SLICE)
        got = solver.solve_limited(assumptions=list(assumptions))
        if got is not None:
            return bool(got)
        if time.perf_counter() >= until:
            return None


@contextmanager
def budget(seconds: float) -> Iterator[None]:
    """The block is cut by :class:`~gather_verify.watchdog.Overtime` once ``seconds`` plus
    :data:`CUT_GRACE` have passed, wherever it is (not only in the user's code): the
    caller catches it and answers ``unknown`` (max-seconds). Objects the block was filling
    may be left half done, so the caller drops them. Where no alarm can be armed (off the
    main thread, Windows), only the clock checks hold the budget."""
    with deadline(seconds + CUT_GRACE), watched():
        yield


@dataclass
class Result:
    """The answer (exists, none, unknown) and what backs it."""

    answer: str
    views: int
    candidates: int
    seconds: float
    limit: str | None = None
    table: dict[int, int] = field(default_factory=dict)
    counterexamples: list[dict[str, Any]] = field(default_factory=list)
    literals: list[dict[int, int]] = field(default_factory=list)
    tree: Any = None
    """The certificate's decision tree, or its :class:`~.refute.Refutation`."""
    states: int = 0
    """States explored, over every candidate."""
    one_mover: str | None = None
    """How the first phase (one class of movers, :class:`_Search`) ended: ``witness``,
    ``exhausted``, ``time``, ``running`` (a limit stopped the search during it), or None
    when there was none."""
    one_robot: str | None = None
    """How the first phase's first step (one robot moves, :class:`_Search`) ended, in the
    same words."""


def solver_class() -> Callable[..., Any]:
    try:
        from pysat.solvers import Solver
    except ImportError:
        raise InvalidInput("synthesize needs python-sat: pip install 'gather-verify[synth]'"
                           ) from None
    return Solver


def synthesize(inst: Instance, *, max_seconds: float = DEFAULT_MAX_SECONDS,
               max_candidates: int = DEFAULT_MAX_CANDIDATES,
               max_states: int = DEFAULT_MAX_STATES, max_tree: int = DEFAULT_MAX_TREE,
               views: Views | None = None, seeds: Sequence[Any] = (), ladder: bool = True,
               parts: Sequence[tuple[Instance, Views]] | None = None,
               max_memory_mb: float = DEFAULT_MAX_MEMORY_MB,
               one_mover: bool | None = None) -> Result:
    """Search for a table that solves ``inst`` from every initial configuration.

    ``ladder``: judge each candidate under the cheaper adversaries first (FSYNC, then SSYNC,
    then the instance's own, :func:`~gather_verify.synthesis.lift.rungs`); a counterexample
    found there is one under the instance's scheduler too (:mod:`.lift`). ``seeds``:
    algorithms whose answers the solver tries first on each view (a phase, never a
    constraint). ``parts``: several instances (one per ring size) whose views share one table
    of keys (the gap rules of :mod:`~gather_verify.synthesis.gapviews`): one table must solve
    every one; their counterexamples name their part. ``one_mover``: propose first the tables
    in which one robot moves per configuration, then those in which one class of robots does
    (:class:`_Search`), then any (None: :data:`ONE_MOVER`)."""
    views = views or Views(inst)
    run = _Search(list(parts) if parts else [(inst, views)], seeds, ladder,
                  (max_seconds, max_candidates, max_states, max_tree, max_memory_mb),
                  ONE_MOVER if one_mover is None else one_mover)
    try:
        with budget(max_seconds):
            return run.loop()
    except Overtime:
        return run.result("unknown", f"{TIME_LIMIT} (cut by the watchdog)")
    except OverMemory:  # the command's memory watch (engine.bounds.setup): keep the counts
        return run.result("unknown", f"memory (the search over algorithms: past "
                          f"{max_memory_mb:g} MB)")


class _Search:
    """One run of the loop of :func:`synthesize`: the solver, its variables (per view of the
    shared table, one per option), the counterexamples and their clauses.

    With ``one_mover``, the search has two phases. In the first, the solver proposes only
    tables in which, in every configuration met so far, the robots that leave their node all
    have one view (one robot, or one symmetric class of them: the shape of most of the
    field's algorithms, and one under which the adversaries differ least): per pair of
    distinct views of one configuration, "one of the two stays". Its first step asks more:
    one robot, so a view that two robots of its configuration hold (twins across an axis, or
    a tower) stays. When one robot moves per configuration (and the robots have no lights,
    whose changes are not moves), the robots act one at a time whatever the adversary, so a
    table that solves the task under FSYNC solves it under SSYNC and ASYNC too: the step
    finds asynchronous algorithms at the cost of synchronous ones. Each restriction's
    clauses are guarded by a variable of :attr:`gates` that the solver assumes true; the
    clauses of counterexamples hold for every table, so they stay.
    When a step's tables are exhausted (unsatisfiable under the assumptions), or after its
    share of the time (:data:`ONE_ROBOT_SHARE`, :data:`ONE_MOVER_SHARE`), its variable is
    set false and the search goes on with the next: only the second phase, over every
    table, ever answers ``none``. A witness of any step is checked as any other."""

    def __init__(self, parts: list[tuple[Instance, Views]], seeds: Sequence[Any],
                 ladder: bool, limits: tuple[float, int, int, int, float],
                 one_mover: bool = False):
        self.started = time.perf_counter()
        self.parts = parts
        self.views = parts[0][1]  # every part's views share its table of keys
        self.solver = solver_class()(name="cadical153")
        self.base: list[int] = []  # per view: its first variable - 1
        self.gates = dict(zip(STEPS, (1, 2), strict=True)) if one_mover else {}
        """The first phase's steps still running, strictest first, and their variables."""
        self.ended: dict[str, str] = dict.fromkeys(self.gates, "running")
        """How each step of the first phase ended (``running`` until it does)."""
        self.movers_done = self.crowded_done = 0  # views.movers, views.crowded restricted
        self.total = len(self.gates)
        self.seeds = [_SeedMoves(seed) for seed in seeds]
        self.phases: list[int] = []
        target = parts[0][0].scheduler
        colours = parts[0][0].lights.colours
        self.rungs = rungs(target, colours) if ladder else [target]
        self.insts = [{r: replace(inst, scheduler=r) for r in self.rungs} for inst, _ in parts]
        self.order = [(p, i) for p, (inst, _) in enumerate(parts)
                      for i in range(len(inst.configurations))]
        self.cexs: list[dict[str, Any]] = []
        self.clauses: list[dict[int, int]] = []
        self.passes: dict[tuple[int, int, str], list[tuple[tuple[int, int], ...]]] = {}
        """Per (part, start, rung): the answers of the views that recent passing
        explorations read (:meth:`passed`)."""
        self.candidates = self.explored = 0
        self.limits = limits  # seconds, candidates, states, tree nodes, memory (MB)

    def result(self, answer: str, limit: str | None = None, **more: Any) -> Result:
        self.solver.delete()
        if answer == "exists":  # every running step's tables hold the witness
            self.ended.update(dict.fromkeys(self.gates, "witness"))
        return Result(answer, len(self.views.texts), self.candidates,
                      time.perf_counter() - self.started, limit, counterexamples=self.cexs,
                      literals=self.clauses, states=self.explored,
                      one_mover=self.ended.get("one class"),
                      one_robot=self.ended.get("one robot"), **more)

    def register(self) -> None:
        """Variables for every view met so far: one per option, exactly one true; the seeds'
        answers as the solver's phases."""
        views = self.views
        while len(self.base) < len(views.texts):
            j = len(self.base)
            count = len(views.options[j])
            self.base.append(self.total)
            self.total += count
            xs = [self.base[j] + o + 1 for o in range(count)]
            self.solver.add_clause(xs)
            for a in range(count):
                for b in range(a + 1, count):
                    self.solver.add_clause([-xs[a], -xs[b]])
            if self.seeds:
                want = self.preferred(j)
                self.phases += [x if o == want else -x for o, x in enumerate(xs)]
        if self.seeds:
            self.solver.set_phases(self.phases)
        if self.gates:
            self.restrict()

    def stays(self, k: int) -> list[int]:
        """The literals of view ``k``'s options that leave its robot on its node."""
        return [self.base[k] + o + 1 for o in self.views.still[k]]

    def restrict(self) -> None:
        """The first phase's clauses for the configurations met since the last call: of two
        distinct views of one configuration, one stays; in the first step, a view two robots
        hold stays too (:class:`_Search`)."""
        views = self.views
        one_class, one_robot = self.gates["one class"], self.gates.get("one robot")
        for keys in views.movers[self.movers_done:]:
            stays = [self.stays(k) for k in keys]
            for a in range(len(keys)):
                for b in range(a + 1, len(keys)):
                    self.solver.add_clause([-one_class, *stays[a], *stays[b]])
        self.movers_done = len(views.movers)
        if one_robot:
            for k in views.crowded[self.crowded_done:]:
                self.solver.add_clause([-one_robot, *self.stays(k)])
        self.crowded_done = len(views.crowded)

    def share(self) -> float:
        """The share of the time budget the current step may take (1 past the first phase)."""
        if not self.gates:
            return 1.0
        return ONE_ROBOT_SHARE if "one robot" in self.gates else ONE_MOVER_SHARE

    def end_step(self, why: str) -> None:
        """The first phase's current step is over (``why``: exhausted, time): the next
        step's tables, or every table, from now on."""
        step = next(iter(self.gates))
        self.solver.add_clause([-self.gates.pop(step)])
        self.ended[step] = why

    def preferred(self, k: int) -> int:
        """The option of view ``k`` that the first seed with an answer there gives (0: none)."""
        p, seen, node, colour = self.views.first[k]
        inst, views = self.parts[p]
        _, acts = views.occurrence(seen, node, colour)
        for seed in self.seeds:
            wanted = seed.actions(inst, seen, node, colour)
            if wanted in acts:
                return acts.index(wanted)
        return 0

    def loop(self) -> Result:
        max_seconds, max_candidates, _, max_tree, _ = self.limits
        views = self.views
        while True:
            if time.perf_counter() - self.started > max_seconds:
                return self.result("unknown", "max-seconds")
            if self.candidates >= max_candidates:
                return self.result("unknown", "max-candidates")
            self.register()
            end = self.started + max_seconds * self.share()
            if self.gates and time.perf_counter() >= end:
                self.end_step("time")
                continue
            sat = solve_within(self.solver, end, list(self.gates.values()))
            if sat is not True and self.gates:
                self.end_step("time" if sat is None else "exhausted")
                continue
            if sat is None:
                return self.result("unknown", f"{TIME_LIMIT} (during the SAT solver's call)")
            if not sat:
                return self.refuted(max_tree)
            model = self.solver.get_model() or []
            choice = Table({k: o for k, first in enumerate(self.base)
                            for o in range(len(views.options[k])) if model[first + o] > 0},
                           self.preferred if self.seeds else None)
            self.candidates += 1
            reached: set[int] = set()
            failed = self.judge(choice, reached)
            if isinstance(failed, str):
                return self.result("unknown", failed)
            if failed is None:
                return self.result("exists",
                                   table={k: choice[k] for k in sorted(reached)})
            self.learn(choice, *failed)

    def refuted(self, max_tree: int) -> Result:
        """``none``, with its certificate: the decision tree, or where that outgrows
        ``max_tree`` nodes, a resolution proof (:mod:`.refute`) and the counterexamples it
        uses; ``unknown`` (max-tree) when neither comes within the time left."""
        options = [len(o) for o in self.views.options]
        try:
            tree, kept = prune(build_tree(self.clauses, options, max_tree), self.clauses)
        except TreeTooLarge:
            pass
        else:
            self.cexs = [self.cexs[j] for j in kept]
            self.clauses = [self.clauses[j] for j in kept]
            return self.result("none", tree=tree)
        left = self.limits[0] - (time.perf_counter() - self.started)
        got = refutation(self.clauses, options, max(left, 0.001))
        if got is None:
            return self.result("unknown", "max-tree (the certificate's decision tree outgrew "
                               "it, and no resolution proof came in the time left)")
        kept, proof = got
        self.cexs = [self.cexs[j] for j in kept]
        self.clauses = [self.clauses[j] for j in kept]
        return self.result("none", tree=proof)

    def judge(self, choice: dict[int, int], reached: set[int]
              ) -> tuple[int, int, str, WorldSearch, list[Finding]] | str | None:
        """The candidate from every configuration of every part, under each rung of the
        ladder in turn: the first failure (part, configuration, rung, search, findings),
        a limit's name, or None when it solves them all."""
        max_seconds, _, max_states, _, max_memory_mb = self.limits
        for rung in self.rungs:
            for p, idx in self.order:
                passes = self.passes.setdefault((p, idx, rung), [])
                if self.passed(choice, passes, reached):
                    continue
                left = max_seconds - (time.perf_counter() - self.started)
                read: set[int] = set()
                s, findings = explore(self.insts[p][rung], self.parts[p][1], choice, idx,
                                      read, Limits(max_states=max_states,
                                                   max_seconds=max(left, 0.001),
                                                   max_memory_mb=max_memory_mb))
                reached |= read
                self.explored += s.states
                if s.stopped is not None:
                    return {"time": "max-seconds", "states": "max-states",
                            "memory": "memory"}.get(s.stopped, s.stopped)
                if findings:
                    self.order.remove((p, idx))
                    self.order.insert(0, (p, idx))
                    return p, idx, rung, s, findings
                if s.complete:
                    passes.insert(0, tuple((k, choice[k]) for k in sorted(read)))
                    del passes[PASSES:]
        return None

    @staticmethod
    def passed(choice: dict[int, int], passes: list[tuple[tuple[int, int], ...]],
               reached: set[int]) -> bool:
        """Whether ``choice`` answers as one of ``passes`` (the answers an earlier candidate's
        passing exploration of this start read, most recent first) on every view it read:
        its exploration would be that one, step for step, so it passes too; its views count
        as reached (the witness's table holds them)."""
        for j, reads in enumerate(passes):
            if all(choice[k] == o for k, o in reads):
                passes.insert(0, passes.pop(j))
                reached.update(k for k, _ in reads)
                return True
        return False

    def learn(self, choice: dict[int, int], p: int, idx: int, rung: str, s: WorldSearch,
              findings: list[Finding]) -> None:
        """Each finding as a counterexample and its clause: "not all of these options"."""
        inst, views = self.insts[p][rung], self.parts[p][1]
        target = self.parts[p][0].scheduler
        known = {frozenset(c.items()) for c in self.clauses[-len(findings) * 4:]}
        for finding in findings:
            cex = restart(inst, counterexample(inst, views, choice, idx, s, finding))
            if inst.task.visits and "loop" in cex:
                unroll(inst, cex)
            if rung != target:
                cex["scheduler"] = rung  # the adversary it was found under (lift.py)
            if len(self.parts) > 1:
                cex["part"] = p
            lits = replay(views, cex).literals  # the clause is what the replay shows
            self.register()
            if not all(choice[k] == o for k, o in lits.items()):  # pragma: no cover
                raise AssertionError("a counterexample that the candidate does not have")
            if frozenset(lits.items()) in known:
                continue
            known.add(frozenset(lits.items()))
            self.cexs.append(cex)
            self.clauses.append(lits)
            self.solver.add_clause([-(self.base[k] + o + 1) for k, o in sorted(lits.items())])


class Table(dict[int, int]):
    """A candidate: view -> option. A view the exploration meets for the first time takes
    ``fresh``'s option (the first seed's answer there; option 0 without seeds), and keeps it
    for the rest of the candidate's check."""

    def __init__(self, chosen: dict[int, int], fresh: Callable[[int], int] | None = None):
        super().__init__(chosen)
        self.fresh = fresh

    def __missing__(self, k: int) -> int:
        o = self[k] = 0 if self.fresh is None else self.fresh(k)
        return o


class _SeedMoves:
    """A seed algorithm's actions at an occurrence (None where it has no rule or crashes):
    the option the solver tries first there."""

    def __init__(self, algorithm: Any):
        self.algorithm = algorithm
        self.moves: dict[int, Any] = {}

    def actions(self, inst: Instance, seen: Any, node: int, colour: int) -> frozenset | None:
        from gather_verify.worlds.moves import WorldMoves

        moves = self.moves.get(id(inst.world))
        if moves is None:
            moves = self.moves[id(inst.world)] = WorldMoves(
                inst.world, self.algorithm, inst.meeting, inst.detection, inst.frames,
                inst.visibility, inst.lights)
        try:
            return moves.table(seen)[node, colour]
        except Exception:  # no rule there, a hidden read or a crash: the seed has no say
            return None


def explore(inst: Instance, views: Views, choice: dict[int, int], idx: int,
            reached: set[int], limits: Limits) -> tuple[WorldSearch, list[Finding]]:
    """Every execution of the table ``choice`` from configuration ``idx``, and the task's
    violations there: a few of its safety parts (the search stops soon after the first),
    else its first liveness failure (unreduced); none when it holds. The liveness parts are
    looked for in stages (:func:`staged`): a fair component among the first states of the
    breadth-first search is one of the whole space."""
    robots, colours = inst.configurations[idx]

    def actions(state: tuple[tuple[int, int | None, int], ...]) -> list[frozenset]:
        out = []
        for k, acts in views.robots(state):
            reached.add(k)
            out.append(acts[choice[k]])
        return out

    w = inst.world
    ctx = Context(len(robots), w.size, inst.meeting, inst.scheduler,
                  tuple(w.format_node(v) for v in range(w.size)))

    def plain(watched: bool) -> Callable[[Limits], tuple[WorldSearch, list[Halt]]]:
        def run(lim: Limits) -> tuple[WorldSearch, list[Halt]]:
            found: list[Halt] = []
            return search(w, robots, actions, inst.scheduler, colours=colours, limits=lim,
                          watch=watcher(inst, found) if watched else None), found
        return run

    def termination(s: WorldSearch) -> list[Finding]:
        return livelocks(s, ctx, "termination")

    if inst.task.visits:
        # termination first, on the states without the visited set (measured: fewer
        # candidates, as its counterexamples name the views of the moves that matter); then
        # the safety part, on the reduced states (sound for safety, §4: a
        # BFS parent's stored state is the concrete predecessor, so the path is a concrete
        # run), stopping at the first final state that has not seen every node. Under
        # round-robin too: the search relabels identical robots as the scheduler says (its
        # order made the first start) and the symmetries leave its order and turn alone, as
        # the checker reduces; the path then runs from that first start, a real start the
        # counterexample names
        s, _, loops = staged(plain(False), limits, termination)
        if loops or not s.complete:
            return s, loops
        found: list[Halt] = []
        s = search(w, robots, actions, inst.scheduler, colours=colours, visits=True,
                   limits=limits, watch=watcher(inst, found), anonymity=True,
                   symmetries=w.symmetries(inst.frames), meeting=inst.meeting)
        if not found:
            return s, []
    else:
        def liveness(s: WorldSearch) -> list[Finding]:
            return termination(s) if "termination" in inst.task.parts else exploring(s, ctx)

        s, found, loops = staged(plain(True), limits, liveness)
        if loops:
            return s, loops
    if found:
        if s.stopped == "watch":
            s.stopped, s.halt = None, None  # violations, not a limit
        return s, [Finding(h.property, h.state, h.reason,
                           edge=None if h.detail.get("edge") is None else
                           (h.state, h.detail["edge"]))  # type: ignore[arg-type]
                   for h in found]
    if s.halt is not None:  # pragma: no cover - a table answers every view
        raise AssertionError(f"a table halted the search: {s.halt.reason}")
    return s, []


def staged(run: Callable[[Limits], tuple[WorldSearch, list[Halt]]], limits: Limits,
           liveness: Callable[[WorldSearch], list[Finding]]
           ) -> tuple[WorldSearch, list[Halt], list[Finding]]:
    """``run`` (a search, and the safety violations its watch found) within
    :data:`STAGE_STATES` states, then :data:`STAGE_GROWTH` times as many, and so on up to
    ``limits``; after each stage its liveness failures (``liveness``). A stage cut by its own
    bound is a prefix of the whole breadth-first search, and a fair component of its expanded
    states is a fair component's worth of the whole space (the same states, edges and stays;
    a run can stay in it for ever), so its failure is one of the table. Most candidates fail
    near their start: they are refuted at a fraction of the whole space's cost; one that
    holds pays its earlier stages (at most 1 / (growth - 1) more). Returns the deciding
    search (``stopped`` None when a stage's bound cut it and a failure was found), the
    watch's violations and the liveness failures (those of the complete search, or none
    after a limit)."""
    started = time.perf_counter()
    bound = STAGE_STATES
    while True:
        last = bound >= limits.max_states
        left = max(limits.max_seconds - (time.perf_counter() - started), 0.001)
        s, found = run(replace(limits, max_seconds=left) if last else
                       replace(limits, max_states=bound, max_seconds=left))
        if found and s.stopped == Stop.STATES and not last:
            s.stopped = Stop.WATCH  # the stage's bound, not a limit: its violations stand
        if last or found or s.stopped != Stop.STATES:
            return s, found, liveness(s) if s.complete and not found else []
        loops = liveness(s)
        if loops:
            s.stopped = None  # the stage's bound, not a limit: its failure stands
            return s, found, loops
        bound *= STAGE_GROWTH


def exploring(s: WorldSearch, ctx: Context) -> list[Finding]:
    """Perpetual exploration's failures: per node, a fair component where it stays empty
    (as the task checks it)."""
    out: list[Finding] = []
    for v in range(ctx.size):
        out += livelocks(s, ctx, "perpetual-exploration", v)
        if len(out) >= LIVENESS_FINDINGS:
            break
    return out[:LIVENESS_FINDINGS]


def livelocks(s: WorldSearch, ctx: Context, prop: str, node: int | None = None
              ) -> list[Finding]:
    """Up to :data:`LIVENESS_FINDINGS` fair components (§5's test, as
    :func:`~gather_verify.tasks.base.livelock` runs it): for ``termination``, those with
    an edge between distinct states and no final state; for ``perpetual-exploration``,
    those inside the states where ``node`` is empty (one state is enough)."""
    out = []
    if node is None:
        inside = None
    else:
        def inside(sid: int) -> bool:
            return all(u != node for u, *_ in s.keys[sid][0])
    for comp in components(s, inside):
        if node is None and (len(comp) == 1 or any(s.final[v] for v in comp)):
            continue
        if fair(s, comp, ctx.n):
            f = Finding(prop, min(comp), "a fair execution never ends" if node is None else
                        f"a fair execution stops visiting node {ctx.names[node]}")
            if node is not None:
                f.detail["node"] = node
            out.append(f)
            if len(out) >= LIVENESS_FINDINGS:
                break
    return out


ONE_MOVER = True
"""Whether :func:`synthesize` runs its first phase (one class of movers) by default."""
ONE_ROBOT_SHARE = 0.25
"""The share of the time budget the first phase's first step (one robot) may take before
the search goes on with the second (one class)."""
ONE_MOVER_SHARE = 0.5
"""The share of the time budget the first phase may take before the search goes on over
every table."""
STEPS = ("one robot", "one class")
"""The first phase's steps, strictest first (:class:`_Search`)."""
PASSES = 8
"""Passing explorations remembered per start and rung (:meth:`_Search.passed`)."""
STAGE_STATES = 200
"""States of the first stage of a candidate's exploration (:func:`staged`)."""
STAGE_GROWTH = 8
"""Each stage of :func:`staged` is this many times the one before."""
SAFETY_FINDINGS = 8
"""Safety violations collected from one exploration (one clause each)."""
LIVENESS_FINDINGS = 1
"""Fair components taken from one exploration (measured: more of them, each with its long
path and cycle, sends the solver astray more often than it helps)."""


def watcher(inst: Instance, found: list[Halt]) -> Callable[..., Halt | None]:
    """The task's safety parts, tested on each state as the search expands it (the same
    tests as :mod:`gather_verify.tasks`; the liveness parts wait for the whole space). Each
    violation goes to ``found``; the search stops at the eighth, or once it has expanded
    twice as many states as it had at the first."""
    first = [0]

    def watch(sid: int, key: Any, final: bool, out: list[Any]) -> Halt | None:
        got = test(sid, key, final, out)
        if got is not None:
            if not found:
                first[0] = sid
            found.append(got)
            if len(found) >= SAFETY_FINDINGS:
                return got
        if found and sid > 2 * first[0] + 100:
            return found[-1]
        return None

    name = inst.task.name
    meeting = inst.meeting
    everything = (1 << inst.world.size) - 1

    def test(sid: int, key: Any, final: bool, out: list[Any]) -> Halt | None:
        robots = key[0]
        nodes = [v for v, _, _ in robots]
        if name == "exclusive-perpetual-exploration":
            if len(set(nodes)) < len(nodes):
                return Halt("exclusivity", sid, "two robots on one node")
            for k, (_, _, event) in enumerate(out):
                if event.kind == "round":
                    crossing = {(a, b) for _, a, b in event.moves}
                    if any((b, a) in crossing for a, b in crossing):
                        return Halt("exclusivity", sid, "two robots cross one edge",
                                    {"edge": k})
            return None
        if not final:
            return None
        if name == "exploration-with-stop":
            if key[1] != everything:
                return Halt("explored-when-final", sid, "stopped before every node was seen")
            return None
        if len(set(nodes)) > 1:
            return Halt(inst.task.parts[0], sid, "deadlock")
        if name == "gathering-on-meeting-nodes" and nodes[0] not in meeting:
            return Halt("final", sid, "gathered off the meeting nodes")
        return None

    return watch


# -- from a finding to a counterexample ----------------------------------------------------

def counterexample(inst: Instance, views: Views, choice: dict[int, int], idx: int,
                   s: WorldSearch, f: Finding) -> dict[str, Any]:
    """The finding as a counterexample: the path's events, and for a liveness part a cycle
    through the failing component that every robot acts on or may stay in (so it is fair in
    every table that has its literals)."""
    w = inst.world
    out: dict[str, Any] = {"configuration": idx, "property": f.property}
    if f.property in LIVENESS:
        inside = None
        if f.property == "perpetual-exploration":
            node = f.detail["node"]
            out["node"] = w.node_to_json(node)  # type: ignore[arg-type]
            inside = (lambda sid: all(u != node for u, *_ in s.keys[sid][0]))  # noqa: E731
        comp = next(c for c in components(s, inside) if f.state in c)
        walk, stays, busy = fair_cycle(inst, views, choice, s, comp, f.state)
        path = s.path_to(f.state)
        out["loop"] = len(path) - 1
        ids = path + walk[1:]
        out["stays"] = [[out["loop"] + j, i] for j, i in stays]
        if busy:
            out["busy"] = [[out["loop"] + j, i, w.node_to_json(d), c] for j, i, d, c in busy]
    else:
        ids = s.path_to(f.state)
        out["final"] = f.property in SAFETY_FINAL
    events = [_event(s, a, b) for a, b in zip(ids, ids[1:], strict=False)]
    if f.edge is not None:
        src, k = f.edge
        events.append(s.edges[src][k][2])
    start: Any = s.keys[ids[0]][2]  # the scheduler's own state: round-robin's (order, turn)
    out["start"] = None if start is None else [list(start[0]), start[1]]
    out["events"] = [event_to_json(w, e) for e in events]
    if inst.task.visits and f.property in LIVENESS:
        unroll(inst, out)
    return out


def unroll(inst: Instance, cex: dict[str, Any]) -> None:
    """A cycle found without the visited nodes, repeated until the visited set comes back
    to itself (it only grows, so within as many rounds as there are nodes): the stays and
    busy robots move to the last round."""
    w = inst.world
    robots0, colours0 = inst.configurations[cex["configuration"]]
    state: tuple[tuple[int, int | None, int], ...] = tuple(
        (v, None, c) for v, c in zip(robots0, colours0, strict=True))
    visited = [_bits(robots0)]
    events = [event_from_json(w, e) for e in cex["events"]]
    for e in events:
        state = apply_event(state, e)
        visited.append(visited[-1] | _bits(v for v, _, _ in state))
    loop = cex["loop"]
    cycle = cex["events"][loop:]
    while cycle and visited[-1] != visited[loop]:
        shift = len(cex["events"]) - loop
        for raw in cycle:
            state = apply_event(state, event_from_json(w, raw))
            visited.append(visited[-1] | _bits(v for v, _, _ in state))
        cex["events"] = cex["events"] + cycle
        cex["stays"] = [[j + shift, i] for j, i in cex["stays"]]
        if "busy" in cex:
            cex["busy"] = [[j + shift, *rest] for j, *rest in cex["busy"]]
        loop += shift
    cex["loop"] = loop


def _bits(nodes: Any) -> int:
    bits = 0
    for v in nodes:
        bits |= 1 << v
    return bits


def _event(s: WorldSearch, a: int, b: int) -> Any:
    for target, _, event in s.edges[a]:
        if target == b:
            return event
    raise AssertionError(f"no edge {a} -> {b}")  # pragma: no cover


def fair_cycle(inst: Instance, views: Views, choice: dict[int, int], s: WorldSearch,
               comp: list[int], entry: int
               ) -> tuple[list[int], list[tuple[int, int]], list[tuple[int, int, int, int]]]:
    """A closed walk from ``entry`` inside ``comp`` (state ids, first = last) on which every
    robot acts or is idle where it may stay; the stays used, as (position on the walk,
    robot); for round-robin, a robot with a move in each state where the walk only stays
    (that state is not final)."""
    members = set(comp)
    n = len(s.keys[entry][0])
    walk = [entry]
    stays: list[tuple[int, int]] = []
    covered = 0
    full = (1 << n) - 1

    def take_stays() -> None:
        nonlocal covered
        here = walk[-1]
        for i in range(n):
            if not covered >> i & 1 and s.stay[here] >> i & 1:
                stays.append((len(walk) - 1, i))
                covered |= 1 << i

    def path(src: int, goal: Callable[[int, int, int], bool]) -> list[tuple[int, int]] | None:
        """Shortest (target, robots) steps inside comp from src to an edge that ``goal``
        accepts (goal(source, target, robots)); the last step is that edge."""
        parent: dict[int, tuple[int, int, int] | None] = {src: None}
        queue = [src]
        for v in queue:
            for t, robots, _ in s.edges[v]:
                if t not in members:
                    continue
                if goal(v, t, robots):
                    steps = [(t, robots)]
                    x = v
                    while parent[x] is not None:
                        p, r, _ = parent[x]  # type: ignore[misc]
                        steps.append((x, r))
                        x = p
                    return steps[::-1]
                if t not in parent:
                    parent[t] = (v, robots, 0)
                    queue.append(t)
        return None

    take_stays()
    needs_edge = inst.task.name != "exclusive-perpetual-exploration" or len(comp) > 1
    while covered != full or (needs_edge and len(walk) == 1):
        def uncovered(_v: int, t: int, r: int, c: int = covered) -> bool:
            return (r | s.stay[t]) & ~c != 0 or c == full

        steps = path(walk[-1], uncovered)
        if steps is None:  # pragma: no cover - the component is fair
            raise AssertionError("no fair cycle in a fair component")
        for t, robots in steps:
            walk.append(t)
            covered |= robots
            take_stays()
    if walk[-1] != entry:
        back = path(walk[-1], lambda _v, t, _r: t == entry)
        if back is None:  # pragma: no cover - a component is strongly connected
            raise AssertionError("a component that does not lead back")
        for t, _robots in back:
            walk.append(t)
    busy: list[tuple[int, int, int, int]] = []
    if getattr(_scheduler(inst), "stateful", False):
        for j, sid in enumerate(walk[:-1]):
            state = s.keys[sid][0]
            for i, (k, acts) in enumerate(views.robots(state)):
                v, p, c = state[i]
                other = [a for a in sorted(acts[choice[k]]) if a != (v, c)]
                if p is None and other:
                    busy.append((j, i, other[0][0], other[0][1]))
                    break
    return walk, stays, busy


def _scheduler(inst: Instance) -> Any:
    from schedulers import get_scheduler

    return get_scheduler(inst.scheduler)


def certificate_stats(result: Result) -> dict[str, Any]:
    """What a certificate's ``stats`` hold: the views the search met, its candidates, the
    counterexamples, the decision tree's questions (inner nodes) and leaves (0 and 0 for a
    resolution proof, with its lemmas and steps), and the views the counterexamples rely on
    (the certificate's list, what ``--verify`` counts)."""
    proof = result.tree if isinstance(result.tree, Refutation) else None
    inner, leaves = (0, 0) if proof is not None else tree_size(result.tree)
    return {"views": result.views, "candidates": result.candidates,
            "counterexamples": len(result.counterexamples), "tree_nodes": inner,
            "tree_leaves": leaves,
            "tree_views": len({k for lits in result.literals for k in lits}),
            **({"proof_lemmas": proof.lemmas, "proof_steps": len(proof.steps)} if proof
               else {})}
