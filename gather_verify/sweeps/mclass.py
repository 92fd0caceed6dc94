"""The paper's world's union engine in a sweep (``sweep --engine union``).

:func:`decide_class` settles most configurations of one class from one union graph
(:mod:`gather_verify.engine.union`, which documents the rules), with the rows
:func:`gather_verify.sweeps.sweep.verify_one` gives one at a time; the others
(NOT-APPLICABLE ones, and those the union does not settle exactly) are left to the
per-configuration check (:func:`gather_verify.sweeps.classes.verify_class` runs them). :func:`class_tasks` cuts a
sweep's configurations into classes, largest first, so a pool starts the long
ones early.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import Any

from gather_verify import properties as props
from gather_verify.algorithms import Algorithm, get_algorithm
from gather_verify.algorithms.base import target_commutes_with_translations as commutes
from gather_verify.algorithms.moves import frames_for
from gather_verify.engine import union
from gather_verify.engine.encoding import Turns
from gather_verify.engine.explore import (
    Encoding,
    Exploration,
    TurnState,
    Violation,
    facts_cache,
    rss_mb,
    symmetry_group,
)
from gather_verify.engine.facts_table import make_room
from gather_verify.engine.region import PLANE
from gather_verify.engine.resources import memory_budget_mb
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import Automorphism
from gather_verify.plane_check import _safety_trace, cause_of
from gather_verify.sweeps.classes import ClassDecision
from gather_verify.sweeps.store import row
from gather_verify.theory import failing, get_fact, scope_of
from gather_verify.watchdog import Overtime, allowance, deadline
from schedulers import initial_state

ENGINES = ("union", "per-config")
Row = dict[str, Any]


def class_tasks(todo: Sequence[tuple[int, Configuration]], frames: str = "all"
                ) -> list[list[tuple[int, Configuration]]]:
    """``todo`` as tasks, the largest first (ties: enumeration order): one per shape of
    ``M`` (up to translations and the robots' frame group), its meeting-node classes (``M``
    up to translation) one after the other; :func:`decide_class` explores one union for all
    of them."""
    shapes: dict[object, list[tuple[int, Configuration]]] = {}
    for members in union.meeting_classes(todo):
        shape = union.shape_key(members[0][1], frames)
        shapes.setdefault(shape, []).extend(members)
    return sorted(shapes.values(), key=lambda members: (-len(members), members[0][0]))


def decide_class(settings: Any, members: Sequence[tuple[int, Configuration]],
                 configuration_key: Callable[[Configuration], str]) -> ClassDecision:
    """The sweep rows of ``members`` (one shape of ``M``: one union graph per ``n``, every
    configuration moved onto ``M0`` by :func:`~gather_verify.engine.union.shape_isometry`)
    that the union graphs settle
    exactly as :func:`gather_verify.sweeps.sweep.verify_one` would (rows keyed by
    ``configuration_key``); the rest in ``fallback``, each with its reason. What the union
    may decide, it asks: the scheduler (:func:`~gather_verify.engine.union.unsupported`),
    each property (its ``union`` fact) and the algorithm's target
    (:func:`target_commutes_with_translations`)."""
    out = ClassDecision([], [])
    why_not = union.unsupported(settings.scheduler, settings.reduction, settings.frames)
    if why_not is not None:
        return out.fall_back(members, why_not)
    wanted = props.check_property_names(settings.properties or None)
    facts = {p: union.property_fact(p) for p in wanted}
    # a property outside the frames a paper gives it does not apply, as run_check says
    wanted = [p for p in wanted
              if (s := scope_of(p)) is None or s.under_frames(settings.frames) is None]
    undecided = [p for p in wanted if facts[p] is None]
    if undecided:  # a property of the user's: only its own search knows it
        return out.fall_back(members, f"property {undecided[0]} names no fact of the union graph")
    algo = get_algorithm(settings.algorithm)  # resolved once, for the union and the traces
    if "target-change" in facts.values() and not target_commutes_with_translations(algo):
        # its target is for its own searches to read
        return out.fall_back(members, "its target is not marked as commuting with translations")
    memory = memory_budget_mb() if settings.max_memory_mb is None else settings.max_memory_mb
    todo: list[tuple[int, Configuration, Any, Configuration, Automorphism,
                     tuple[int, ...]]] = []
    for index, c in members:
        cls = get_fact("class").of(c)
        unmet = failing(c, settings.frames)  # a precondition of the paper's (gather_verify.theory)
        if unmet is not None:  # NOT-APPLICABLE (or --force): decided on its own
            out.fall_back([(index, c)], unmet[0].summary)
        else:
            iso = union.shape_isometry(c, settings.frames)
            todo.append((index, c, cls, union.normalise(c, iso), Automorphism(*iso).inverse(),
                         union.labels(c, iso)))
    if not todo:
        return out
    by_n: dict[tuple[frozenset, int], list[int]] = {}  # one union per shape of M and n
    for k, (_, c, _, nc, _, _) in enumerate(todo):
        by_n.setdefault((nc.meeting_nodes, c.n), []).append(k)
    trace_facts: dict[frozenset, Any] = {}  # the facts met by the traces, per M
    graph_props = any(facts[p] in GRAPH_FACTS for p in wanted)
    for ks in by_n.values():
        normal = [todo[k][3] for k in ks]
        group = symmetry_group(normal[0], settings.frames)  # what the frames allow
        box = geometry.bounding_box([v for c in normal for b in [PLANE.region(c, union.UNION_MARGIN, group)]
                                     for v in (b[:2], b[2:])])
        turned = {}  # per linear part, a map from M0 back to a seed's M
        for k in ks:
            if todo[k][4].g != geometry.IDENTITY:
                turned.setdefault(todo[k][4].g, todo[k][4])
        make_room(memory)
        kept, left = len(out.rows), len(out.fallback)
        try:  # the user's code that does not return: the per-configuration checks decide
            # (each stops at its own time limit, INCOMPLETE); the watchdog's bound is theirs
            with deadline(allowance(settings.max_seconds)):
                out.union_states += _decide_union(settings, algo, wanted, facts, todo, ks, normal,
                                                  group, box, turned, memory, graph_props, out,
                                                  configuration_key, trace_facts)
        except Overtime:
            del out.rows[kept:], out.fallback[left:]
            out.fall_back([(todo[k][0], todo[k][1]) for k in ks],
                          "the union search ran past the time limit")
    return out


GRAPH_FACTS = ("longest-path", "acyclic")
"""The union facts of the whole graph (those of a graph property): with one checked, a row
reports ``max_moves``."""


def _decide_union(settings: Any, algo: Algorithm, wanted: list[str],
                  facts: dict[str, str | None], todo: list[Any], ks: list[int], normal: list[Configuration], group: Any,
                  box: Any, turned: dict, memory: float, graph_props: bool, out: ClassDecision,
                  configuration_key: Callable[[Configuration], str],
                  trace_facts: dict[frozenset, Any]) -> int:
    """The rows of the configurations ``ks`` of ``todo`` (one shape of ``M`` and one ``n``,
    ``normal``: moved onto it) from their union graph, into ``out.rows``; those it does not
    settle into ``out.fallback``, with their reasons. The union's states (0 when it settles
    none). ``facts``: each wanted property's union fact."""
    rows = out.rows
    u = union.explore_union(normal[0].meeting_nodes, [c.robots for c in normal],
                            algo,
                            settings.scheduler, detection=settings.detection,
                            frames=settings.frames, properties=wanted, box=box,
                            max_states=max(union.UNION_MAX_STATES, settings.max_states),
                            orientations=list(turned.values()),
                            labels=[todo[k][5] for k in ks])
    if u is None or rss_mb() > memory or u.seconds > settings.max_seconds:
        # too large, or past a limit the per-configuration searches might hit: they decide
        out.fall_back([(todo[k][0], todo[k][1]) for k in ks],
                      "the union graph is too large" if u is None else
                      "the union search passed the memory limit" if rss_mb() > memory else
                      "the union search ran past the time limit")
        return 0
    share = u.seconds / len(ks)
    order = [p for p in props.names() if p in wanted]  # the verdict order
    bits = {p: union.FACT_BITS.get(facts[p] or "", 0) for p in order}
    bounded = [p for p in order if facts[p] == "longest-path"]
    for j, k in enumerate(ks):
        index, c, cls, nc, back, _ = todo[k]
        reach = u.reach_of(j)
        count = int(u.counts[j])
        if reach & union.ASYMMETRIC:
            out.fall_back([(index, c)], "its target does not commute with the isometries that "
                                        "merge its states")
            continue
        margin = union.margin_needed(nc, group, u.box_of(j))
        if (reach & (union.DEFINED | union.TAINT | union.CYCLE) or margin is None or count < 0
                or count > settings.max_states):
            out.fall_back([(index, c)], _seed_reason(reach, margin))
            continue
        D, n = c.D, c.n
        max_moves = u.best_of(j) if graph_props else None
        failing = [p for p in order if bits[p] & reach]
        if failing and margin > PLANE.initial and not settings.keep_growing:
            # its own search at the first margin is stopped by the region: whether that
            # BFS prefix meets a violation, and so ends the search there, only it can say
            out.fall_back([(index, c)], "a violation its own search may meet at a smaller margin")
            continue
        if reach & union.RING and graph_props and not _lifted_fits(nc, group, u.box_of(j),
                                                                     margin, count, settings):
            out.fall_back([(index, c)], "its own check lifts its graph (a turn goes round "
                                        "stuck robots), and that search may pass a limit")
            continue
        bound = settings.move_bound_c * D * n
        over = [p for p in bounded if max_moves is not None and max_moves > bound]
        if not failing and over:
            out.fall_back([(index, c)], "move-bound fails: its trace is its own graph's longest "
                                        "path")
            continue
        t0 = time.perf_counter()
        trace = None
        if failing:
            trace = witness_trace(u, j, c, back, failing[0], margin, settings, algo, trace_facts)
            if trace is None:
                out.fall_back([(index, c)], "no witness path in the union graph")
                continue
            trace["cause"] = cause_of(algo, trace)
        rows.append(row(
            key=configuration_key(c), index=index, robots=[list(r) for r in c.robots],
            meeting_nodes=sorted(list(m) for m in c.meeting_nodes), class_=cls,
            verdict="VIOLATED" if failing else "VERIFIED",
            property=failing[0] if failing else None,
            reason=trace["reason"] if trace else None,
            states=count, transitions=int(u.transitions[j]), max_moves=max_moves, D=D, n=n,
            ratio=None if max_moves is None or not D * n else max_moves / (D * n),
            trace=trace, seconds=share + time.perf_counter() - t0,
            # every failing property, as the check lists them (acyclic: termination holds)
            failing=failing + over, cause=None if trace is None else trace["cause"]))
    return u.states


