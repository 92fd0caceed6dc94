"""The bulk search of luminous robots on the paper's world (SEMANTICS.md §4, §10): what
:func:`~gather_verify.engine.explore.explore_reference` finds with ``lights``, on numpy
arrays: :func:`~gather_verify.engine.fast_explore.explore_fast` with ``lights``, which
takes its face and its setup from here.

It explores exactly the reference's states, with the same ids in the same order, the same
parents, edges, witnesses and traces. A state is its reference key
(:class:`~gather_verify.engine.encoding.LuminousEncoding`: robot codes
``(cell * SLOTS + d) * K + colour``, sorted and minimised over ``Aut(M)`` when the reductions
are on; the symmetries move nodes and pending steps together, never colours, so the
canonical form acts on each robot's (node, pending, colour) as one). What it shares with
the oblivious bulk engine: the search loop itself
(:func:`~gather_verify.engine.bulk_loop.bulk_search`: the colour is one more digit of a
robot's code, and :class:`Luminous` is its face for lights), the hash index of keys, the
canonical keys of code rows (:class:`~gather_verify.engine.canonical_keys.Canon`), the
successor keys (:func:`~gather_verify.engine.bulk_step.successor_keys`, compiled when the
kernels run) and the column checks of the properties. What is its own:

- :class:`LitTable`, the luminous configurations met (the sorted (node, colour) pairs), each
  with the reference's own :class:`~gather_verify.properties.facts.ConfigurationFacts` (the
  same facts object, so every property reads what it reads in the reference) and each
  robot's actions as a bit set (:func:`schedulers.base.luminous_order`);
- the scheduler's ``bulk_luminous``: the events of ``luminous`` in bulk (a Look sets the
  pending step and the colour at once; a colour change while staying is an event; a round
  that changes nothing is a self-loop, as on Z² without lights).

>>> from gather_verify.engine.explore import explore_reference
>>> from gather_verify.engine.fast_explore import explore_fast
>>> from gather_verify.model.configuration import Configuration
>>> from gather_verify.model.view import Lights
>>> c = Configuration([(1, 1), (3, 2)], [(0, 0), (4, 0)], initial=True)
>>> e = explore_fast(c, "beacon", "async", lights=Lights(2), reduction=False)
>>> r = explore_reference(c, "beacon", "async", lights=Lights(2), reduction=False)
>>> (e.states, e.transitions) == (r.states, r.transitions) and list(e.keys) == r.keys
True
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from functools import partial
from itertools import islice
from typing import Any, cast

import numpy as np

from gather_verify.engine.bulk_loop import Face
from gather_verify.engine.bulk_step import cell_ranks, successor_codes
from gather_verify.engine.canonical_keys import decode_keys
from gather_verify.engine.checks import Checks, ColumnChecks
from gather_verify.engine.encoding import (
    NO_LIMITS,
    Limits,
    LuminousEncoding,
    region_box,
    symmetry_group,
)
from gather_verify.engine.explore import (
    Request,
    TurnState,
    lit_configuration,
    lit_initial_state,
    luminous_events,
    luminous_facts_cache,
    luminous_steps,
    turns_of,
)
from gather_verify.engine.facts_table import BIT, ReadsIdle
from gather_verify.engine.key_index import KeyIndex
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import SLOTS
from gather_verify.model.view import Lights
from gather_verify.properties.facts import ConfigurationFacts, StateFacts
from schedulers import Scheduler, State, as_scheduler

CHUNK = 1 << 13
"""States expanded per bulk step (fewer when their events are many)."""
EVENTS = 1 << 19
MAX_IDS = 2**31 - 2
MAX_ACTIONS = 62
"""A robot's actions (``SLOTS`` = degree + 1 per colour) are the bits of one ``int64`` mask."""


