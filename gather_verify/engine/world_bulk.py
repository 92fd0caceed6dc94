"""The bulk search on a finite world: what :func:`gather_verify.engine.world_search.search`
finds, on numpy arrays and compiled kernels (SEMANTICS.md §4, §9-11).

It finds the same :class:`~gather_verify.engine.world_search.WorldSearch`: the same states
with the same ids (breadth-first, in the order the reference meets them), the same parents,
edges, transitions, final and stay facts, the same halt and the same stop under a state
limit. What changes is how:

- a state is one ``int64`` (:mod:`gather_verify.kernels.world` gives the layout): per robot
  its node, its pending destination as a slot of the world's neighbour table (none, or
  one of the node's neighbours: the table is as wide as the world's degree) and its
  colour; then the visited nodes and the round-robin scheduler's order and turn;
- visited states live in the bulk engine's hash index (:class:`KeyIndex`) of their keys
  (their least images under the reductions, when those are on: under round-robin the
  robots first relabelled as the scheduler says, from a table asked of it once); the stored
  state is the first concrete successor met, as in the reference;
- the algorithm is asked once per configuration (the robots' nodes and colours: the
  robots are oblivious, so pending moves play no part), through
  :meth:`~gather_verify.worlds.moves.WorldMoves.table`; each robot's answers become a bit
  set over its node's possible actions, in the order the schedulers try them;
- the frontier is expanded a chunk of states at a time by a compiled kernel per scheduler
  (ASYNC; the rounds of FSYNC, SSYNC, centralized and round-robin).

The edges are kept as arrays; :attr:`WorldSearch.edges` builds a state's list of
``(target, robots, Event)`` when asked (a trace), from the scheduler's own ``luminous``;
the tasks read the arrays (:attr:`WorldSearch.arrays`). :func:`unsupported` says when this
engine cannot run a request (the compiled kernels switched off, a key past 63 bits, a
scheduler it does not know); the caller then runs the reference.

>>> from gather_verify.algorithms import get_algorithm
>>> from gather_verify.worlds import get_world
>>> from gather_verify.worlds.moves import WorldMoves
>>> ring = get_world("ring:9")
>>> moves = WorldMoves(ring, get_algorithm("go-to-target"), frozenset({7}))
>>> s = search(ring, (0, 3, 5), moves, "async")
>>> s.states, s.transitions, s.stopped, s.engine
(225, 560, None, 'bulk')
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from gather_verify import kernels
from gather_verify.algorithms.base import AlgorithmCrash, Unhandled
from gather_verify.engine.bfs import EVENT_CUT
from gather_verify.engine.chunks import drive
from gather_verify.engine.columns import Growing, glibc
from gather_verify.engine.encoding import NO_LIMITS, Limits, Stop, rss_mb
from gather_verify.engine.key_index import KeyIndex
from gather_verify.engine.world_search import (
    Halt,
    Relabel,
    SearchArrays,
    WorldSearch,
    WorldState,
    canonicaliser,
    relabeller,
)
from gather_verify.kernels.codes import NO_EDGE
from gather_verify.progress import PROGRESS
from schedulers import Event, Scheduler, as_scheduler

if TYPE_CHECKING:
    from gather_verify.worlds.base import World
    from gather_verify.worlds.moves import WorldMoves

CHUNK = 1 << 13
"""States expanded per bulk step at first (halved while a step makes more than
:data:`~gather_verify.engine.world_bulk.EVENTS` events, doubled up to
:data:`~gather_verify.engine.world_bulk.MAX_CHUNK` while it makes fewer)."""
MAX_CHUNK = 1 << 16
"""The most states expanded per bulk step."""
EVENTS = 1 << 20
"""About how many events a bulk step may make before the next step takes fewer states."""
KEY_LIMIT = 1 << 63


Why = tuple[str, str, dict[str, object]]
"""Why a configuration has no answer: ``crash`` or ``defined``, the reason, the detail."""


def unsupported(world: World, n: int, scheduler: str | Scheduler, colours: int, *, visits: bool = False,
                anonymity: bool = False, symmetries: Sequence[Sequence[int]] = (),
                meeting: frozenset[int] = frozenset()) -> str | None:
    """Why the bulk engine cannot run this search (one line), or None when it can."""
    if not kernels.enabled():
        return "the compiled kernels are off (numba missing, or GATHER_VERIFY_KERNELS=numpy)"
    sched = as_scheduler(scheduler)
    if not hasattr(sched, "activations"):  # a scheduler of the user's that declares none
        return f"the scheduler {sched.name} does not say which robots its rounds activate"
    if getattr(sched, "phased", False):
        return f"the phase scheduler {sched.name} runs on the reference engine"
    stateful = getattr(sched, "stateful", False)
    if n < 1 or n > 62:
        return f"{n} robots (the bulk engine takes 1 to 62)"
    if (world.degree + 1) * colours > 63:
        return (f"a robot has {(world.degree + 1) * colours} possible actions (degree + 1 "
                "times the colours; at most 63)")
    starts = len(sched.starts(n)) if stateful else 1  # type: ignore[attr-defined]
    radix = world.size * (world.degree + 1) * colours
    if radix ** n * (1 << world.size if visits else 1) * (n * starts if stateful else 1) \
            >= KEY_LIMIT:
        return "a state does not fit 63 bits"
    return None


def _group(symmetries: Sequence[Sequence[int]], meeting: frozenset[int]) -> list[Sequence[int]]:
    """The symmetries the reductions use: those fixing the meeting nodes (as the reference)."""
    return [p for p in symmetries if frozenset(p[m] for m in meeting) == meeting]


class _Plan:
    """The static tables of one search: the world's neighbour table, each node's possible
    actions in the schedulers' order, the key layout."""

    def __init__(self, world: World, n: int, colours: int, visits: bool, sched: Any,
                 starts: list[Any]):
        size, adjacency = world.size, world.adjacency
        self.n, self.size, self.colours, self.visits = n, size, colours, visits
        self.adjacency = adjacency
        degree = max(1, world.degree)
        self.pend = world.degree + 1
        # node v's neighbours, NO_EDGE past its degree (no such edge: an illegal move; a
        # finite world has no OUTSIDE, its search region is the whole world)
        self.adj = np.full((size, degree), NO_EDGE, dtype=np.int64)
        for v, nbrs in enumerate(adjacency):
            self.adj[v, :len(nbrs)] = nbrs
        width = max((len(a) + 1) * colours for a in adjacency)
        self.act_node = np.zeros((size, width), dtype=np.int64)
        self.act_col = np.zeros((size, width), dtype=np.int64)
        self.act_slot = np.zeros((size, width), dtype=np.int64)
        self.stay_bit = np.zeros((size, colours), dtype=np.int64)
        self.bit: list[dict[tuple[int, int], int]] = []
        self.action: list[list[tuple[int, int]]] = []
        for v, nbrs in enumerate(adjacency):
            # the schedulers try a robot's actions sorted by repr: bit b is the b-th of them
            acts = sorted(((d, c) for d in (v, *nbrs) for c in range(colours)), key=repr)
            self.action.append(acts)
            self.bit.append({a: b for b, a in enumerate(acts)})
            for b, (d, c) in enumerate(acts):
                self.act_node[v, b], self.act_col[v, b] = d, c
                self.act_slot[v, b] = 0 if d == v else 1 + nbrs.index(d)
            for c in range(colours):
                self.stay_bit[v, c] = self.bit[v][v, c]
        self.radix = size * self.pend * colours
        codes = np.arange(self.radix, dtype=np.int64)  # a robot's code -> its parts
        self.rc_col = codes % colours
        self.rc_slot = codes // colours % self.pend
        self.rc_node = codes // colours // self.pend
        self.vb = 1 << size if visits else 1
        self.pw = np.array([self.radix ** i for i in range(n + 1)], dtype=np.int64)
        self.cfg_base = size * colours
        self.starts, self.sched = starts, sched
        # a scheduler that keeps its own state (round-robin): the kernel reads whose turn it
        # is off its ``state_index``, a start's place times n plus the turn
        self.rr = bool(getattr(sched, "stateful", False))
        self.rr_orders = np.array([list(order) for order, _ in starts] if self.rr else [[0] * n],
                                  dtype=np.int64).reshape(-1, n)
        # the rounds' subsets (ASYNC: one robot at a time; round-robin reads its own turn)
        active = sched.activations(n)
        self.subsets = np.eye(n, dtype=np.bool_) if active is None else \
            np.ascontiguousarray(active, dtype=np.bool_).reshape(-1, n)

    def pack(self, robots: Sequence[tuple[int, int | None, int]], visited: int,
             extra: int) -> int:
        key = 0
        for i, (v, p, c) in enumerate(robots):
            slot = 0 if p is None else 1 + self.adjacency[v].index(p)
            key += ((v * self.pend + slot) * self.colours + c) * self.radix ** i
        return key + (visited + self.vb * extra) * self.radix ** self.n

    def unpack(self, key: int) -> WorldState:
        robots = []
        for _ in range(self.n):
            key, rc = divmod(key, self.radix)
            t, c = divmod(rc, self.colours)
            v, slot = divmod(t, self.pend)
            robots.append((v, None if slot == 0 else self.adjacency[v][slot - 1], c))
        extra, visited = divmod(key, self.vb)
        if self.rr:
            return tuple(robots), visited, self.sched.state_of(extra, self.n)
        return tuple(robots), visited, None

    def mask(self, v: int, actions: frozenset[tuple[int, int]]) -> int:
        bits = self.bit[v]
        out = 0
        for a in actions:
            out |= 1 << bits[a]
        return out


