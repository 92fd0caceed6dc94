"""``run_check``: classify, explore, decide every requested property, build the trace.

The one entry point behind ``gather-verify check`` and the sweep; it returns
the JSON-able report the CLI prints with ``--json``.

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
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

from gather_verify.engine.checks import Violation
from gather_verify.engine.explore import (
    DEFAULT_MARGIN,
    Exploration,
    Limits,
)
from gather_verify.engine.resources import memory_budget_mb
from gather_verify.engine.search import explore
from gather_verify.errors import InvalidInput
from gather_verify.model.classes import classify_configuration
from gather_verify.model.configuration import Configuration
from gather_verify.properties.facts import StateFacts
from gather_verify.properties.graph import GraphFacts, longest_path
from gather_verify.properties.registry import check_property_names, get_property, registered
from gather_verify.trace import build_trace
from gather_verify.verdict import INCOMPLETE, NOT_APPLICABLE, combine


def _memory_limit(value: float | None) -> float:
    """The memory limit asked for, else this machine's budget (:mod:`gather_verify.engine.resources`)."""
    return memory_budget_mb() if value is None else value


AUTO_MARGIN_MAX = 32
"""The largest region margin tried when the margin is left to grow by itself."""


def _trace(e: Exploration, prop: str, reason: str, ids: Sequence[int],
           cycle: Sequence[int] | None = None, **detail: Any) -> dict[str, Any]:
    steps = e.concretise(ids)
    cycle_start = None
    if cycle is not None:
        cycle_start = len(steps)
        start = steps[-1][1] if steps else e.initial_state
        steps += e.concretise(cycle, start=start)
    return build_trace(e.initial, e.algorithm.name, e.scheduler_name, e.detection, e.frames,
                       steps, prop, reason, cycle_start, **detail)


def _safety_trace(e: Exploration, v: Violation) -> dict[str, Any] | None:
    """The trace of a state or transition property's witness; for a transition, the first
    concrete transition out of the witness state's concrete member that fails (None when
    none does: a ``value`` that is not equivariant, the caller re-checks without reductions)."""
    prop = get_property(v.property)
    steps = e.concretise(e.path_to(v.state))
    state = steps[-1][1] if steps else e.initial_state
    here = e.facts(tuple(sorted(n for n, _ in state)))
    if prop.kind == "state":  # the reason, on the concrete state shown
        reason = prop.message_for(StateFacts(here, all(p is None for _, p in state)))
        return build_trace(e.initial, e.algorithm.name, e.scheduler_name, e.detection, e.frames,
                           steps, v.property, reason)
    assert prop.value is not None and prop.holds is not None
    before = prop.value(here)
    for event, succ in e.concrete_successors(state):
        after = prop.value(e.facts(tuple(sorted(n for n, _ in succ))))
        if not prop.holds(before, after):
            steps.append((event, succ))
            return build_trace(
                e.initial, e.algorithm.name, e.scheduler_name, e.detection, e.frames, steps,
                v.property, prop.message_for(before, after), None,
                **prop.detail_for(before, after))
    return None


