"""The check of the paper's world (Z²): ``run_check`` classifies, explores, decides every
requested property and builds the trace; ``check`` is the Python API over it,
``gather_verify.check`` (defaults for every limit, a typed :class:`CheckReport`).

The one entry point behind ``gather-verify check`` and the sweep; it builds a
:class:`CheckReport` and returns it as the JSON-able dict the CLI prints with ``--json``
(:meth:`CheckReport.to_json`); ``check`` returns the report itself.

How reductions preserve each property: the search expands a concrete
representative of each class and computes every fact on concrete states, so
deadlocks, classes (``in U``), move counts and (for algorithms whose
``target`` is equivariant) target changes are the same for every member of a
class. Termination needs robot identities: when the reduced graph has a
cycle, the space is explored again without reductions and the fair
components are decided there.

>>> from gather_verify.model.configuration import Configuration
>>> r = run_check(Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True),
...               algorithm="go-to-target", scheduler="async", max_states=10**5, max_seconds=60)
>>> r["verdict"], r["max_moves"], r["ratio"]
('VERIFIED', 9, 0.75)
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from functools import wraps
from typing import Any, ParamSpec

from gather_verify import pipeline, theory
from gather_verify.algorithms.base import Algorithm, phase_of
from gather_verify.engine.checks import Violation
from gather_verify.engine.explore import (
    DEFAULT_MAX_SECONDS,
    DEFAULT_MAX_STATES,
    Exploration,
    Limits,
    rss_mb,
)
from gather_verify.engine.region import PLANE
from gather_verify.engine.resources import memory_budget_mb
from gather_verify.engine.search import explore
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node
from gather_verify.model.view import Lights
from gather_verify.progress import PROGRESS
from gather_verify.properties.drift import find_drift
from gather_verify.properties.facts import StateFacts
from gather_verify.properties.graph import GraphFacts, Walk, longest_path, most_moves
from gather_verify.properties.registry import check_property_names, get_property, registered
from gather_verify.trace import build_trace, initial_of, steps_of
from gather_verify.verdict import INCOMPLETE, NOT_APPLICABLE, combine, named_first
from gather_verify.worlds.moves import parse_lights
from schedulers import Scheduler, get_scheduler, initial_state, not_phased


def _memory_limit(value: float | None) -> float:
    """The memory limit asked for, else this machine's budget (:mod:`gather_verify.engine.resources`)."""
    return memory_budget_mb() if value is None else value


AUTO_MARGIN_MAX = PLANE.maximum
"""The largest region margin tried when the margin is left to grow by itself."""


def sorted_colours(robots: Sequence[Node], colours: Sequence[int]) -> list[int]:
    """Initial colours given robot by robot as ``robots`` are written (``--robots``, a
    scenario's list), in the order :func:`run_check` takes them: that of the sorted robots
    (a configuration keeps its robots sorted; robot i of a trace is the i-th of them).

    >>> sorted_colours([(3, 2), (1, 1)], [1, 0])
    [0, 1]
    """
    nodes = [tuple(v) for v in robots]
    if len(nodes) != len(colours) or len(set(nodes)) != len(nodes):
        return list(colours)  # run_check refuses it in one line
    colour = dict(zip(nodes, colours, strict=True))
    return [colour[v] for v in sorted(nodes)]


def _lit(e: Exploration, trace: dict[str, Any]) -> dict[str, Any]:
    """A trace of a search with lights names them and the initial colours (docs/traces.md);
    with one colour, seen by all (``--lights 1``, the oblivious robot), it is the oblivious
    trace: states without colours."""
    if e.lights is None:
        return trace
    if e.lights == Lights(1):
        for step in trace["steps"]:
            for robot in step["state"]:
                del robot["colour"]
        return trace
    trace["lights"] = str(e.lights)
    trace["initial"]["colours"] = list(e.colours or (0,) * e.n)
    return trace


def _trace(e: Exploration, prop: str, reason: str, ids: Sequence[int],
           cycle: Sequence[int] | None = None, weights: Sequence[int] | None = None,
           **detail: Any) -> dict[str, Any]:
    steps = e.concretise(ids, weights=weights)
    cycle_start = None
    if cycle is not None:
        cycle_start = len(steps)
        start = steps[-1][1] if steps else e.start_of(ids[0])
        steps += e.concretise(cycle, start=start)
    return _lit(e, build_trace(e.initial, e.algorithm.name, e.scheduler_from(e.start_of(ids[0])),
                               e.detection, e.frames, steps, prop, reason, cycle_start,
                               **detail))