class _Relabelled:
    """Anonymity on packed keys under a scheduler that keeps its own state
    (:func:`~gather_verify.engine.world_search.relabeller`): each of its states' relabelling,
    asked of the scheduler once, as a table (its ``state_index`` -> the robots' new order
    and its state after), applied to a column of keys at a time."""

    def __init__(self, plan: _Plan, relabel: Relabel):
        n = plan.n
        count = plan.sched.state_count(n)
        self.perm = np.zeros((count, n), dtype=np.int64)
        self.to = np.zeros(count, dtype=np.int64)
        for i in range(count):
            perm, after = relabel(plan.sched.state_of(i, n))
            self.perm[i] = perm
            self.to[i] = plan.sched.state_index(after, n)
        self.plan = plan

    def __call__(self, keys: np.ndarray) -> np.ndarray:
        """Each key with its robots relabelled and the scheduler's state replaced."""
        plan, n = self.plan, self.plan.n
        pw = plan.pw
        codes = keys[:, None] // pw[None, :n] % plan.radix
        rest = keys // pw[n]
        visited, extra = rest % plan.vb, rest // plan.vb
        codes = np.take_along_axis(codes, self.perm[extra], axis=1)
        return (codes * pw[None, :n]).sum(axis=1) + (visited + plan.vb * self.to[extra]) * pw[n]