def unsupported(initial: Configuration, scheduler: str | Scheduler, lights: Lights, *,
                reduction: bool = True, symmetry: bool | None = None, frames: str = "all",
                limits: Limits = NO_LIMITS, **_: object) -> str | None:
    """Why this engine cannot run a luminous search (one line), or None when it can."""
    sched = as_scheduler(scheduler)  # an unknown name is an error, not a fallback
    if not hasattr(sched, "bulk_luminous"):
        return f"the scheduler {sched.name} has no bulk face for lights (bulk_luminous)"
    if SLOTS * lights.colours > MAX_ACTIONS:
        return f"{lights.colours} colours: a robot has more than {MAX_ACTIONS} actions"
    symmetry = reduction if symmetry is None else symmetry
    group = symmetry_group(initial, frames) if symmetry else []
    x0, y0, x1, y1 = region_box(initial, limits.margin, group)
    base = (x1 - x0 + 1) * (y1 - y0 + 1) * SLOTS * lights.colours
    turns = turns_of(sched, initial.n, False, base)
    if not (base ** initial.n < 2**63 if turns is None else turns.fits()):
        return "a state does not fit 63 bits"
    return None


class LitRowFacts(ReadsIdle):
    """A configuration's :class:`ConfigurationFacts` as the column checks read them: with
    ``idle`` given, a state's facts, and ``read_idle`` tells whether a predicate read it."""

    __slots__ = ("facts", "_idle", "read_idle")

    def __init__(self, facts: ConfigurationFacts, idle: bool | None = None):
        self.facts, self._idle, self.read_idle = facts, idle, False

    def __getattr__(self, name: str) -> Any:
        return getattr(self.facts, name)