def _lifted_fits(c: Configuration, group: Any, box: Any, margin: int, count: int,
                 settings: Any) -> bool:
    """Whether the search without reductions that ``run_check`` makes when a graph property
    meets a cycle (here a turn going round stuck robots, whose component holds a final state:
    no livelock) stays within its limits: at most ``count * n! * |Aut|`` states (each state
    of the reduced graph stands for at most that many), every node reachable (``box``, closed
    under the group) inside its region (at ``margin``, not closed under the group)."""
    own = PLANE.needed(c, [], box)
    return (own is not None and own <= margin
            and count * math.factorial(c.n) * max(1, len(group)) <= settings.max_states)


def _seed_reason(reach: int, margin: int | None) -> str:
    """Why one seed of a union graph is left to its own check (the first that applies)."""
    if reach & union.DEFINED:
        return "a reachable configuration has no rule, or the algorithm crashes there"
    if reach & union.TAINT:
        return "a reachable state leaves the union's region"
    if reach & union.CYCLE:
        return "a cycle is reachable"
    if margin is None:
        return "its region would pass the largest margin"
    return "its state space passes max_states"


def target_commutes_with_translations(algorithm: Any) -> bool:
    """Whether the union may read ``algorithm``'s target on a translate of a configuration
    (docs/interpretations.md, E8): no target, or one marked
    :func:`~gather_verify.algorithms.base.commutes_with_translations` (each built-in target
    is: read off a canonical form, or a minimum over nodes ordered by their coordinates). A
    target of the user's is global coordinates with no such promise unless it makes it."""
    return commutes(algorithm)