class _Configurations:
    """Each configuration met (the sorted (node, colour) pairs of a state's robots), once:
    its robots' action bit sets by sorted position, or why the algorithm gave none."""

    def __init__(self, plan: _Plan, moves: WorldMoves):
        self.plan, self.moves = plan, moves
        self.index = KeyIndex(bits=12, capacity=1 << 12)
        self.masks = np.zeros((1 << 12, plan.n), dtype=np.int64)
        self.halted = np.zeros(1 << 12, dtype=np.bool_)
        self.why: dict[int, tuple[str, str, dict[str, object]]] = {}
        self.mask_of: dict[tuple[int, frozenset[tuple[int, int]]], int] = {}
        """A node's action set -> its bit set (algorithms answer few distinct sets)."""

    def chunk(self, nodes: np.ndarray, cols: np.ndarray, ckey: np.ndarray, pos: np.ndarray
              ) -> tuple[np.ndarray, int, Why | None]:
        """The robots' bit sets of a chunk's states, as far as the first state whose
        configuration has no answer (its index, and why; else the chunk's length, None)."""
        rows = self.rows(ckey, nodes, cols)
        bad = self.halted[rows]
        cut = int(np.argmax(bad)) if bad.any() else len(rows)
        why = self.why[int(rows[cut])] if cut < len(rows) else None
        return self.masks[rows[:cut, None], pos[:cut]], cut, why

    def rows(self, ckey: np.ndarray, nodes: np.ndarray, cols: np.ndarray) -> np.ndarray:
        rows, first = self.index.find_or_add(ckey.view(np.uint64))
        if len(first):
            count = self.index.count
            if count > len(self.masks):
                grow = max(count, 2 * len(self.masks))
                self.masks = np.resize(self.masks, (grow, self.plan.n))
                self.halted = np.resize(self.halted, grow)
            new = rows[first]
            self.halted[new] = False
            got = [self._evaluate(row, v, c) for row, v, c in zip(
                new.tolist(), nodes[first].tolist(), cols[first].tolist(), strict=True)]
            self.masks[new] = got
        return rows

    def _evaluate(self, row: int, nodes: list[int], cols: list[int]) -> list[int]:
        """The bit sets of a new configuration's robots, by sorted position (zeros when the
        algorithm gives none: the row is marked halted, with why)."""
        seen = tuple(sorted(zip(nodes, cols, strict=True)))
        try:
            table = self.moves.table(seen)
        except AlgorithmCrash as error:
            self.halted[row] = True
            self.why[row] = ("crash", error.reason, error.detail())
            return [0] * len(seen)
        except Unhandled as error:
            self.halted[row] = True
            self.why[row] = ("defined", f"the algorithm has no rule here: {error}", {})
            return [0] * len(seen)
        cache, mask = self.mask_of, self.plan.mask
        out = []
        for v, c in seen:
            actions = table[v, c]
            m = cache.get((v, actions))
            if m is None:
                m = cache[v, actions] = mask(v, actions)
            out.append(m)
        return out

    def actions(self, robots: Sequence[tuple[int, int | None, int]]
                ) -> list[frozenset[tuple[int, int]]]:
        """Each robot's actions in the configuration of ``robots`` (met already), read back
        from its row's bit sets (what the kernels used)."""
        plan = self.plan
        seen = sorted((v * plan.colours + c) for v, _, c in robots)
        key = sum(e * plan.cfg_base ** j for j, e in enumerate(seen))
        count = self.index.count
        rows, _ = self.index.find_or_add(np.array([key], dtype=np.uint64))
        row = int(rows[0])
        if row >= count or self.halted[row]:  # pragma: no cover - never for a stored edge
            raise AssertionError(f"configuration {seen} was not expanded")
        out = []
        for v, _, c in robots:
            m = int(self.masks[row, seen.index(v * plan.colours + c)])
            out.append(frozenset(a for b, a in enumerate(plan.action[v]) if m >> b & 1))
        return out


