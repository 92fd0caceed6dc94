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

from gather_verify import properties as props
from gather_verify.engine.explore import (
    DEFAULT_MARGIN,
    Exploration,
    Limits,
    Violation,
)
from gather_verify.engine.resources import memory_budget_mb
from gather_verify.engine.search import explore
from gather_verify.errors import InvalidInput
from gather_verify.model.classes import classify_configuration
from gather_verify.model.configuration import Configuration
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
    ids = e.path_to(v.state)
    if v.event is None:
        return _trace(e, v.property, v.reason, ids)
    steps = e.concretise(ids)
    state = steps[-1][1] if steps else e.initial_state
    before = e.facts(tuple(sorted(n for n, _ in state))).target
    for event, succ in e.concrete_successors(state):
        after = e.facts(tuple(sorted(n for n, _ in succ))).target
        if before is not None and after is not None and after != before:
            steps.append((event, succ))
            return build_trace(
                e.initial, e.algorithm.name, e.scheduler_name, e.detection, e.frames, steps,
                v.property, f"the target meeting node changes from {list(before)} to {list(after)}",
                None, target_before=list(before), target_after=list(after))
    return None  # the target is not equivariant: the caller re-checks without reductions


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
    wanted = props.check_property_names(properties)
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
    stopped = e.stopped if e.stopped != "defined" else None
    complete = e.stopped is None
    for name in ("final", "no-ungatherable", "target-invariance"):
        if name in wanted and name not in traces:
            results[name] = {"holds": True} if complete else {"holds": None,
                                                               "reason": f"search stopped ({e.stopped})"}
    if "no-ungatherable" in wanted and e.initial_in_U and complete:
        results["no-ungatherable"] = {"holds": True, "reason": "initial configuration is in U"}
    if complete and ({"move-bound", "termination"} & set(wanted)):
        longest = props.longest_path(e)
        lifted = e
        if longest.max_moves is None and (e.anonymity or e.symmetry):
            lifted = explore(configuration, algorithm, scheduler, engine=engine,
                             detection=detection, frames=frames, reduction=False, properties=[], limits=lim)
            if lifted.stopped:
                stopped = f"{lifted.stopped} (while lifting the reduced graph to check cycles)"
        if longest.max_moves is not None:
            report["max_moves"] = longest.max_moves
            report["ratio"] = longest.max_moves / (D * n) if D * n else None
            if "termination" in wanted:
                results["termination"] = {"holds": True, "reason": "the reachable graph is acyclic"}
            if "move-bound" in wanted:
                ok = longest.max_moves <= move_bound_c * D * n
                results["move-bound"] = {
                    "holds": ok, "max_moves": longest.max_moves, "bound": move_bound_c * D * n,
                    "reason": f"largest total moves {longest.max_moves} "
                              f"{'<=' if ok else '>'} {move_bound_c:g}*D*n = {move_bound_c * D * n:g}"}
                if not ok:
                    traces["move-bound"] = _trace(
                        e, "move-bound", results["move-bound"]["reason"], longest.path,
                        max_moves=longest.max_moves, c=move_bound_c, D=D, n=n)
        elif not lifted.stopped:
            report["max_moves_infinite"] = True
            if "move-bound" in wanted:
                cyc = props.any_cycle(lifted)
                assert cyc is not None
                results["move-bound"] = {"holds": False, "max_moves": None,
                                         "reason": "a cycle with moves: no bound"}
                traces["move-bound"] = _trace(
                    lifted, "move-bound", "a reachable cycle makes moves forever: no bound",
                    lifted.path_to(cyc[0]), cyc, max_moves=None, c=move_bound_c, D=D, n=n)
            if "termination" in wanted:
                live = props.livelock(lifted)
                if live is None:
                    results["termination"] = {"holds": True, "reason": "every cycle is unfair"}
                else:
                    reason = ("livelock: a fair execution stays forever in a component of "
                              f"{len(live.component)} states without reaching a final state")
                    results["termination"] = {"holds": False, "reason": reason}
                    traces["termination"] = _trace(lifted, "termination", reason,
                                                   lifted.path_to(live.cycle[0]), live.cycle)
    if "defined" in e.violations:
        results["defined"] = {"holds": False, "reason": e.violations["defined"].reason}
    failing = [p for p in props.ORDER if p in traces]
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