def _safety_trace(e: Exploration, v: Violation) -> dict[str, Any] | None:
    """The trace of a state or transition property's witness; for a transition, the first
    concrete transition out of the witness state's concrete member that fails (None when
    none does: a ``value`` that is not equivariant, the caller re-checks without reductions)."""
    prop = get_property(v.property)
    ids = e.path_to(v.state)
    steps = e.concretise(ids)
    state = steps[-1][1] if steps else e.start_of(ids[0])
    scheduler = e.scheduler_from(e.start_of(ids[0]))
    here = e.facts_of(state)
    if prop.kind == "state":  # the reason, on the concrete state shown
        seen = StateFacts(here, all(r[1] is None for r in state))
        return _lit(e, build_trace(e.initial, e.algorithm.name, scheduler, e.detection,
                                   e.frames, steps, v.property, prop.message_for(seen), None,
                                   **prop.detail_for(seen)))
    assert prop.value is not None and prop.holds is not None
    before = prop.value(here)
    for event, succ in e.concrete_successors(state):
        after = prop.value(e.facts_of(succ))
        if not prop.holds(before, after):
            steps.append((event, succ))
            return _lit(e, build_trace(
                e.initial, e.algorithm.name, scheduler, e.detection, e.frames, steps,
                v.property, prop.message_for(before, after), None,
                **prop.detail_for(before, after)))
    return None


def _walk(e: Exploration, bound: float) -> Walk | None:
    """:func:`most_moves` of ``e``, computed once per exploration."""
    cached = getattr(e, "_most_moves", None)
    if cached is None or cached[0] != bound:
        cached = (bound, most_moves(e, bound))
        e._most_moves = cached
    return cached[1]


def _over_bound(e: Exploration, c: float, D: int, n: int) -> dict[str, Any] | None:
    """The trace of an execution whose total moves exceed ``c * D * n`` in ``e``'s stored
    graph, finished or not (fewest events first, :func:`most_moves`), or None."""
    bound = c * D * n
    PROGRESS.doing = "searching the longest walk (move-bound)"
    walk = _walk(e, bound)
    if walk is None or walk.moves <= bound:
        return None
    events = len(walk.path) - 1
    reason = (f"an execution makes {walk.moves} moves > {c:g}*D*n = {bound:g} in {events} "
              "events")
    return _trace(e, "move-bound", reason, walk.path, weights=walk.weights,
                  moves=walk.moves, c=c, D=D, n=n)


def _drift(e: Exploration, bound: float) -> dict[str, Any] | None:
    """The drift pattern (:mod:`gather_verify.properties.drift`) along the run that left the
    region (the BFS path to the last state expanded), else along the walk with the most
    moves of ``e``'s stored graph; None when neither shows one."""

    def move_sets(robots: tuple[Node, ...]) -> Any:
        return e.facts(robots).move_sets or {}

    PROGRESS.doing = "looking for a drift along the run that left the region"
    walk = _walk(e, bound)
    runs = [(e.path_to(max(len(e.offsets) - 2, 0)), None)]
    if walk is not None:
        runs.append((walk.path, walk.weights))
    for ids, weights in runs:
        steps = e.concretise(ids, weights=weights)
        states = [e.start_of(ids[0]), *(state for _, state in steps)]
        found = find_drift(states, [event for event, _ in steps], move_sets)
        if found is not None:
            return found
    return None


def _label(text: str) -> str:
    """A message's stable label: its text before the first colon."""
    return text.split(":", 1)[0].strip()


def cause_of(algorithm: object, trace: dict[str, Any]) -> str:
    """The rule a violation's run failed in, as a short string (docs/traces.md):

    - ``defined``: the Unhandled message's label, with the phase of the snapshot behind the
      last move (``"I41 after I3 symmetry breaking (L)"``);
    - ``crash``: the exception's type;
    - ``final``: the phase of the plan at the deadlock;
    - ``target-invariance``: the phase at the transition (``"A -> B"`` when it changes);
    - ``termination`` and a move bound with a cycle: the sorted phases on the cycle;
    - ``no-ungatherable`` and a move bound without one: the phase of the snapshot behind
      the last move.

    Without phases (an algorithm with no ``phase``) it is the property, or for ``defined``
    and ``crash`` the label alone."""
    prop = trace["property"]
    trace_steps = steps_of(trace)
    initial = initial_of(trace)
    states = [initial_state(initial.robots), *(state for _, state in trace_steps)]
    events = [event for event, _ in trace_steps]
    meeting = initial.meeting_nodes

    def phase(k: int) -> str | None:
        robots = tuple(sorted(r[0] for r in states[k]))
        return phase_of(algorithm, Configuration.trusted(robots, meeting))

    def behind_last_move() -> str | None:
        """The phase of the snapshot that decided the last move (its Look under ASYNC)."""
        for k in range(len(events) - 1, -1, -1):
            ev = events[k]
            if ev.kind == "round" and ev.distance:
                return phase(k)
            if ev.kind == "move":
                robot = ev.robots[0]
                look = next((j for j in range(k - 1, -1, -1) if events[j].kind == "look"
                             and robot in events[j].robots), None)
                return None if look is None else phase(look)
        return None

    if prop == "crash":
        return _label(str(trace["detail"].get("exception", "crash")))
    if prop == "defined":
        label = _label(trace["reason"].split("no rule here:", 1)[-1])
        where = behind_last_move()
        return label if where is None else f"{label} after {where}"
    cs = trace.get("cycle_start")
    if prop in ("termination", "move-bound") and cs is not None:
        phases = sorted({p for k in range(cs, len(states)) if (p := phase(k)) is not None})
        return ", ".join(phases) or prop
    if prop == "final":
        return phase(len(states) - 1) or prop
    if prop == "target-invariance" and len(states) > 1:
        before, after = phase(len(states) - 2), phase(len(states) - 1)
        if before is None and after is None:
            return prop
        return str(before) if before == after else \
            f"{before or 'no phase'} -> {after or 'no phase'}"
    if prop in ("no-ungatherable", "move-bound"):
        return behind_last_move() or prop
    return prop