class _Nodes:
    """:class:`_Configurations` for an algorithm whose answers depend on the robot's node
    only (``WorldMoves.by_node``, go-to-target): each (node, colour)'s bit set, asked once
    (``known``: 0 not asked yet, 1 answered, 2 no answer)."""

    def __init__(self, plan: _Plan, moves: WorldMoves):
        self.plan, self.moves = plan, moves
        self.masks = np.zeros(plan.size * plan.colours, dtype=np.int64)
        self.known = np.zeros(plan.size * plan.colours, dtype=np.int8)

    def learn(self, nodes: list[int], cols: list[int]) -> None:
        """Ask the algorithm for the pairs of one configuration that are not asked yet, in
        its robots' order (a pair it gives no answer for is marked 2)."""
        seen = tuple(sorted(zip(nodes, cols, strict=True)))
        for v, c in zip(nodes, cols, strict=True):
            pair = v * self.plan.colours + c
            if self.known[pair]:
                continue
            try:
                actions = self.moves.table_of(seen, v, c)
            except (AlgorithmCrash, Unhandled):
                self.known[pair] = 2
                continue
            self.masks[pair] = self.plan.mask(v, actions)
            self.known[pair] = 1

    def why(self, nodes: list[int], cols: list[int]) -> Why:
        """The reference's own error for a configuration with a pair that has no answer:
        its configuration's table, asked as the reference asks."""
        seen = tuple(sorted(zip(nodes, cols, strict=True)))
        try:
            self.moves.table(seen)
        except AlgorithmCrash as error:
            return "crash", error.reason, error.detail()
        except Unhandled as error:
            return "defined", f"the algorithm has no rule here: {error}", {}
        raise AssertionError(f"the algorithm answered {seen} after failing on it")  # pragma: no cover

    def chunk(self, nodes: np.ndarray, cols: np.ndarray, ckey: np.ndarray, pos: np.ndarray
              ) -> tuple[np.ndarray, int, Why | None]:
        pairs = nodes * self.plan.colours + cols
        for s in np.flatnonzero((self.known[pairs] == 0).any(axis=1)).tolist():
            self.learn(nodes[s].tolist(), cols[s].tolist())
        bad = (self.known[pairs] == 2).any(axis=1)
        if not bad.any():
            return self.masks[pairs], len(pairs), None
        cut = int(np.argmax(bad))
        return self.masks[pairs[:cut]], cut, self.why(nodes[cut].tolist(), cols[cut].tolist())

    def expand(self, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                np.ndarray, np.ndarray, int, Why | None]:
        """ASYNC on a chunk of states in one compiled pass
        (:func:`~gather_verify.kernels.world.world_async_by_node`), asking the algorithm for
        the pairs it meets first on the way: per event its state, its successor and its
        robots' mask; per state its events' end, final and stay; the states expanded (up to
        the first whose configuration has no answer) and why they stop there (or None)."""
        from gather_verify.kernels import world as kw

        plan = self.plan
        parts: list[tuple[np.ndarray, ...]] = []
        done, events, why = 0, 0, None
        while True:
            cut, src, succ, rmask, ends, fin, sty = kw.world_async_by_node(
                keys[done:], plan.n, plan.radix, plan.rc_node, plan.rc_slot, plan.rc_col,
                self.masks, self.known, plan.adj, plan.act_node, plan.act_col, plan.act_slot,
                plan.stay_bit, plan.pw, plan.visits, plan.pend, plan.colours, plan.vb)
            parts.append((src + done, succ, rmask, ends + events, fin, sty))
            done, events = done + cut, events + len(src)
            if done == len(keys):
                break
            robots = plan.unpack(int(keys[done]))[0]
            nodes, cols = [v for v, _, _ in robots], [c for _, _, c in robots]
            self.learn(nodes, cols)
            if (self.known[[v * plan.colours + c for v, c in zip(nodes, cols, strict=True)]]
                    == 2).any():
                why = self.why(nodes, cols)
                break
        src, succ, rmask, ends, fin, sty = (parts[0] if len(parts) == 1 else [
            np.concatenate(column) for column in zip(*parts, strict=True)])
        return src, succ, rmask, ends, fin, sty, done, why

    def actions(self, robots: Sequence[tuple[int, int | None, int]]
                ) -> list[frozenset[tuple[int, int]]]:
        plan = self.plan
        out = []
        for v, _, c in robots:
            m = int(self.masks[v * plan.colours + c])
            out.append(frozenset(a for b, a in enumerate(plan.action[v]) if m >> b & 1))
        return out