def run_check(
    configuration: Configuration,
    *,
    algorithm: str,
    scheduler: str,
    detection: str = "local-weak",
    frames: str = "all",
    properties: Sequence[str] | None = None,
    reduction: bool = True,
    max_states: int,
    max_seconds: float,
    move_bound_c: float = 4.0,
    force: bool = False,
    engine: str = "auto",
    memo: bool = False,
    on_exploration: Callable[[Exploration], object] | None = None,
    **limits: Any,
) -> dict[str, Any]:
    """Check ``algorithm`` from ``configuration``; the report as a JSON-able dict.

    Extra ``limits``: ``max_memory_mb`` and ``margin``. Without a ``margin`` the
    region grows by itself: a search stopped by the region is run again with the
    margin doubled, up to ``AUTO_MARGIN_MAX`` (the same exact search on a larger
    region, so the verdict stays honest; only the last run is reported).
    ``on_exploration`` receives that last search (``check --graph-out`` exports it)."""
    started = time.perf_counter()
    wanted = check_property_names(properties)
    fixed_margin = limits.pop("margin", None)
    lim = Limits(max_states=max_states, max_seconds=max_seconds,
                 max_memory_mb=_memory_limit(limits.pop("max_memory_mb", None)),
                 margin=DEFAULT_MARGIN if fixed_margin is None else fixed_margin)
    if limits:
        raise InvalidInput(f"unknown limit(s): {', '.join(sorted(limits))}")
    cls = classify_configuration(configuration)
    n, D = configuration.n, configuration.D
    report: dict[str, Any] = {
        "class": cls.name, "verdict": None, "property": None, "reason": None, "states": 0,
        "transitions": 0, "max_moves": None, "max_moves_infinite": False, "D": D, "n": n,
        "ratio": None, "bound": move_bound_c * D * n, "seconds": 0.0, "trace": None,
        "properties": {p: {"holds": None} for p in wanted},
        "limits": {"max_states": max_states, "max_seconds": max_seconds,
                   "max_memory_mb": lim.max_memory_mb, "margin": lim.margin,
                   "margin_auto": fixed_margin is None},
        "algorithm": algorithm, "scheduler": scheduler, "detection": detection, "frames": frames,
        "reduction": reduction,
    }
    if (cls.in_U or cls.name == "UNCLASSIFIED") and not force:
        report.update(verdict=NOT_APPLICABLE, reason=f"initial configuration is {cls.name}: "
                      "use the impossibility checks (or --force)",
                      seconds=time.perf_counter() - started)
        return report
    e = explore(configuration, algorithm, scheduler, engine=engine, detection=detection,
                frames=frames, reduction=reduction, properties=wanted, limits=lim, memo=memo)
    while fixed_margin is None and e.stopped == "region" and lim.margin < AUTO_MARGIN_MAX:
        left = max_seconds - (time.perf_counter() - started)
        if left <= 0:
            break
        lim = replace(lim, margin=min(2 * lim.margin, AUTO_MARGIN_MAX), max_seconds=left)
        e = explore(configuration, algorithm, scheduler, engine=engine, detection=detection,
                    frames=frames, reduction=reduction, properties=wanted, limits=lim, memo=memo)
    report["limits"]["margin"] = lim.margin
    if on_exploration is not None:
        on_exploration(e)
    report.update(states=e.states, transitions=e.transitions, peak_rss_mb=round(e.peak_rss_mb, 1))
    results = report["properties"]
    traces: dict[str, dict[str, Any] | None] = {}
    for name, v in e.violations.items():
        trace = _safety_trace(e, v)
        if trace is None:  # target not equivariant: find the witness on the concrete graph
            plain = explore(configuration, algorithm, scheduler, engine=engine,
                            detection=detection, frames=frames, reduction=False, properties=[name], limits=lim)
            w = plain.violations.get(name)
            trace = _safety_trace(plain, w) if w is not None else None
            if trace is None:
                continue
        # the trace's reason: it names the nodes of the concrete execution shown
        results[name] = {"holds": False, "reason": trace["reason"]}
        traces[name] = trace
    halted = e.stopped is not None and e.stopped in e.violations  # a halting property
    stopped = None if halted else e.stopped
    complete = e.stopped is None
    chosen = [p for p in registered() if p.name in wanted]
    for prop in chosen:
        if prop.kind != "graph" and prop.name not in traces:
            results[prop.name] = {"holds": True} if complete else {
                "holds": None, "reason": f"search stopped ({e.stopped})"}
            if complete and prop.name in e.vacuous:
                results[prop.name] = {"holds": True, "reason": e.vacuous[prop.name]}
    on_graph = [p for p in chosen if p.kind == "graph"]
    if complete and on_graph:
        longest = longest_path(e)
        lifted = e
        if longest.max_moves is None and (e.anonymity or e.symmetry):
            lifted = explore(configuration, algorithm, scheduler, engine=engine,
                             detection=detection, frames=frames, reduction=False, properties=[], limits=lim)
            if lifted.stopped:
                stopped = f"{lifted.stopped} (while lifting the reduced graph to check cycles)"
        if longest.max_moves is not None:
            report["max_moves"] = longest.max_moves
            report["ratio"] = longest.max_moves / (D * n) if D * n else None
        elif not lifted.stopped:
            report["max_moves_infinite"] = True
        if longest.max_moves is not None or not lifted.stopped:
            graph = GraphFacts(e, longest, None if longest.max_moves is not None else lifted,
                               D, n, move_bound_c)
            for prop in on_graph:
                assert prop.decide is not None
                outcome = prop.decide(graph)
                results[prop.name] = outcome.result
                w = outcome.witness
                if w is not None:
                    traces[prop.name] = _trace(w.exploration, prop.name, w.reason, w.path,
                                               w.cycle, **w.detail)
    for name, v in e.violations.items():  # always checked, so never requested: add them
        if get_property(name).pseudo:
            results.setdefault(name, {"holds": False, "reason": v.reason})
    failing = [p.name for p in registered() if p.name in traces]
    verdict = combine(failing, stopped)
    report["verdict"] = verdict
    if failing:
        report["property"] = failing[0]
        report["trace"] = traces[failing[0]]
        report["reason"] = results[failing[0]]["reason"]
    elif verdict == INCOMPLETE:
        report["reason"] = stopped
    report["seconds"] = time.perf_counter() - started
    return report