def drift_line(drift: dict[str, Any]) -> str:
    """The drift evidence in one line of text, saying what it is not."""
    v = tuple(drift["vector"])
    return (f"drift: from step {drift['start']} the run repeats every {drift['period']} events "
            f"with robots moved by {v} ({drift['periods_checked']} periods seen); a pattern, "
            "not a proof: the meeting nodes stay, so the configuration never repeats")


def _witnesses(e: Exploration, configuration: Configuration, algorithm: Algorithm,
               scheduler: Scheduler, engine: str, detection: str, frames: str,
               lim: Limits, **lit: Any) -> dict[str, dict[str, Any]]:
    """The trace of each violation ``e`` found, by property (a violation whose witness
    does not concretise, a target that is not equivariant, is looked for again on the
    concrete graph, and left out if that search does not meet it)."""
    traces: dict[str, dict[str, Any]] = {}
    for name, v in e.violations.items():
        PROGRESS.doing = f"building the counterexample of {name}"
        trace = _safety_trace(e, v)
        if trace is None:  # target not equivariant: find the witness on the concrete graph
            PROGRESS.doing = f"exploring without reductions (the counterexample of {name})"
            plain = explore(configuration, algorithm, scheduler, engine=engine,
                            detection=detection, frames=frames, reduction=False,
                            properties=[name], limits=lim, graph=False, **lit)
            w = plain.violations.get(name)
            trace = _safety_trace(plain, w) if w is not None else None
        if trace is not None:
            traces[name] = trace
    return traces


def no_target(algo: Algorithm) -> str | None:
    """Why ``target-invariance`` does not apply to ``algo`` (None: it does): an algorithm with
    no ``target()`` has no target meeting node to keep."""
    if getattr(algo, "target", None) is not None:
        return None
    return f"the algorithm {algo.name!r} exposes no target(): there is no target meeting node to keep"


def inapplicable(wanted: Sequence[str], algo: Algorithm, frames: str, light: Lights | None
                 ) -> list[tuple[str, str, str, str]]:
    """The properties of ``wanted`` that do not apply here, in the order check leaves them
    out: outside the scope a paper registered for them (oblivious robots only, some frames
    only) or ``target-invariance`` for an algorithm with no target. Each as ``(name, why,
    where, reason)``: ``where`` names the option, ``reason`` is what ``not_applicable``
    records (a property met twice is left out at its first)."""
    out = []
    scopes = {p: s for p in wanted if (s := theory.scope_of(p)) is not None}
    if light is not None:  # a paper's property defined for oblivious robots only
        for name, s in scopes.items():
            if (why := s.with_colours(light.colours)) is not None:
                out.append((name, why, f" with --lights {light}", why))
    if "target-invariance" in wanted and (why := no_target(algo)) is not None:
        out.append(("target-invariance", why, "", why))
    for name, s in scopes.items():  # a paper's property defined under some frames only
        if (why := s.under_frames(frames)) is not None:
            out.append((name, why, f" under --frames {frames}", f"{why}, not --frames {frames}"))
    return out


def refuse_inapplicable(named: Sequence[str], algo: Algorithm, frames: str,
                        light: Lights | None) -> None:
    """InvalidInput (one line, check's words) when a property asked for by name does not
    apply (:func:`inapplicable`): left out, the rest would be called VERIFIED without it."""
    for name, why, where, _ in inapplicable(named, algo, frames, light):
        raise InvalidInput(f"{name} does not apply{where}: {why}")


def _leave_out(name: str, why: str, where: str, wanted: list[str],
               properties: Sequence[str] | None, not_applicable: dict[str, str],
               reason: str | None = None) -> None:
    """Leave the property ``name`` out of ``wanted`` (when in it): it does not apply, because
    ``why`` (``where``: under which option). Asked for by name (``properties``): InvalidInput;
    else recorded in ``not_applicable`` with ``reason`` (by default ``why``)."""
    if name not in wanted:
        return
    if properties:
        raise InvalidInput(f"{name} does not apply{where}: {why}")
    wanted.remove(name)
    not_applicable[name] = why if reason is None else reason