class LitTable:
    """Per luminous configuration (sorted ``cell * K + colour``, packed), a row: its facts
    (the reference's, from ``facts``) and, per sorted robot, its actions as a bit set
    (bit ``k * K + c``: ``STEPS[k]``, k = ``len(STEPS)`` staying, with colour c); ``flags[row]`` is 1
    when the algorithm gives no actions there (no rule, or a crash)."""

    def __init__(self, enc: LuminousEncoding, n: int,
                 facts: Callable[[Any], ConfigurationFacts]):
        self.enc, self.n, self.colours, self.facts_of = enc, n, enc.colours, facts
        self.index = KeyIndex(bits=10, capacity=1024)
        self.weights = np.array([(enc.cells * enc.colours) ** j for j in range(n)],
                                dtype=np.int64)
        self.masks = np.zeros((1024, n), dtype=np.int64)
        self.flags = np.zeros(1024, dtype=np.int8)
        self.facts: list[ConfigurationFacts] = []

    def locate(self, codes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each state's row (robot codes per row; new configurations' facts computed) and,
        per robot, the position of its (cell, colour) among the sorted ones."""
        k = self.colours
        lit = codes // (SLOTS * k) * k + codes % k
        srt = np.sort(lit, axis=1)
        ids, first = self.index.find_or_add((srt @ self.weights).astype(np.uint64))
        if len(first):
            self._add(srt[first])
        return ids, cell_ranks(lit, srt)

    def _add(self, srt: np.ndarray) -> None:
        start = len(self.facts)
        if start + len(srt) > len(self.masks):
            size = max(start + len(srt), 2 * len(self.masks))
            self.masks = np.resize(self.masks, (size, self.n))
            self.flags = np.resize(self.flags, size)
        k, node = self.colours, self.enc.node
        for row, cells in enumerate(srt.tolist(), start):
            robots = tuple((node(c // k), c % k) for c in cells)
            f = self.facts_of(robots)
            self.facts.append(f)
            acts = f.actions
            self.flags[row] = acts is None
            self.masks[row] = [0] * self.n if acts is None else [
                sum(1 << ((BIT[d[0] - v[0], d[1] - v[1]].bit_length() - 1) * k + c2)
                    for d, c2 in acts[v, c]) for v, c in robots]


def luminous(initial: Configuration, req: Request, detection: str, lights: Lights,
             colours: Sequence[int] | None, properties: Iterable[str] | None
             ) -> tuple[Luminous, Checks, ColumnChecks, State]:
    """The luminous side of :func:`~gather_verify.engine.fast_explore.explore_fast`'s setup:
    its :class:`Luminous` face (the encoding with colours, the :class:`LitTable`), the
    property checks on that table (the initial configuration's discovery checked), and the
    initial state."""
    enc = LuminousEncoding(req.box, req.group, req.relabel, lights.colours)
    n, k = initial.n, lights.colours
    turns = turns_of(req.scheduler, n, req.anonymity, enc.base)
    facts = luminous_facts_cache(req.algorithm, initial, detection, req.frame_elements, lights)
    table = LitTable(enc, n, facts)
    start = lit_initial_state(initial.robots, colours)
    checks = Checks(properties, StateFacts(facts(lit_configuration(start)), True))
    columns = ColumnChecks(checks, lambda row, idle=None: LitRowFacts(table.facts[row], idle),
                           lambda rows, idle: [LitRowFacts(table.facts[r], i) for r, i in
                                               zip(rows.tolist(), idle.tolist(), strict=True)])
    init_rows, _ = table.locate(np.array([[enc.code(r[0], None) * k + r[2]  # type: ignore[misc]
                                           for r in start]], dtype=np.int64))
    columns.states(0, init_rows, np.ones(1, dtype=bool), checks.on_discovery)
    return Luminous(enc, n, req.scheduler, turns, facts, req.reduced, table), checks, columns, \
        start


class Luminous(Face):
    """:class:`~gather_verify.engine.bulk_loop.Face` of luminous robots: a robot's code
    has its colour as one more digit, and a :class:`LitTable` gives its actions."""

    chunk = CHUNK
    enc: LuminousEncoding

    def __init__(self, enc: LuminousEncoding, n: int, sched: Scheduler, turns: Any,
                 facts: Callable[[Any], ConfigurationFacts], reduced: bool, table: LitTable):
        super().__init__(enc, n, sched, turns, facts, reduced)
        self.table, self.k = table, enc.colours

    def decode(self, keys: np.ndarray) -> tuple[np.ndarray, ...]:
        codes = decode_keys(keys, self.enc.base, self.n)
        rows, rank = self.table.locate(codes)
        return keys, codes, None, rows, self.idle(codes), rank  # type: ignore[return-value]

    def no_actions(self, rows: np.ndarray) -> np.ndarray:
        return self.table.flags[rows]

    def events(self, codes: np.ndarray, rows: np.ndarray, rank: np.ndarray,
               extra: np.ndarray | None) -> Any:
        frontier = self.enc.frontier(codes, self.table.masks[rows[:, None], rank])
        if extra is None:
            return self.sched.bulk_luminous(frontier, EVENTS, self.k)
        return cast(Any, self.sched).bulk_luminous(frontier, EVENTS, self.k, extra=extra)

    def after_rows(self, codes: np.ndarray, cells: np.ndarray | None, src: np.ndarray,
                   robot: np.ndarray, new: np.ndarray, event: np.ndarray | None,
                   succ_codes: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
        return self.rows_of(successor_codes(codes, src, robot, new, event)), succ_codes

    def rows_of(self, codes: np.ndarray) -> np.ndarray:
        return self.table.locate(codes)[0]

    def idle(self, codes: np.ndarray) -> np.ndarray:
        return np.all(codes // self.k % SLOTS == 0, axis=1)

    def witness(self, keys: np.ndarray, src: np.ndarray,
                succ_codes: np.ndarray | None) -> Callable[[int], tuple[Any, State]]:
        return partial(_step, self.enc, self.sched, self.facts, self.n, keys, src,
                       turns=self.turns)


def _step(enc: LuminousEncoding, sched: Any, facts: Callable[[Any], ConfigurationFacts],
          n: int, keys: np.ndarray, src: np.ndarray, i: int, turns: Any = None
          ) -> tuple[Any, State]:
    """The event and successor of the ``i``-th transition of a bulk step, asked of the
    scheduler's ``luminous`` on its decoded source state: its ``k``-th event, k its rank
    among its state's events (the bulk events come in the same order)."""
    state = enc.decode(int(keys[src[i]]), n)
    rank = i - int(np.searchsorted(src, src[i]))
    if turns is not None:
        event, succ, after = next(islice(luminous_steps(
            sched, state, facts(lit_configuration(state)), turns.extra(int(keys[src[i]]))),
            rank, None))
        return event, TurnState(succ, after)
    return next(islice(luminous_events(sched, state, facts(lit_configuration(state))), rank,
                       None))