class _Column(Sequence[Any]):
    """A read-only numpy column handing out Python scalars."""

    __slots__ = ("array",)

    def __init__(self, array: np.ndarray):
        self.array = array

    def __len__(self) -> int:
        return len(self.array)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return self.array[i].tolist()
        return self.array[i].item()

    def __iter__(self) -> Iterator[Any]:
        for start in range(0, len(self.array), 1 << 16):
            yield from self.array[start:start + (1 << 16)].tolist()


class _Keys(_Column):
    """The stored states, decoded when read."""

    __slots__ = ("plan",)

    def __init__(self, array: np.ndarray, plan: _Plan):
        super().__init__(array)
        self.plan = plan

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self.plan.unpack(k) for k in self.array[i].tolist()]
        return self.plan.unpack(int(self.array[i]))

    def __iter__(self) -> Iterator[Any]:
        for start in range(0, len(self.array), 1 << 16):
            yield from map(self.plan.unpack, self.array[start:start + (1 << 16)].tolist())


class _Edges(Sequence[list[tuple[int, int, Event]]]):
    """Per expanded state, its ``(target, robots, event)`` list, built when read: the events
    from the scheduler's ``luminous`` on the stored state (the same, in the same order, as
    the kernel's), the targets and masks from the arrays."""

    def __init__(self, arrays: SearchArrays, keys: _Keys, sched: Any,
                 actions: Callable[..., list[frozenset[tuple[int, int]]]]):
        self.arrays, self.keys, self.sched, self.actions = arrays, keys, sched, actions

    def __len__(self) -> int:
        return len(self.arrays.offsets) - 1

    def __getitem__(self, sid: Any) -> Any:
        if isinstance(sid, slice):
            return [self[i] for i in range(*sid.indices(len(self)))]
        if sid < 0:
            sid += len(self)
        if not 0 <= sid < len(self):
            raise IndexError(sid)
        robots, _, extra = self.keys[sid]
        options = self.actions(robots)
        events = [e for e, _, _ in self.sched.luminous(robots, extra, options.__getitem__)]
        lo, hi = int(self.arrays.offsets[sid]), int(self.arrays.offsets[sid + 1])
        if len(events) != hi - lo:  # pragma: no cover - the kernels and luminous disagree
            raise AssertionError(f"state {sid}: {hi - lo} edges kept, {len(events)} events")
        targets = self.arrays.targets[lo:hi].tolist()
        masks = self.arrays.robots[lo:hi].tolist()
        return list(zip(targets, masks, events, strict=True))

    def __iter__(self) -> Iterator[Any]:
        for sid in range(len(self)):
            yield self[sid]


BYTES_PER_EVENT = 64
"""What one event of a bulk step takes while it is made and stored (its state, successor,
robots, crossing, the index's answer, the edge kept), for the memory limit."""


def rounds_taken(counts: np.ndarray, stored: int, limits: Limits) -> tuple[int, Stop | None]:
    """How many of the leading states (their events ``counts``) a bulk step expands, and the
    limit that stops the search after them, if any: a state with more than
    :data:`EVENT_CUT` events that could take the states past ``max_states`` + EVENT_CUT, or
    whose events would not fit the memory left, is not expanded."""
    if not len(counts):
        return 0, None
    total = np.cumsum(counts)
    take = int(np.searchsorted(total, EVENTS, side="right")) or 1
    big = np.flatnonzero((counts[:take] > EVENT_CUT)
                         & (stored + total[:take] > limits.max_states + EVENT_CUT))
    if len(big):
        return int(big[0]), Stop.STATES
    if take == 1 and counts[0] > EVENTS and \
            rss_mb() + counts[0] * BYTES_PER_EVENT / 2**20 > limits.max_memory_mb:
        return 0, Stop.MEMORY
    return min(take, len(counts)), None