def _check_report(
    configuration: Configuration,
    *,
    algorithm: str | Algorithm,
    scheduler: str,
    detection: str = "local-weak",
    frames: str = "all",
    properties: Sequence[str] | None = None,
    reduction: bool = True,
    max_states: int = DEFAULT_MAX_STATES,
    max_seconds: float = DEFAULT_MAX_SECONDS,
    move_bound_c: float = 4.0,
    force: bool = False,
    engine: str = "auto",
    memo: bool = False,
    keep_growing: bool = False,
    keep_going: bool = True,
    on_exploration: Callable[[Exploration], object] | None = None,
    lights: str | None = None,
    colours: Sequence[int] | None = None,
    **limits: Any,
) -> CheckReport:
    """Check ``algorithm`` from ``configuration``; the report (:func:`run_check` returns it
    as a JSON-able dict, :meth:`CheckReport.to_json`).

    Extra ``limits``: ``max_memory_mb`` and ``margin``. Without a ``margin`` the
    region grows by itself: a search stopped by the region that has found no violation
    is run again in a larger region (:data:`~gather_verify.engine.region.PLANE`: the margin
    doubled, up to ``AUTO_MARGIN_MAX``; the same exact search on a larger region, so the
    verdict stays honest; only the last run is reported). A search that has found one is
    the last, as SPIN and TLC stop at the first error: the larger search would meet the
    same violations with the same traces (a search stopped by the region is a prefix of
    the larger one's BFS), only later.
    ``keep_growing`` grows it anyway, to look for violations of properties the smaller
    region did not reach (the row then names the first in the verdict order).
    ``keep_going=False`` stops the search once every requested property (``properties``
    named, none needing the whole graph) has its counterexample, as SPIN stops at its first
    error; the report then says the others were not looked for.
    ``on_exploration`` receives that last search (``check --graph-out`` exports it).

    ``lights``: luminous robots (SEMANTICS.md §10), ``K``, ``K:external`` or ``K:internal``,
    with ``colours`` their initial colours (default 0), one per robot of
    ``configuration.robots`` (sorted: :func:`sorted_colours` reorders colours given as the
    robots were written). The bulk engine runs them
    (:mod:`~gather_verify.engine.lit_bulk`; the report's ``engine`` says which ran, and
    ``engine_fallback`` why ``auto`` ran the reference).

    A property outside the scope a paper registered for it (:func:`gather_verify.theory.scope`:
    the frames, or oblivious robots only, with K > 1 colours) is left out, its reason under
    ``not_applicable``, or refused (InvalidInput) when ``properties`` names it.

    On that last search, finished or not, ``move-bound`` fails as soon as its stored graph
    holds an execution with more than ``c * D * n`` moves (the one with the fewest events,
    :func:`~gather_verify.properties.graph.most_moves`); it holds only on a finished graph.
    A search stopped by the region also looks for a drift along the run that left it
    (:mod:`gather_verify.properties.drift`): evidence under ``drift``, and the reason
    ``drift`` when nothing fails, never a proof.

    The user's code runs under a watchdog (:mod:`gather_verify.watchdog`, on the main thread
    of a POSIX system), with the :func:`~gather_verify.watchdog.allowance` of
    ``max_seconds`` (as much again, at least :data:`~gather_verify.watchdog.GRACE_SECONDS`
    more): the algorithm and property files must import within it (else InvalidInput, one
    line), and a call of ``decide`` (``target``, a property's function ...) still running
    past it ends the check: INCOMPLETE, reason ``time``, never a crash and never VERIFIED. ``max_seconds=math.inf``: no watchdog."""
    checker = PlaneCheck(configuration, algorithm=algorithm, scheduler=scheduler,
                         detection=detection, frames=frames, properties=properties,
                         reduction=reduction, max_states=max_states, max_seconds=max_seconds,
                         move_bound_c=move_bound_c, force=force, engine=engine, memo=memo,
                         keep_growing=keep_growing, keep_going=keep_going,
                         on_exploration=on_exploration, lights=lights, colours=colours,
                         limits=limits)
    if checker.why_not is not None:  # a precondition of the paper's theory (gather_verify.theory)
        return replace(checker.report, verdict=NOT_APPLICABLE, reason=checker.why_not,
                       seconds=time.perf_counter() - checker.started)
    return pipeline.run(checker, max_seconds)