_TRANSITION = object()  # marks a transition witness: the trace finds the edge itself


def witness_trace(u: union.UnionGraph, seed: int, c: Configuration, back: Automorphism,
                  prop: str, margin: int, settings: Any, algo: Algorithm,
                  facts: dict[frozenset, Any]
                  ) -> dict[str, Any] | None:
    """The trace ``run_check`` reports for the safety property ``prop`` from ``c`` (seed
    ``seed`` of ``u``, ``back`` the map from the union's ``M0`` to ``c``'s ``M``): its
    first witness and BFS path found in the
    union graph, mapped back and concretised as the check does (:func:`plane_check._safety_trace`,
    on the keys of the check's own encoding, margin ``margin``). ``facts``: the facts
    caches of the class's traces, by meeting-node set, filled here (a configuration's
    facts do not depend on the initial configuration they carry, which only a property
    of the user's could read, and those are never decided here)."""
    order = None if back.g == geometry.IDENTITY else u.oriented(back)
    spec = props.get_property(prop)
    # a property that is vacuous when the initial state fails it has no witness there
    path = u.witness_path(seed, union.FACT_BITS[spec.union or ""],
                          fresh=spec.vacuous is not None, order=order)
    if path is None:
        return None
    if c.meeting_nodes not in facts:
        facts[c.meeting_nodes] = facts_cache(algo, c, settings.detection,
                                             frames_for(settings.frames))
    group = symmetry_group(c, settings.frames)
    turns = u.turns
    enc = Encoding(PLANE.region(c, margin, group), group, turns is None)
    own = None if turns is None else Turns(turns.sched, c.n, True, enc.base)
    keys = []
    for sid in path:
        key = int(u.keys[sid])
        state = tuple((back(v), None if p is None else back(p))
                      for v, p in u.encoding.decode(key, c.n))
        # with a stateful scheduler its state too (the isometries leave it alone)
        keys.append(enc.key(state) if own is None or turns is None else
                    own.key(enc, state, turns.extra(key)))
    starts = None
    if u.starts is not None and own is not None:  # the start the path leaves from
        first = u.initial(seed).tolist().index(path[0])
        starts = [TurnState(initial_state(c.robots), u.starts[seed][first])]
    e = Exploration(initial=c, algorithm=algo, scheduler_name=settings.scheduler,
                    detection=settings.detection, frames=settings.frames, anonymity=True,
                    symmetry=True, encoding=enc, keys=keys, parents=[-1, *range(len(path) - 1)],
                    offsets=[], targets=[], weights=[], changed_loops=0, states=len(path),
                    transitions=0, stopped=None, violations={}, seconds=0.0, peak_rss_mb=0.0,
                    facts=facts[c.meeting_nodes], vacuous={}, turns=own, starts=starts)
    event = _TRANSITION if spec.kind == "transition" else None
    return _safety_trace(e, Violation(prop, len(path) - 1, "", event))