def _stored(index: KeyIndex, reps: Growing | None, lo: int, hi: int) -> np.ndarray:
    """The stored states ``lo .. hi - 1`` (as far as there are): the index's keys when they
    are the states themselves (``reps`` None: unreduced), else ``reps``."""
    if reps is None:
        return index.keys[lo:min(hi, index.count)].view(np.int64)
    return reps.data[lo:min(hi, reps.size)]


def _join(parts: list[np.ndarray], dtype: Any) -> np.ndarray:
    """The chunks of a column joined into one array, each chunk let go once copied (so the
    peak is the column and one chunk, not the column twice)."""
    out = np.empty(sum(len(p) for p in parts), dtype=dtype)
    at = 0
    parts.reverse()
    while parts:
        part = parts.pop()
        out[at:at + len(part)] = part
        at += len(part)
        del part
    _trim()
    return out


def _trim() -> None:
    """Hand the pages freed inside the C heap back to the system (glibc's ``malloc_trim``,
    where there is one): the chunks of a column are freed there, not unmapped."""
    libc = glibc()
    if libc is not None:
        libc.malloc_trim(0)


def search(world: World, robots: Sequence[int], moves: WorldMoves, scheduler: str | Scheduler, *,
           colours: Sequence[int] | None = None, visits: bool = False,
           anonymity: bool = False, symmetries: Sequence[Sequence[int]] = (),
           meeting: frozenset[int] = frozenset(), limits: Limits = NO_LIMITS,
           seeds: Sequence[tuple[Sequence[int], Sequence[int]]] | None = None) -> WorldSearch:
    """:func:`gather_verify.engine.world_search.search` in bulk (same arguments, but the
    :class:`~gather_verify.worlds.moves.WorldMoves` itself instead of its ``actions``);
    :func:`unsupported` must have said yes.

    ``seeds``: several initial states searched at once, each ``(robots, colours)`` (then
    ``robots`` and ``colours`` only give the number of robots): the union of their spaces,
    one state graph for them all (:mod:`gather_verify.sweeps.world_union`). The search's
    ``seed_ids`` give each seed's state ids (one per start of the scheduler). Each chunk of
    stored states is one :meth:`_WorldRun.step`, driven by
    :func:`~gather_verify.engine.chunks.drive`."""
    started = time.perf_counter()
    sched = as_scheduler(scheduler)
    n = len(robots)
    why = unsupported(world, n, sched, moves.lights.colours, visits=visits,
                      anonymity=anonymity, symmetries=symmetries, meeting=meeting)
    if why is not None:
        raise ValueError(f"the bulk engine cannot run this search: {why}")
    if seeds is None:
        seeds = [(robots, tuple(colours) if colours is not None else (0,) * n)]
    run = _WorldRun(world, n, moves, sched, visits, anonymity, symmetries, meeting, seeds)
    drive(run, limits, started)
    return run.result(started)