class PlaneCheck:
    """The paper's world's part of the one check (:class:`~gather_verify.pipeline.Checker`):
    the request resolved once (the properties that apply, the algorithm, the lights, the
    limits and the region, the configuration's class and the theory's precondition), then
    the search in a region grown while it stops the search, the properties decided on what
    it found (the graph's on a finished graph, lifted to robot identities for its cycles)
    and the report."""

    def __init__(self, configuration: Configuration, *, algorithm: str | Algorithm,
                 scheduler: str, detection: str, frames: str, properties: Sequence[str] | None,
                 reduction: bool, max_states: int, max_seconds: float, move_bound_c: float,
                 force: bool, engine: str, memo: bool, keep_growing: bool, keep_going: bool,
                 on_exploration: Callable[[Exploration], object] | None, lights: str | None,
                 colours: Sequence[int] | None, limits: dict[str, Any]):
        from gather_verify.algorithms import get_algorithm

        self.started = time.perf_counter()
        wanted, algo = pipeline.user_code(max_seconds, lambda: (
            check_property_names(properties),
            get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm))
        light = None if lights is None else parse_lights(lights)
        pipeline.check_colours(colours, configuration.n, None if light is None else light.colours)
        not_phased(scheduler, "on the paper's world Z²")
        if not getattr(algo, "plane", True):
            raise InvalidInput(f"algorithm {algo.name!r} is written for finite worlds: give "
                               "--world ring:N (docs/worlds.md)")
        not_applicable: dict[str, str] = {}
        for name, why, where, reason in inapplicable(wanted, algo, frames, light):
            _leave_out(name, why, where, wanted, properties, not_applicable, reason)
        self.fixed_margin = limits.pop("margin", None)
        self.lim = Limits(max_states=max_states, max_seconds=max_seconds,
                          max_memory_mb=_memory_limit(limits.pop("max_memory_mb", None)),
                          margin=PLANE.initial if self.fixed_margin is None else self.fixed_margin)
        if limits:
            raise InvalidInput(f"unknown limit(s): {', '.join(sorted(limits))}")
        self.configuration, self.algo, self.wanted, self.light = configuration, algo, wanted, light
        self.scheduler, self.detection, self.frames = scheduler, detection, frames
        self.reduction, self.engine, self.memo = reduction, engine, memo
        self.keep_growing, self.keep_going, self.on_exploration = keep_growing, keep_going, \
            on_exploration
        self.max_seconds, self.c = max_seconds, move_bound_c
        self.lit: dict[str, Any] = {} if light is None else {
            "lights": light, "colours": None if colours is None else tuple(colours)}
        # the edges are kept only for a graph property or the caller's use of the graph
        self.keep_graph = on_exploration is not None or any(
            get_property(p).kind == "graph" for p in wanted)
        PROGRESS.doing = "classifying the configuration"
        self.why_not = None if force else theory.not_applicable(configuration, frames)
        self.report = self.skeleton(algorithm, colours, not_applicable)

    def skeleton(self, algorithm: str | Algorithm, colours: Sequence[int] | None,
                 not_applicable: dict[str, str]) -> CheckReport:
        """The report with nothing decided yet: every return sets the verdict."""
        c, lim, light = self.configuration, self.lim, self.light
        n, D = c.n, c.D
        return CheckReport(
            verdict=INCOMPLETE, property=None, reason=None,
            class_=theory.get_fact("class").of(c), n=n, D=D, states=0, transitions=0,
            max_moves=None, max_moves_infinite=False, ratio=None, bound=self.c * D * n,
            properties={p: PropertyResult(None) for p in self.wanted}, trace=None,
            algorithm=algorithm if isinstance(algorithm, str) else algorithm.name,
            scheduler=self.scheduler, detection=self.detection, frames=self.frames,
            reduction=self.reduction,
            limits={"max_states": lim.max_states, "max_seconds": lim.max_seconds,
                    "max_memory_mb": lim.max_memory_mb, "margin": lim.margin,
                    "margin_auto": self.fixed_margin is None, "keep_growing": self.keep_growing},
            seconds=0.0, not_applicable=not_applicable or None,
            lights=None if light is None else str(light),
            colours=None if light is None else list(colours or (0,) * n),
            engine=None if light is None else "reference" if self.engine == "reference"
            else "bulk")

    @property
    def bound(self) -> float:
        """The move bound ``c * D * n``."""
        return self.c * self.configuration.D * self.configuration.n

    # -- the search ------------------------------------------------------------------------

    def search(self, watch: pipeline.Watch) -> tuple[Exploration, dict[str, dict[str, Any]]]:
        """The search in the region, grown while the region stops it and nothing fails
        (:data:`~gather_verify.engine.region.PLANE`: the margin doubled, up to
        ``AUTO_MARGIN_MAX``; the same exact search on a larger region, so the verdict stays
        honest; only the last search is reported), and its counterexamples' traces."""
        self.sched = get_scheduler(self.scheduler)  # resolved once: the engines take the objects
        lim = self.lim
        e, traces = self.explore(lim, watch)
        while self.fixed_margin is None and e.stopped == "region" and not traces:
            larger = PLANE.grow(lim.margin)
            left = self.max_seconds - (time.perf_counter() - self.started)
            if larger is None or left <= 0:
                break
            lim = replace(lim, margin=larger, max_seconds=left)
            e, traces = self.explore(lim, watch)
        self.lim = lim
        if traces is None:
            traces = self.witnesses(e)
        if e.stopped is not None and "move-bound" in self.wanted and self.keep_graph:
            # an unfinished search whose stored graph already has an execution over the bound
            # (a finite prefix: no need to finish); only on the last search
            over = _over_bound(e, self.c, self.configuration.D, self.configuration.n)
            if over is not None:
                traces["move-bound"] = over
        return e, traces

    def explore(self, lim: Limits, watch: pipeline.Watch
                ) -> tuple[Exploration, dict[str, dict[str, Any]] | None]:
        """The search in ``lim``'s region, and its traces (None: not needed yet, the region
        grows whatever they are)."""
        PROGRESS.doing = ("exploring" if lim.margin == self.lim.margin else
                          f"exploring a larger region (margin {lim.margin})")
        e = explore(self.configuration, self.algo, self.sched, engine=self.engine,
                    detection=self.detection, frames=self.frames, reduction=self.reduction,
                    properties=self.wanted, limits=lim, memo=self.memo, graph=self.keep_graph,
                    settle=not self.keep_going, **self.lit)
        watch.searched[:] = [e]
        if self.keep_growing:
            return e, None
        return e, self.witnesses(e, lim)

    def witnesses(self, e: Exploration, lim: Limits | None = None) -> dict[str, dict[str, Any]]:
        """The trace of each violation ``e`` found (:func:`_witnesses`)."""
        return _witnesses(e, self.configuration, self.algo, self.sched, self.engine,
                          self.detection, self.frames, lim or self.lim, **self.lit)

    # -- the decisions -----------------------------------------------------------------------

    def decide(self, found: tuple[Exploration, dict[str, dict[str, Any]]]) -> CheckReport:
        """Every requested property decided on the last search: the state and transition
        properties from its witnesses, the graph's on a finished graph; the verdict, the
        first failing property's trace and cause."""
        e, traces = found
        report = replace(self.report, limits={**self.report.limits, "margin": self.lim.margin})
        if self.on_exploration is not None:
            self.on_exploration(e)
        report = replace(report, states=e.states, transitions=e.transitions,
                         peak_rss_mb=round(e.peak_rss_mb, 1))
        if self.light is not None:  # which engine ran the last search, and why not the bulk one
            report = replace(report, engine=e.engine, engine_fallback=e.engine_fallback)
        results: dict[str, dict[str, Any]] = {p: {"holds": None} for p in self.wanted}
        for name, trace in traces.items():
            # the trace's reason: it names the nodes of the concrete execution shown
            results[name] = {"holds": False, "reason": trace["reason"]}
        halted = e.stopped is not None and e.stopped in e.violations  # a halting property
        stopped = None if halted or e.stopped == "settled" else e.stopped
        self.state_results(e, traces, results)
        report, stopped = self.graph_results(e, traces, results, report, stopped)
        self.move_bound(e, traces, results)
        self.undecided(e, results, stopped)
        drift = _drift(e, self.bound) if (
            e.stopped == "region" and self.keep_graph and self.light is None) else None
        for name, v in e.violations.items():  # always checked, so never requested: add them
            if get_property(name).pseudo:
                results.setdefault(name, {"holds": False, "reason": v.reason})
        return self.verdict(e, report, traces, results, stopped, drift)

    def state_results(self, e: Exploration, traces: dict[str, dict[str, Any]],
                      results: dict[str, dict[str, Any]]) -> None:
        """The state and transition properties with no counterexample: they hold on a
        finished search (vacuously, with the reason, where the initial state settles them),
        else are not decided."""
        complete = e.stopped is None
        for prop in registered():
            if prop.name not in self.wanted or prop.kind == "graph" or prop.name in traces:
                continue
            results[prop.name] = {"holds": True} if complete else {
                "holds": None, "reason": SETTLED if e.stopped == "settled" else
                f"search stopped ({e.stopped})"}
            if complete and prop.name in e.vacuous:
                results[prop.name] = {"holds": True, "reason": e.vacuous[prop.name]}

    def on_graph(self) -> list[Any]:
        """The requested graph properties (``move-bound``, ``termination``), in order."""
        return [p for p in registered() if p.name in self.wanted and p.kind == "graph"]

    def graph_results(self, e: Exploration, traces: dict[str, dict[str, Any]],
                      results: dict[str, dict[str, Any]], report: CheckReport,
                      stopped: str | None) -> tuple[CheckReport, str | None]:
        """The graph properties decided on a finished graph: the longest run (the report's
        ``max_moves``), the graph lifted to robot identities when it has cycles and was
        reduced (a limit there stops the decision, and says so in ``stopped``)."""
        on_graph = self.on_graph()
        if e.stopped is not None or not on_graph:
            return report, stopped
        c = self.configuration
        D, n = c.D, c.n
        PROGRESS.doing = "measuring the longest run (move-bound)"
        longest = longest_path(e)
        lifted = e
        cycles = longest.max_moves is None or longest.cyclic
        if cycles and (e.anonymity or e.symmetry):
            PROGRESS.doing = "exploring without reductions (to check the cycles)"
            lifted = explore(c, self.algo, self.sched, engine=self.engine,
                             detection=self.detection, frames=self.frames, reduction=False,
                             properties=[], limits=self.lim, **self.lit)
            if lifted.stopped:
                stopped = f"{lifted.stopped} (while lifting the reduced graph to check cycles)"
        if longest.max_moves is not None:
            report = replace(report, max_moves=longest.max_moves,
                             ratio=longest.max_moves / (D * n) if D * n else None)
        elif not lifted.stopped:
            report = replace(report, max_moves_infinite=True)
        if (longest.max_moves is not None and not longest.cyclic) or not lifted.stopped:
            graph = GraphFacts(e, longest, lifted if cycles else None, D, n, self.c)
            for prop in on_graph:
                assert prop.decide is not None
                PROGRESS.doing = f"deciding {prop.name}" + (
                    " (looking for a fair livelock)" if prop.name == "termination" else "")
                outcome = prop.decide(graph)
                results[prop.name] = outcome.result
                w = outcome.witness
                if w is not None:
                    traces[prop.name] = _trace(w.exploration, prop.name, w.reason, w.path,
                                               w.cycle, **w.detail)
        return report, stopped

    def move_bound(self, e: Exploration, traces: dict[str, dict[str, Any]],
                   results: dict[str, dict[str, Any]]) -> None:
        """``move-bound`` fails on an execution over the bound: on a finished graph whose
        cycles could not be lifted the reduced graph shows one all the same."""
        c = self.configuration
        if ("move-bound" in self.wanted and self.keep_graph and e.stopped is None
                and "move-bound" not in traces and results["move-bound"].get("holds") is None):
            over = _over_bound(e, self.c, c.D, c.n)
            if over is not None:
                traces["move-bound"] = over
        if "moves" in traces.get("move-bound", {}).get("detail", {}):  # an execution over the bound
            results["move-bound"] = {"holds": False, "max_moves": None, "bound": self.bound,
                                     "reason": traces["move-bound"]["reason"]}

    def undecided(self, e: Exploration, results: dict[str, dict[str, Any]],
                  stopped: str | None) -> None:
        """A graph property left undecided says why, as the others do."""
        for prop in self.on_graph():
            if results[prop.name].get("holds") is None and "reason" not in results[prop.name]:
                if e.stopped == "settled":
                    why = SETTLED
                elif e.stopped is not None:
                    why = f"search stopped ({e.stopped})"
                else:  # the search finished, lifting its graph did not
                    limit = (stopped or "a limit").split(" ", 1)[0]
                    why = f"search stopped while lifting the reduced graph to check cycles ({limit})"
                results[prop.name]["reason"] = why

    def verdict(self, e: Exploration, report: CheckReport, traces: dict[str, dict[str, Any]],
                results: dict[str, dict[str, Any]], stopped: str | None,
                drift: dict[str, Any] | None) -> CheckReport:
        """The causes of the failures, the verdict and the trace shown (the first failing
        property's, in the verdict order)."""
        PROGRESS.doing = "naming the causes"
        for name, trace in traces.items():
            trace["cause"] = cause_of(e.algorithm, trace)
            results[name]["cause"] = trace["cause"]
        failing = named_first([p.name for p in registered() if p.name in traces])
        verdict = combine(failing, stopped)
        shown: dict[str, Any] | None = None  # the first failing property's trace
        cause = reason = None
        if failing:
            shown = traces[failing[0]]
            if drift is not None:
                shown["detail"]["drift"] = drift
            reason, cause = results[failing[0]]["reason"], shown["cause"]
        elif verdict == INCOMPLETE:
            reason = "drift" if drift is not None and stopped == "region" else stopped
        return replace(report, verdict=verdict, property=failing[0] if failing else None,
                       reason=reason, trace=shown, cause=cause, drift=drift,
                       properties={p: PropertyResult.from_json(r) for p, r in results.items()},
                       seconds=time.perf_counter() - self.started)

    def overtime(self, seconds: float, watch: pipeline.Watch) -> CheckReport:
        """Stopped by the watchdog: INCOMPLETE, the states stored so far, no property decided."""
        last = watch.searched[-1] if watch.searched else None
        return replace(
            self.report, verdict=INCOMPLETE, property=None, trace=None, cause=None,
            max_moves=None, max_moves_infinite=False, ratio=None, drift=None,
            reason=pipeline.overtime_reason(seconds),
            states=max(PROGRESS.states, last.states if last else 0),
            transitions=last.transitions if last else 0, peak_rss_mb=round(rss_mb(), 1),
            properties={p: PropertyResult(None, "search stopped (time)") for p in self.wanted},
            seconds=time.perf_counter() - self.started)


