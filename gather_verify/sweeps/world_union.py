"""One state graph per meeting-node set of a finite world: every initial configuration of a
sweep that shares it, searched at once (SEMANTICS.md §4, §9, §11).

On a finite world the states reachable from the configurations with one set of meeting
nodes M live in one finite space: a sweep need not search it once per configuration. Each
configuration of the sweep is moved by a symmetry of the world under the robots' frames
(:meth:`~gather_verify.worlds.base.World.symmetries`, the elements that move a robot's
frames onto frames, so the move sets move with them) so that its M becomes the least image
``M0`` of its class; robot ``i`` stays robot ``i``, with its initial colour. The bulk engine
(:func:`gather_verify.engine.world_bulk.search`, ``seeds``) searches every such initial state
of the class in one graph, with the reductions the per-configuration check would use
(those that fix ``M0``). Then, per configuration:

- the states its own search would count are those reachable from its initial states (one
  per start of the scheduler), and its transitions their out-edges (the graph of a moved
  configuration is the image of its own, so both counts are those of its own search);
- it is VERIFIED exactly when no state it reaches is *bad*: a final state that is not
  gathered (or not on a meeting node, or with a node never visited, by the task), two
  robots on one node or a crossing round, a state of a fair component (§5: termination;
  perpetual exploration per node, where the node stays empty). A strongly connected
  component is closed under reachability, so the components met from one configuration are
  whole components of the union.

A configuration that reaches a bad state, or more states than ``max_states``, is checked on
its own (:func:`~gather_verify.sweeps.world_census.verify_world_one`): its verdict, reason
and trace are its own search's. So is every configuration of a class whose union search did
not finish (a crash or a missing rule anywhere in it, a limit), or that the bulk engine
cannot run. The rows are the per-configuration rows, timings aside
(``tests/test_world_union.py``).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from gather_verify.errors import InvalidInput
from gather_verify.sweeps.classes import ClassDecision
from gather_verify.sweeps.store import row
from gather_verify.sweeps.world_census import WorldConfiguration, world_key
from gather_verify.watchdog import Overtime, allowance, deadline
from gather_verify.worlds import finite_world
from gather_verify.worlds.base import World

Item = tuple[int, WorldConfiguration]
"""A configuration of a sweep with its index in the enumeration."""


def class_of(world: World, group: Sequence[Sequence[int]], c: WorldConfiguration
             ) -> tuple[tuple[int, ...], Sequence[int]]:
    """The least image ``M0`` of the configuration's meeting nodes under ``group``, and the
    first element of ``group`` that gives it."""
    best: tuple[tuple[int, ...], Sequence[int]] | None = None
    for p in group:
        image = tuple(sorted(p[m] for m in c.meeting))
        if best is None or image < best[0]:
            best = (image, p)
    assert best is not None
    return best


def world_class_tasks(settings: Any, items: list[Item]) -> list[list[Item]]:
    """The configurations of a sweep grouped by their meeting-node class (one union search
    each), the largest first; in enumeration order within a class."""
    world = finite_world(settings.world)
    try:
        group = world.symmetries(settings.frames)
    except InvalidInput:  # the frames do not apply here: each configuration says so itself
        return [[item] for item in items]
    classes: dict[tuple[int, ...], list[Item]] = {}
    for index, c in items:
        classes.setdefault(class_of(world, group, c)[0], []).append((index, c))
    return sorted(classes.values(), key=lambda members: -len(members))


def decide_world_class(settings: Any, items: Sequence[Item]) -> ClassDecision:
    """The rows the union graph of the class decides (VERIFIED, with their own search's
    counts, the union's time shared among them); the other configurations left to their own
    checks, each with why."""
    out = ClassDecision([], [])
    if not items:
        return out
    started = time.perf_counter()
    try:  # the user's code that does not return: the per-configuration checks decide (each
        # stops at its own time limit, INCOMPLETE), as on the paper's world
        with deadline(allowance(settings.max_seconds)):
            union = _Union(settings, list(items))
            decided = union.rows()
    except InvalidInput as error:  # each configuration's own check says it in its own words
        return out.fall_back(items, f"the union cannot run this class: {error}")
    except Overtime:
        return out.fall_back(items, "the union search ran past the time limit")
    share = (time.perf_counter() - started) / max(1, len(decided))
    for index, c in items:
        if index in decided:
            decided[index]["seconds"] = share
            out.rows.append(decided[index])
        else:
            out.fall_back([(index, c)], union.why_not(index))
    return out


class _Union:
    """The union search of one meeting-node class, and what it decides."""

    def __init__(self, settings: Any, items: list[Item]):
        from gather_verify.algorithms import get_algorithm
        from gather_verify.engine import world_bulk
        from gather_verify.engine.encoding import DEFAULT_MAX_MEMORY_MB, Limits
        from gather_verify.tasks import get_task
        from gather_verify.world_check import _parts, default_task
        from gather_verify.worlds.moves import WorldMoves, parse_lights
        from schedulers import get_scheduler

        self.settings, self.items = settings, items
        self.unfinished: str | None = None
        self.reasons: dict[int, str] = {}
        w = self.world = finite_world(settings.world)
        group = w.symmetries(settings.frames)
        m0, _ = class_of(w, group, items[0][1])
        self.m0 = m0
        n = len(items[0][1].robots)
        light = parse_lights(settings.lights)
        task = self.task = get_task(settings.task or default_task(list(m0)))
        parts = self.parts = _parts(task, list(settings.properties) or None, w)
        if settings.visibility is not None and settings.visibility < 0:
            raise InvalidInput("negative visibility")
        if task.needs_meeting and not m0 or task.visits and w.size > 62:
            raise InvalidInput("the task cannot run here")
        sched = get_scheduler(settings.scheduler)  # resolved once: the engine takes the object
        liveness = any(p in task.liveness for p in parts)
        reduce = settings.reduction and not liveness  # as run_world_check reduces
        symmetries = w.symmetries(settings.frames) if reduce else ()
        algorithm = get_algorithm(settings.algorithm)
        moves = WorldMoves(w, algorithm, frozenset(m0), settings.detection, settings.frames,
                           settings.visibility, light)
        seeds = []
        for _, c in items:
            image, p = class_of(w, group, c)
            if image != m0:
                raise InvalidInput("not one class")  # pragma: no cover - grouped by class
            colours = tuple(c.colours) if c.colours else (0,) * n
            if any(not 0 <= x < light.colours for x in colours):
                raise InvalidInput("bad colours")
            seeds.append((tuple(p[v] for v in c.robots), colours))
        if world_bulk.unsupported(w, n, sched, light.colours, visits=task.visits,
                                  anonymity=reduce, symmetries=symmetries,
                                  meeting=frozenset(m0)) is not None:
            raise InvalidInput("the bulk engine cannot run this class")
        memory = settings.max_memory_mb if settings.max_memory_mb is not None \
            else DEFAULT_MAX_MEMORY_MB
        limits = Limits(max_states=settings.max_states * len(items),
                        max_seconds=settings.max_seconds, max_memory_mb=memory)
        self.n = n
        self.search = world_bulk.search(w, seeds[0][0], moves, sched,
                                        colours=seeds[0][1], visits=task.visits,
                                        anonymity=reduce, symmetries=symmetries,
                                        meeting=frozenset(m0), limits=limits, seeds=seeds)

    def rows(self) -> dict[int, dict[str, Any]]:
        """The rows the union decides, by index (:meth:`why_not` says why of the others)."""
        s = self.search
        if not s.complete or s.halt is not None or s.arrays is None or s.seed_ids is None:
            self.unfinished = "the union search did not finish (a crash, no rule or a limit)"
            return {}
        a = s.arrays
        offsets = np.asarray(a.offsets, dtype=np.int64)
        targets = np.asarray(a.targets, dtype=np.int64)
        total = len(offsets) - 1
        sources = np.repeat(np.arange(total, dtype=np.int64), np.diff(offsets))
        doomed = _reaching(self._bad(sources, targets), sources, targets)
        forward = (offsets, targets)
        out = {}
        w, settings = self.world, self.settings
        for (index, c), ids in zip(self.items, s.seed_ids, strict=True):
            starts = np.unique(np.asarray(ids, dtype=np.int64))
            if doomed[starts].any():
                self.reasons[index] = "a failing state is reachable"
                continue
            seen = _reachable(starts, *forward)
            states = int(seen.size)
            if states > settings.max_states:
                self.reasons[index] = "more states than max-states"
                continue
            transitions = int((offsets[seen + 1] - offsets[seen]).sum())
            out[index] = row(
                key=world_key(w, c), index=index, class_=w.name, verdict="VERIFIED",
                robots=[w.node_to_json(v) for v in c.robots] if not c.colours else [
                    [w.node_to_json(v), colour]
                    for v, colour in zip(c.robots, c.colours, strict=True)],
                meeting_nodes=[w.node_to_json(v) for v in c.meeting],
                states=states, transitions=transitions, n=len(c.robots), seconds=0.0)
        return out

    def why_not(self, index: int) -> str:
        """Why the union left the configuration ``index`` to its own check."""
        return self.unfinished or self.reasons[index]

    def _bad(self, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """Per state of the union: whether a part of the task fails there (the states a
        configuration must not reach to be VERIFIED)."""
        s = self.search
        a = s.arrays
        assert a is not None
        total = len(a.offsets) - 1
        final = np.asarray(a.final, dtype=bool)
        nodes = np.asarray(a.nodes)[:total]
        bad = np.zeros(total, dtype=bool)
        together = (nodes == nodes[:, :1]).all(axis=1)
        for part in self.parts:
            if part in ("final", "gathered-when-final"):
                bad |= final & ~together
                if part == "final":
                    bad |= final & together & ~np.isin(nodes[:, 0], np.array(self.m0))
            elif part == "explored-when-final":
                everything = (1 << self.world.size) - 1
                for sid in np.flatnonzero(final):
                    if s.keys[int(sid)][1] != everything:
                        bad[sid] = True
            elif part == "exclusivity":
                ordered = np.sort(nodes, axis=1)
                bad |= (ordered[:, 1:] == ordered[:, :-1]).any(axis=1)
                if a.crossing is not None:
                    bad[sources[np.asarray(a.crossing, dtype=bool)]] = True
            elif part == "termination":
                bad |= self._fair(np.ones(total, dtype=bool), sources, targets,
                                  skip_final=True, single_states=False)
            elif part == "perpetual-exploration":
                for v in range(self.world.size):
                    bad |= self._fair(~(nodes == v).any(axis=1), sources, targets,
                                      skip_final=False, single_states=True)
            else:  # pragma: no cover - every task part is named above
                raise InvalidInput(f"the union cannot decide {part}")
        return bad

    def _fair(self, inside: np.ndarray, sources: np.ndarray, targets: np.ndarray, *,
              skip_final: bool, single_states: bool) -> np.ndarray:
        """The states of every fair component of the states ``inside`` (§5; the same
        components as :func:`gather_verify.tasks.base.livelock`, all of them)."""
        from gather_verify.kernels import world as kw

        a = self.search.arrays
        assert a is not None
        total = len(inside)
        labels, count = kw.scc_labels(a.offsets, a.targets, np.ascontiguousarray(inside))
        if count == 0:
            return np.zeros(total, dtype=bool)
        member = labels >= 0
        size = np.bincount(labels[member], minlength=count)
        has_final = np.zeros(count, dtype=bool)
        has_final[labels[member & np.asarray(a.final, dtype=bool)]] = True
        covered = np.zeros(count, dtype=np.int64)
        np.bitwise_or.at(covered, labels[member], np.asarray(a.stay, dtype=np.int64)[member])
        inner = (targets < total)
        inner[inner] = labels[targets[inner]] == labels[sources[inner]]
        inner &= labels[sources] >= 0
        np.bitwise_or.at(covered, labels[sources[inner]],
                         np.asarray(a.robots, dtype=np.int64)[inner])
        fair = covered == (1 << self.n) - 1
        if not single_states:
            fair &= size > 1
        if skip_final:
            fair &= ~has_final
        return member & fair[np.maximum(labels, 0)]


def _reaching(bad: np.ndarray, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """The states from which a ``bad`` state is reachable (themselves included)."""
    total = len(bad)
    keep = targets < total
    order = np.argsort(targets[keep], kind="stable")
    preds = sources[keep][order]
    offsets = np.searchsorted(targets[keep][order], np.arange(total + 1))
    mark = bad.copy()
    frontier = np.flatnonzero(bad)
    while frontier.size:
        nxt = _gather(frontier, offsets, preds)
        nxt = np.unique(nxt[~mark[nxt]])
        mark[nxt] = True
        frontier = nxt
    return mark


def _reachable(starts: np.ndarray, offsets: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """The states reachable from ``starts`` (sorted ids)."""
    total = len(offsets) - 1
    mark = np.zeros(total, dtype=bool)
    mark[starts] = True
    frontier = starts
    while frontier.size:
        nxt = _gather(frontier, offsets, targets)
        nxt = np.unique(nxt[~mark[nxt]])
        mark[nxt] = True
        frontier = nxt
    return np.flatnonzero(mark)


def _gather(frontier: np.ndarray, offsets: np.ndarray, values: np.ndarray) -> np.ndarray:
    """``values[offsets[f]:offsets[f + 1]]`` for every ``f`` of ``frontier``, joined."""
    lo = offsets[frontier]
    counts = offsets[frontier + 1] - lo
    if not counts.sum():
        return np.zeros(0, dtype=np.int64)
    at = np.repeat(lo - np.cumsum(counts) + counts, counts) + np.arange(int(counts.sum()))
    return values[at]