class _WorldRun:
    """One bulk search of a finite world between its chunks (:class:`~gather_verify.engine.
    chunks.Chunks`): the plan of its keys, the
    reductions, the index of the stored states (and their representatives when reduced),
    the columns kept as chunks (parents, offsets, targets, robots' masks, crossings, final,
    stay), the transitions counted, the chunk size and why it stopped."""

    def __init__(self, world: World, n: int, moves: WorldMoves, sched: Scheduler,
                 visits: bool, anonymity: bool, symmetries: Sequence[Sequence[int]],
                 meeting: frozenset[int], seeds: Sequence[tuple[Sequence[int], Sequence[int]]]):
        self.world, self.n, self.sched, self.visits = world, n, sched, visits
        self.anonymity, self.symmetries, self.meeting = anonymity, symmetries, meeting
        self.starts = getattr(sched, "starts", lambda _n: [None])(n)
        plan = self.plan = _Plan(world, n, moves.lights.colours, visits, sched, self.starts)
        self.rounds = sched.activations(n) is not None
        self.group = _group(symmetries, meeting)
        self.reduce = anonymity or len(self.group) > 1
        self.perms = np.array(self.group if len(self.group) > 1 else [list(range(world.size))],
                              dtype=np.int64).reshape(-1, world.size)
        self.relabel = relabeller(sched, n) if anonymity else None
        self.named = _Relabelled(plan, self.relabel) if self.relabel is not None else None
        self.seeds = seeds
        first_keys = np.array([plan.pack([(v, None, c) for v, c in zip(nodes, lit, strict=True)],
                                         sum(1 << v for v in set(nodes)) if visits else 0,
                                         plan.sched.state_index(self.starts[r], n)
                                         if plan.rr else 0)
                               for nodes, lit in seeds for r in range(len(self.starts))],
                              dtype=np.int64)
        self.index = KeyIndex()
        self.seed_ids, first = self.index.find_or_add(self.canon(first_keys).view(np.uint64))
        # robots' masks as the smallest unsigned type that holds them (and int64 past 32)
        self.mask_type = next((t for t, bits in ((np.uint8, 8), (np.uint16, 16),
                                                 (np.uint32, 32)) if n <= bits), np.int64)
        # unreduced, a state's key is the state itself: the index's key column is the stored
        # states, read back a chunk at a time (else the stored states are a column of their own)
        self.reps = None if not self.reduce else Growing(np.int64, 1 << 20)
        if self.reps is not None:
            self.reps.extend(first_keys[first])
        # the other columns are only appended to: kept as chunks, joined once at the end
        self.parents: list[np.ndarray] = [np.full(len(first), -1, dtype=np.int32)]
        self.configs = (_Nodes if moves.by_node else _Configurations)(plan, moves)
        self.offsets: list[np.ndarray] = [np.zeros(1, dtype=np.int64)]
        self.targets: list[np.ndarray] = []
        self.rmasks: list[np.ndarray] = []
        self.crossing: list[np.ndarray] = []
        self.final: list[np.ndarray] = []
        self.stay: list[np.ndarray] = []
        self.transitions = self.expanded = 0
        self.stopped: Stop | str | None = None
        self.halt: Halt | None = None
        self.chunk = CHUNK

    def canon(self, keys: np.ndarray) -> np.ndarray:
        """The keys' canonical keys under the reductions (the keys themselves without)."""
        from gather_verify.kernels import world as kw

        if not self.reduce:
            return keys
        if self.named is not None:  # anonymity as the scheduler relabels: no sorting after it
            keys = self.named(keys)
            if len(self.group) <= 1:
                return keys
        plan = self.plan
        return kw.world_canon(keys, self.perms, self.anonymity and self.named is None,
                              self.visits, self.n, self.world.size, plan.radix, plan.pend,
                              plan.colours, plan.adj, plan.vb, plan.pw)

    def stored(self) -> int:
        """The states stored so far (the orbit representatives, with a reduction)."""
        return self.index.count if self.reps is None else int(self.reps.size)

    def pending(self) -> bool:
        """Whether stored states are left to expand."""
        return self.expanded < self.stored()

    def rss(self) -> float:
        """The memory in use now (MB)."""
        return rss_mb()

    def chunk_done(self) -> None:
        """The progress line's count (check --progress)."""
        PROGRESS.states = self.stored()

    def step(self, limits: Limits) -> None:
        """Expand the next chunk of stored states: their events, the successors' ids (cut
        after the first state whose expansion passes the states limit), the columns, a halt
        (``stopped`` set when the search stops in it)."""
        lo = self.expanded
        keys = _stored(self.index, self.reps, lo, lo + self.chunk)
        if not self.rounds and isinstance(self.configs, _Nodes):  # ASYNC by node: one pass
            src, succ, rmask, ends, fin, sty, cut, why_halt = self.configs.expand(keys)
            cross = None
        else:
            src, succ, rmask, cross, fin, sty, cut, why_halt = self._events(keys, limits)
            ends = None
        del keys
        before = self.index.count
        ids, first = self.index.find_or_add(self.canon(succ).view(np.uint64))
        if ends is None:  # per state: its events' end
            ends = np.searchsorted(src, np.arange(cut), side="right")
        if cut and before + len(first) > limits.max_states:
            # the reference stops after the first state whose expansion passes the limit
            grown = before + np.searchsorted(first, ends, side="left")
            k = int(np.argmax(grown > limits.max_states))
            cut, self.stopped = k + 1, Stop.STATES
            first = first[:grown[k] - before]
            ends = ends[:cut]
            self.index.truncate(int(grown[k]))
        e_end = int(ends[-1]) if cut else 0
        if self.reps is not None:
            self.reps.extend(succ[first])
        self.parents.append((lo + src[first]).astype(np.int32))
        self.offsets.append(self.transitions + ends)
        self.targets.append(ids[:e_end].astype(np.int32))
        self.rmasks.append(rmask[:e_end].astype(self.mask_type))
        if cross is not None:
            self.crossing.append(cross[:e_end])
        self.final.append(fin[:cut])
        self.stay.append(sty[:cut].astype(self.mask_type))
        del src, succ, rmask, ids, first, fin, sty, cross
        self.transitions += e_end
        self.expanded = lo + cut
        if self.stopped is not None:
            return
        if why_halt is not None:
            kind, reason, detail = why_halt
            self.halt = Halt(kind, self.expanded, reason, detail)
            self.stopped = kind
            return
        self.chunk = max(1, self.chunk // 2) if e_end > EVENTS else min(MAX_CHUNK, self.chunk * 2)

    def _events(self, keys: np.ndarray, limits: Limits) -> tuple[Any, ...]:
        """The chunk's states decoded, their configurations' actions (up to the first that
        halts), a round scheduler's events weighed first (a limit may take fewer states,
        ``stopped`` set), and their events: sources, successors, robots' masks, crossings
        (rounds), each state's final flag and stay mask, the states taken, the halt."""
        from gather_verify.kernels import world as kw

        plan = self.plan
        nodes, slots, cols, rest, ckey, pos = kw.world_decode(
            keys, self.n, plan.radix, plan.rc_node, plan.rc_slot, plan.rc_col, plan.colours,
            plan.cfg_base)
        masks, cut, why_halt = self.configs.chunk(nodes, cols, ckey, pos)
        del ckey, pos
        if cut < len(keys):
            keys, nodes, slots, cols, rest = (a[:cut] for a in (keys, nodes, slots, cols, rest))
        if self.rounds:  # a round's events weighed before they are made (a limit bounds it)
            counts = kw.world_round_counts(rest // plan.vb, masks, plan.subsets, plan.rr,
                                           plan.rr_orders, plan.act_node.shape[1],
                                           float(EVENTS))
            take, self.stopped = rounds_taken(counts, self.index.count, limits)
            if take < cut:
                keys, nodes, slots, cols, rest, masks = (
                    a[:take] for a in (keys, nodes, slots, cols, rest, masks))
                cut, why_halt = take, None  # (a later state's halt: met again later)
        fin, sty = kw.world_facts(nodes, slots, cols, masks, plan.stay_bit)
        vis = rest % plan.vb
        cross = None
        if self.rounds:
            src, succ, rmask, cross = kw.world_rounds(
                keys, nodes, slots, cols, vis, rest // plan.vb, masks, plan.subsets,
                plan.rr, plan.rr_orders, plan.act_node, plan.act_col, plan.pw, self.visits,
                plan.pend, plan.colours, plan.vb, int(counts[:cut].sum()))
        else:
            src, succ, rmask = kw.world_async(
                keys, nodes, slots, cols, plan.adj, vis, masks, plan.act_node,
                plan.act_col, plan.act_slot, plan.pw, self.visits, plan.pend, plan.colours)
        return src, succ, rmask, cross, fin, sty, cut, why_halt

    def result(self, started: float) -> WorldSearch:
        """The search's result: its columns joined (each chunk let go once copied), the
        index's table let go first (its key column lives on as the stored states when
        unreduced)."""
        from gather_verify.kernels import world as kw

        plan, n = self.plan, self.n
        all_reps = _stored(self.index, self.reps, 0, self.index.count)
        del self.index

        def nodes_of() -> np.ndarray:
            return kw.world_nodes(all_reps, n, plan.radix, plan.pend, plan.colours)[0]

        mask_type = self.mask_type
        arrays = SearchArrays(_join(self.offsets, np.int64), _join(self.targets, np.int32),
                              _join(self.rmasks, mask_type),
                              _join(self.crossing, np.bool_) if self.rounds else None,
                              _join(self.final, np.bool_), _join(self.stay, mask_type),
                              nodes_of)
        keys_col = _Keys(all_reps, plan)
        return WorldSearch(
            keys=keys_col, parents=_Column(_join(self.parents, np.int32)),  # type: ignore[arg-type]
            edges=_Edges(arrays, keys_col, self.sched, self.configs.actions),  # type: ignore[arg-type]
            final=_Column(arrays.final), stay=_Column(arrays.stay),  # type: ignore[arg-type]
            states=len(all_reps), transitions=self.transitions, stopped=self.stopped,
            halt=self.halt, reduced=self.anonymity or len(self.symmetries) > 1,
            seconds=time.perf_counter() - started,
            canonical=canonicaliser(self.symmetries, self.meeting, self.anonymity, self.visits,
                                    self.relabel),
            engine="bulk",
            arrays=arrays, seed_ids=self.seed_ids.reshape(len(self.seeds), len(self.starts)))