P = ParamSpec("P")


def _as_json(build: Callable[P, CheckReport]) -> Callable[P, dict[str, Any]]:
    """``build`` answering its report as the JSON-able dict :meth:`CheckReport.to_json` writes."""
    @wraps(build)
    def as_json(*args: P.args, **kwargs: P.kwargs) -> dict[str, Any]:
        return build(*args, **kwargs).to_json()
    return as_json


# the one entry point behind ``gather-verify check`` and the sweep: the report as a dict
run_check = _as_json(_check_report)
run_check.__name__ = run_check.__qualname__ = "run_check"


SETTLED = ("not looked for: the search stopped once every requested property had its "
           "counterexample (--keep-going looks on)")


# -- the Python API (docs/api.md): defaults, and a typed report ----------------------------

@dataclass(frozen=True)
class PropertyResult:
    """One property: ``holds`` (None: not decided, the search stopped), why, and the numbers
    some properties add (``move-bound``: ``max_moves`` and ``bound``)."""

    holds: bool | None
    reason: str | None = None
    numbers: dict[str, Any] = field(default_factory=dict)
    order: tuple[str, ...] = field(default=(), compare=False, repr=False)
    """The keys in the order of the JSON object read (:meth:`from_json`), so that
    :meth:`to_json` writes it back as it was; else ``holds``, ``reason``, the numbers."""

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"holds": self.holds}
        if self.reason is not None:
            out["reason"] = self.reason
        out.update(self.numbers)
        if set(self.order) == set(out):
            return {key: out[key] for key in self.order}
        return out

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> PropertyResult:
        rest = {k: v for k, v in data.items() if k not in ("holds", "reason")}
        return cls(data["holds"], data.get("reason"), rest, tuple(data))


@dataclass(frozen=True)
class CheckReport:
    """What a check found. ``verdict`` is VERIFIED, VIOLATED, INCOMPLETE or NOT-APPLICABLE;
    ``property`` the first failing one (``failing``: every one), with its ``reason`` and
    ``trace`` (a JSON object, docs/traces.md: it is a file format). Each field is named as
    its JSON key, but for ``class_`` (JSON ``class``, a reserved word in Python)."""

    verdict: str
    property: str | None
    reason: str | None
    class_: str
    n: int
    D: int
    states: int
    transitions: int
    max_moves: int | None
    max_moves_infinite: bool
    ratio: float | None
    bound: float
    properties: dict[str, PropertyResult]
    trace: dict[str, Any] | None
    algorithm: str
    scheduler: str
    detection: str
    frames: str
    reduction: bool
    limits: dict[str, Any]
    seconds: float
    peak_rss_mb: float | None = None
    drift: dict[str, Any] | None = None  # the drift pattern of a run that left the region
    cause: str | None = None  # the rule the first failing property's run failed in
    not_applicable: dict[str, str] | None = None  # properties left out, each with why
    lights: str | None = None  # luminous robots (``K``, ``K:external``, ``K:internal``)
    colours: list[int] | None = None  # their initial colours, robot by robot
    engine: str | None = None  # the engine that ran (with lights: the reference)
    engine_fallback: str | None = None  # why it is not the one asked for

    @property
    def failing(self) -> list[str]:
        """Every property that fails."""
        return [name for name, r in self.properties.items() if r.holds is False]

    @property
    def configuration_class(self) -> str:
        """Deprecated: ``class_``, as JSON's ``class``."""
        import warnings

        warnings.warn("CheckReport.configuration_class is deprecated: use class_ (JSON 'class')",
                      DeprecationWarning, stacklevel=2)
        return self.class_

    def to_json(self) -> dict[str, Any]:
        """The report as ``run_check`` returns it (and ``check --json --timings`` prints it)."""
        out = {
            "class": self.class_, "verdict": self.verdict, "property": self.property,
            "reason": self.reason, "states": self.states, "transitions": self.transitions,
            "max_moves": self.max_moves, "max_moves_infinite": self.max_moves_infinite,
            "D": self.D, "n": self.n, "ratio": self.ratio, "bound": self.bound,
            "seconds": self.seconds, "trace": self.trace, "cause": self.cause,
            "properties": {name: r.to_json() for name, r in self.properties.items()},
            "limits": dict(self.limits), "algorithm": self.algorithm,
            "scheduler": self.scheduler, "detection": self.detection, "frames": self.frames,
            "reduction": self.reduction,
        }
        for key in ("not_applicable", "lights", "colours", "engine", "peak_rss_mb",
                    "engine_fallback", "drift"):  # in the order run_check adds them
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        return out

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> CheckReport:
        return cls(
            verdict=data["verdict"], property=data["property"], reason=data["reason"],
            class_=data["class"], n=data["n"], D=data["D"], states=data["states"],
            transitions=data["transitions"], max_moves=data["max_moves"],
            max_moves_infinite=data["max_moves_infinite"], ratio=data["ratio"],
            bound=data["bound"], trace=data["trace"],
            properties={k: PropertyResult.from_json(v) for k, v in data["properties"].items()},
            algorithm=data["algorithm"], scheduler=data["scheduler"],
            detection=data["detection"], frames=data["frames"], reduction=data["reduction"],
            limits=data["limits"], seconds=data["seconds"], peak_rss_mb=data.get("peak_rss_mb"),
            drift=data.get("drift"), cause=data.get("cause"),
            not_applicable=data.get("not_applicable"), lights=data.get("lights"),
            colours=data.get("colours"), engine=data.get("engine"),
            engine_fallback=data.get("engine_fallback"))


def check(
    configuration: Configuration | None = None,
    *,
    robots: Iterable[Node] | None = None,
    meeting: Iterable[Node] | None = None,
    algorithm: str | Algorithm = "paper",
    scheduler: str = "async",
    **options: Any,
) -> CheckReport:
    """Check ``algorithm`` from a configuration (or ``robots`` and ``meeting``) against every
    adversary of ``scheduler``; the same search as ``gather-verify check``.

    ``algorithm`` is a spec (``"paper"``, ``"my_alg.py:MyAlgorithm"``,
    ``"package.module:NAME"``) or an object with ``name`` and ``decide(view)``. The
    ``options`` are :func:`run_check`'s (``detection``, ``frames``, ``properties``,
    ``reduction``, ``max_states``, ``max_seconds``, ``move_bound_c``, ``force``,
    ``lights``, ``colours``, ...), with the command line's defaults; ``max_memory_mb`` and
    ``margin`` may be given too, and ``keep_growing`` (``check --keep-growing``: the region
    grows after a violation too)."""
    if configuration is None:
        if robots is None or meeting is None:
            raise InvalidInput("give a configuration, or both robots and meeting")
        configuration = Configuration(list(robots), list(meeting), initial=True)
    name = algorithm if isinstance(algorithm, str) else getattr(algorithm, "name", None)
    if not isinstance(name, str):
        raise InvalidInput("an algorithm object needs a name (a string attribute)")
    return _check_report(configuration, algorithm=algorithm, scheduler=scheduler, **options)
