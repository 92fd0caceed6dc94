"""The facts of configurations as small integers, for whole chunks of states at once.

A bulk search meets each configuration (the robots' nodes, whatever their pending
moves) in many states. :class:`FactsTable` gives each configuration met a row
(numbered by a :class:`~gather_verify.engine.key_index.KeyIndex` over packed sorted
cells) and computes its facts once, through the generic algorithm interface: the move
mask of each robot (:data:`BIT`), whether the algorithm has a rule or crashed, whether
the robots are stuck or gathered, and on demand its class (in U) and target.
:class:`RowFacts` reads a row as the properties' ``Facts``. Move sets are computed
once per orbit under the usable part of ``Aut(M)``; with a memo
(:func:`facts_memo`), once per configuration up to translation and the frames for the
whole sweep of a process (:func:`make_room` empties the memos when memory runs short).
"""

from __future__ import annotations

import gc
from collections.abc import Sequence
from typing import Any

import numpy as np

from gather_verify.algorithms import Algorithm, AlgorithmCrash, Unhandled, target_of
from gather_verify.algorithms.moves import move_set, move_sets
from gather_verify.engine.encoding import Encoding
from gather_verify.engine.explore import rss_mb
from gather_verify.engine.key_index import KeyIndex
from gather_verify.model import geometry
from gather_verify.model.canonical import CanonicalForm, canonical_form, moved_form
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import DEGREE, SLOTS, STEPS, Node
from gather_verify.model.symmetry import Automorphism
from gather_verify.recent import most_recent
from gather_verify.theory import get_fact

FactsMemo = dict
"""Facts of configurations up to translation and the frames, shared by the checks of a
sweep (one per algorithm, detection and frames: :func:`facts_memo`)."""
MEMO_SIZE = 1 << 20
"""Configurations a memo holds before it starts over (a few hundred bytes each). The runs of
a sweep that walk away from ``M`` meet some 300,000 configurations each, mostly the same
ones: a memo that holds them all serves the next such run of the class."""
MEMO_ALGORITHMS = 2
"""Algorithms whose memos a process keeps at once (the most recently used). A sweep under
every reading runs 16 or 64 algorithms in one pool: memos for all of them would fill the
worker's memory limit, and every check after that would stop INCOMPLETE (memory)."""
_MEMOS: dict[tuple[Algorithm, str, str], FactsMemo] = {}
_TARGETS: dict[Algorithm, dict[tuple, Node | None]] = {}


def make_room(limit_mb: float) -> None:
    """Drop every memo when this process holds more than half its memory limit: the memos
    are a cache (a few hundred bytes to kilobytes per configuration), and a check must not
    stop INCOMPLETE (memory) because of what earlier checks left in them."""
    if (_MEMOS or _TARGETS) and rss_mb() > limit_mb / 2:
        _MEMOS.clear()
        _TARGETS.clear()
        gc.collect()


def facts_memo(algorithm: Algorithm, detection: str, frames: str) -> FactsMemo:
    """The memo this process shares among the checks of one algorithm object."""
    return most_recent(_MEMOS, (algorithm, detection, frames), dict, MEMO_ALGORITHMS)


def target_memo(algorithm: Algorithm) -> dict[tuple, Node | None]:
    """Targets of configurations (robots and meeting nodes as they are: no symmetry assumed
    of ``target``), shared like :func:`facts_memo` by the checks of a sweep."""
    return most_recent(_TARGETS, algorithm, dict, MEMO_ALGORITHMS)


def _step_perm(g: int) -> tuple[int, ...]:
    """Move masks (bit k: ``STEPS[k]``, bit ``DEGREE``: stay) mapped by the D4 element ``g``."""
    image = [STEPS.index(geometry.apply(g, step)) for step in STEPS]
    return tuple((m & STAY) | sum(1 << image[k] for k in range(DEGREE) if m >> k & 1)
                 for m in range(1 << SLOTS))


STAY = 1 << DEGREE
"""The move mask's bit for staying (after one bit per step of ``STEPS``)."""
UNASKED = object()
"""What :meth:`FactsTable._orbit_facts` gives for a representative whose target it did not ask."""
CRASHED = -3
"""The target id of a configuration where the algorithm's ``target`` crashed."""
STEP_PERM = tuple(_step_perm(g) for g in geometry.ALL)
BIT = {(0, 0): STAY} | {step: 1 << k for k, step in enumerate(STEPS)}
"""The mask bit of each destination, relative to the robot."""


class FactsTable:
    """Per configuration (sorted robot cells, packed), the facts as small integers.

    ``masks[row, j]``: bit ``k`` set when the robots on the ``j``-th sorted cell may
    take ``STEPS[k]``; bit ``DEGREE`` when they may stay. ``in_u`` and ``target`` are
    computed only when asked for (-2 = not computed yet).

    Move sets are computed once per orbit of configurations under ``group`` (the
    elements ``a`` of ``Aut(M)`` whose linear part is one of the robots' frames):
    for such an ``a`` the views of the robots of ``a(C)`` are those of ``C``, so
    the move set of ``a(v)`` in ``a(C)`` is ``a`` of the move set of ``v`` in ``C``
    (SEMANTICS.md §3: the union over the frames), whatever the algorithm. Class
    and target are computed on the configuration itself."""

    fast_facts = True
    """Whether the facts that need no row are shared (the algorithm's ``target_by_meeting``
    hook: one target asked for every row; ``in_U`` when no configuration over ``M`` is in U)
    and a target asked for an orbit's representative is kept for the row it is: False is
    the reference path, every target asked of the algorithm row by row and every row's class
    and target read as its own (what the tests compare the shared facts with)."""

    def __init__(self, enc: Encoding, n: int, algorithm: Algorithm, meeting: frozenset,
                 detection: str, frames: Sequence[int], group: Sequence[Any],
                 memo: FactsMemo | None = None, targets: bool = False):
        self.enc, self.n, self.algorithm, self.meeting = enc, n, algorithm, meeting
        self.memo = memo
        # targets by configuration: the sweep's shared memo (one search keeps none: each row
        # keeps its own in ``target``, and a dict entry per configuration cost 6 bytes a state)
        self.targets: dict[tuple, Node | None] = {} if memo is None else target_memo(algorithm)
        self.keep_targets = targets  # also those met while checking for crashes
        self.detection, self.frames = detection, tuple(frames)
        self.meeting_form = canonical_form((), meeting, self.frames)
        self.aut_m = list(group)  # Aut(M), identity first
        self.in_u_fact = get_fact("in_U")  # the paper's (gather_verify.theory)
        never = self.in_u_fact.never
        self.never_in_u = never is not None and never(self.aut_m, meeting)
        assert not self.aut_m or self.aut_m[0].g == geometry.IDENTITY and self.aut_m[0].t == (0, 0)
        self.index = KeyIndex(bits=10, capacity=1024)  # configuration key -> row
        self.nodes = list(map(tuple, enc.xy.tolist()))  # the node of each cell
        self.compiled = self.index.compiled  # the bulk paths of the compiled engine
        self.cells = np.zeros((1024, n), dtype=np.int32)
        self.masks = np.zeros((1024, n), dtype=np.uint8)
        self.flags = np.zeros((1024, 3), dtype=np.int8)  # undefined (1, 2: crash), stuck, gathered
        self.in_u = np.full(1024, -2, dtype=np.int8)
        self.target = np.full(1024, -2, dtype=np.int32)
        self.size = 0
        self.target_nodes: list = []
        self.target_ids: dict = {}
        self.weights = np.array([enc.cells ** j for j in range(n)], dtype=np.int64)
        # the orbit cache: images of region cells in the group-closed box
        group = sorted(a for a in group if a.g in self.frames)
        corners = [(enc.x0, enc.y0), (enc.x0 + enc.width - 1, enc.y0 + enc.height - 1)]
        x0, y0, x1, y1 = geometry.bounding_box([a(v) for a in group for v in corners] + corners)
        w, h = x1 - x0 + 1, y1 - y0 + 1
        if not group or (w * h) ** n >= 2**63:
            group = [Automorphism(geometry.IDENTITY, (0, 0))]
            x0, y0, w, h = enc.x0, enc.y0, enc.width, enc.height
        self.group = group
        self.identity = next((k for k, a in enumerate(group)
                              if a.g == geometry.IDENTITY and a.t == (0, 0)), -1)
        self._asked: object = UNASKED  # the target _facts asked, if it did
        self.box = (x0, y0, h)
        x, y = enc.xy[:, 0], enc.xy[:, 1]
        self.images = np.array([(m[0] * x + m[1] * y + a.t[0] - x0) * h + m[2] * x + m[3] * y
                                + a.t[1] - y0
                                for a in group for m in [geometry.MATRICES[a.g]]],
                               dtype=np.int64).reshape(len(group), enc.cells)
        self.cpowers = np.array([(w * h) ** j for j in range(n)], dtype=np.int64)
        # an algorithm whose answers depend on the robot's node only (its ``answers_by_node``
        # hook, go-to-target's): each node's move mask once, per cell of the box above
        hook = getattr(algorithm, "answers_by_node", None)
        self.by_node = hook is not None and bool(hook())
        # an algorithm whose target reads nothing of a configuration but its meeting nodes
        # (its ``target_by_meeting`` hook, go-to-target's): one target for every row, asked
        # once (:meth:`_meeting_target`), and read by a property as a fact its row does not fix
        hook = getattr(algorithm, "target_by_meeting", None)
        self.by_meeting = self.fast_facts and hook is not None and bool(hook())
        self.meeting_target: int | None = None
        self.node_mask = np.zeros(w * h, dtype=np.uint8)
        self.node_flag = np.full(w * h, -1, dtype=np.int8)  # -1: not asked yet; 1, 2: as flags
        self.box_meeting = np.array([(x0 + c // h, y0 + c % h) in meeting for c in range(w * h)],
                                    dtype=bool)
        # masks of a representative, seen from the configuration that ``a`` maps onto it
        self.perm = np.array([STEP_PERM[geometry.inverse(a.g)] for a in group], dtype=np.uint8)
        self.orbits = KeyIndex(bits=10, capacity=1024)  # orbit keys, numbered as first met
        self.mask_of: dict[tuple[Node, frozenset[Node]], int] = {}  # (node, move set) -> mask
        self.omasks = np.zeros((1024, n), dtype=np.uint8)
        self.oflags = np.zeros((1024, 3), dtype=np.int8)
        # per orbit, the canonical form of its representative when one was computed (what
        # the algorithm's own work left, or the memo's); per row, its orbit and the element
        # of ``group`` that maps it onto the representative: a row's form then comes from
        # the representative's with no search (canonical.moved_form), which is most of
        # what its target costs
        self.oforms: list[CanonicalForm | None] = []
        self.row_orbit = np.zeros(1024, dtype=np.int32)
        self.row_image = np.zeros(1024, dtype=np.int8)

    def config_keys(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sorted cells per row and their packed key."""
        srt = np.sort(cells, axis=1)
        return srt, srt @ self.weights

    def configuration(self, row: int, form: bool = False) -> Configuration:
        """The configuration of ``row``; with ``form``, carrying its canonical form when its
        orbit's is known (moved from the representative's, no search)."""
        node = self.nodes
        c = Configuration.trusted(tuple([node[c] for c in self.cells[row].tolist()]),
                                  self.meeting)
        known = self.oforms[self.row_orbit[row]] if form else None
        if known is not None:  # the representative is a(C): C is a^-1 of it
            back = self.group[self.row_image[row]].inverse()
            c.__dict__["canonical_form"] = moved_form(known, back.g, back.t)
        return c

    def rows(self, keys: np.ndarray, sorted_cells: np.ndarray) -> np.ndarray:
        """Row of every configuration key (computing the facts of new ones): rows are
        numbered as the index numbers keys, in order of first occurrence."""
        ids, first = self.index.find_or_add(keys.astype(np.uint64))
        if len(first):
            self._add(sorted_cells[first])
        return ids

    def _add(self, cells: np.ndarray) -> np.ndarray:
        m, n = cells.shape
        while self.size + m > len(self.masks):
            self.cells, self.masks, self.flags = (
                np.concatenate([a, np.zeros_like(a)]) for a in (self.cells, self.masks, self.flags))
            self.in_u = np.concatenate([self.in_u, np.full(len(self.in_u), -2, dtype=np.int8)])
            self.target = np.concatenate([self.target,
                                          np.full(len(self.target), -2, dtype=np.int32)])
            self.row_orbit, self.row_image = (np.concatenate([a, np.zeros_like(a)])
                                              for a in (self.row_orbit, self.row_image))
        rows = np.arange(self.size, self.size + m)
        self.size += m
        self.cells[rows] = cells
        # the orbit representative: least packed sorted image over the group
        image = self.images[:, cells]  # (G, m, n), unsorted
        srt = np.sort(image, axis=2)
        packed = srt @ self.cpowers
        best = np.argmin(packed, axis=0)
        pick = np.arange(m)
        okeys, ocells = packed[best, pick], srt[best, pick]
        # each orbit's number, and the first configuration of each orbit met here for the first
        # time (in order: the new orbits are numbered next, in that order)
        orows, new = self.orbits.find_or_add(okeys.astype(np.uint64))
        asked = self._orbit_facts(ocells[new]) if len(new) else []
        # a new orbit's representative that is the row itself: its target, asked above, is the
        # row's (each target asked once)
        for i, t in zip(new.tolist(), asked, strict=True):
            if t is not UNASKED and best[i] == self.identity and self.fast_facts:
                self.target[rows[i]] = self._target_id(t)
        # robot j of the configuration sits on the rank[j]-th cell of the representative
        rank = np.argmax(image[best, pick][:, :, None] == ocells[:, None, :], axis=2)
        self.masks[rows] = self.perm[best[:, None], self.omasks[orows[:, None], rank]]
        self.flags[rows] = self.oflags[orows]
        self.row_orbit[rows] = orows
        self.row_image[rows] = best
        if self.by_meeting:  # a crash is the orbits' (flags); the target is then none
            t = self.meeting_target
            if t is None:
                t = self._meeting_target(self.configuration(int(rows[0])))
            self.target[rows] = max(t, -1)
        return rows

    def _orbit_facts(self, cells: np.ndarray) -> list[object]:
        """The facts of new orbits (numbered next, in order), from their representatives'
        sorted cells in the group-closed box; and the target of each representative where
        it was asked (a crash: None), else :data:`UNASKED`."""
        first = len(self.oforms)
        while first + len(cells) > len(self.omasks):
            self.omasks = np.concatenate([self.omasks, np.zeros_like(self.omasks)])
            self.oflags = np.concatenate([self.oflags, np.zeros_like(self.oflags)])
        if self.by_node:
            return self._node_orbit_facts(cells, first)
        x0, y0, h = self.box
        facts = self._facts if self.memo is None else self._remembered_facts
        masks, flags, asked = [], [], []
        for xs, ys in zip((x0 + cells // h).tolist(), (y0 + cells % h).tolist(), strict=True):
            self._asked = UNASKED
            m, f, form = facts(tuple(zip(xs, ys, strict=True)))
            masks.append(m)
            flags.append(f)
            asked.append(self._asked)
            self.oforms.append(form)
        self.omasks[first:first + len(cells)] = masks
        self.oflags[first:first + len(cells)] = flags
        return asked

    def _node_orbit_facts(self, cells: np.ndarray, first: int) -> list[object]:
        """:meth:`_orbit_facts` for an algorithm that answers by node: the move set of each
        node asked once (:meth:`_node_facts`, in the first configuration met that holds it),
        the masks and flags in bulk, as :meth:`_facts` defines them (the first robot in order
        whose node has no rule or crashes decides the flag, as ``move_sets`` asks the nodes
        in order), and the algorithm's ``target`` asked per configuration (a crash there is
        the configuration's)."""
        x0, y0, h = self.box
        k = len(cells)
        fresh = np.unique(cells[self.node_flag[cells] < 0])
        if len(fresh):
            holder = np.argmax((cells[:, :, None] == fresh).any(axis=1), axis=0)
            for c, i in zip(fresh.tolist(), holder.tolist(), strict=True):
                robots = tuple((x0 + v // h, y0 + v % h) for v in cells[i].tolist())
                self._node_facts(c, Configuration.trusted(robots, self.meeting))
        flag = self.node_flag[cells]
        undefined = flag[np.arange(k), np.argmax(flag != 0, axis=1)].astype(np.int8)
        forms: list[CanonicalForm | None] = [None] * k
        targets: list[object] = [UNASKED] * k
        if self.by_meeting:  # one target for all (its crash too)
            robots = tuple((x0 + v // h, y0 + v % h) for v in cells[0].tolist())
            if self._meeting_target(Configuration.trusted(robots, self.meeting)) == CRASHED:
                undefined[:] = 2
        elif getattr(self.algorithm, "target", None) is not None or self.memo is not None:
            asked = np.flatnonzero(undefined != 2)
            xs, ys = (x0 + cells[asked] // h).tolist(), (y0 + cells[asked] % h).tolist()
            for i, x, y in zip(asked.tolist(), xs, ys, strict=True):
                robots = tuple(zip(x, y, strict=True))
                c = Configuration.trusted(robots, self.meeting)
                try:  # whether it crashes (and the value, for a sweep's memo of targets)
                    t = target_of(self.algorithm, c)
                except Unhandled:
                    t = None
                except AlgorithmCrash:
                    undefined[i] = 2
                    targets[i] = None
                    continue
                targets[i] = t
                if self.keep_targets:
                    self._remember_target((robots, self.meeting), t)
                forms[i] = c.__dict__.get("canonical_form")
        defined = undefined == 0
        masks = np.where(defined[:, None], self.node_mask[cells], 0)
        self.omasks[first:first + k] = masks
        self.oflags[first:first + k, 0] = undefined
        self.oflags[first:first + k, 1] = defined & (masks == STAY).all(axis=1)
        self.oflags[first:first + k, 2] = defined & (cells[:, 0] == cells[:, -1]) & \
            self.box_meeting[cells[:, 0]]
        self.oforms.extend(forms)
        return targets

    def _node_facts(self, cell: int, c: Configuration) -> None:
        """The move mask (or flag: 1 no rule, 2 crash) of the node of box cell ``cell``, asked
        of the algorithm's ``decide`` in ``c``, a configuration that holds that node."""
        x0, y0, h = self.box
        v = (x0 + cell // h, y0 + cell % h)
        try:
            s = move_set(self.algorithm, c, v, self.detection, self.frames)
        except Unhandled:
            self.node_flag[cell] = 1
            return
        except AlgorithmCrash:
            self.node_flag[cell] = 2
            return
        self.node_mask[cell] = sum(BIT[x - v[0], y - v[1]] for x, y in s)
        self.node_flag[cell] = 0

    def _facts(self, robots: tuple[Node, ...]
               ) -> tuple[list[int], tuple[int, int, int], CanonicalForm | None]:
        """Move masks of ``robots`` (in order) and the flags (no move sets: 0, or 1 when the
        algorithm has no rule, 2 when it crashed in ``decide`` or ``target``; stuck; gathered),
        as :func:`~gather_verify.properties.facts.configuration_facts` defines them; and the
        configuration's canonical form if the algorithm computed it (none is searched for)."""
        c = Configuration.trusted(robots, self.meeting)
        undefined = 0
        try:
            ms = move_sets(self.algorithm, c, self.detection, self.frames)
        except Unhandled:
            undefined = 1
        except AlgorithmCrash:
            undefined = 2
        if undefined != 2 and self.by_meeting:  # one target for all (its crash too)
            if self._meeting_target(c) == CRASHED:
                undefined = 2
        elif undefined != 2:
            try:  # whether it crashes; the value is kept for target_id_of (c's canonical form
                # is already computed here, which is most of what a target costs)
                t = target_of(self.algorithm, c)
            except Unhandled:
                t = None
            except AlgorithmCrash:
                undefined = 2
                t = None
            self._asked = t
            if undefined != 2 and self.keep_targets:
                self._remember_target((robots, self.meeting), t)
        form = c.__dict__.get("canonical_form")
        if undefined:
            return [0] * len(robots), (undefined, 0, 0), form
        mask_of, by_node = self.mask_of, {}
        for v, s in ms.items():  # each occupied node once; each (node, move set) computed once
            m = mask_of.get((v, s)) if type(s) is frozenset else None
            if m is None:
                m = sum(BIT[x - v[0], y - v[1]] for x, y in s)
                if type(s) is frozenset:
                    mask_of[v, s] = m
            by_node[v] = m
        return [by_node[v] for v in robots], (0, all(m == STAY for m in by_node.values()),
                                              robots[0] == robots[-1] and robots[0] in self.meeting
                                              ), form

    def _remembered_facts(self, robots: tuple[Node, ...]
                          ) -> tuple[list[int], tuple[int, int, int], CanonicalForm | None]:
        """:meth:`_facts` through the shared memo, keyed by a canonical form of the
        configuration over translations and the frames (multiplicities kept): ``M`` moved
        to its canonical place by one of the isometries that do so, the one that gives
        the least sorted robot nodes (``M`` is fixed during a search, so those isometries
        are found once). Exact for any algorithm: with ``g`` in the frame group, the views
        of ``g(C) + t`` are those of ``C`` in the frames composed with ``g``, which run over
        the same frames, so its move sets are the images of those of ``C`` (SEMANTICS.md
        §3: the union over the frames); the flags are invariant. The canonical form is kept
        as the placed configuration's, and moved back to each configuration that finds it."""
        best = None
        for g, (tx, ty) in self.meeting_form.minimisers:
            a, b, c, d = geometry.MATRICES[g]
            image = [(a * x + b * y + tx, c * x + d * y + ty) for x, y in robots]
            placed = sorted(image)
            if best is None or placed < best[0]:
                best = (placed, g, (tx, ty), image)
        placed, g, best_t, image = best
        key = (self.meeting_form.key, tuple(placed))
        known = self.memo.get(key)
        if known is None:
            masks, flags, form = self._facts(robots)
            forward = STEP_PERM[g]
            if len(self.memo) >= MEMO_SIZE:
                self.memo.clear()
            self.memo[key] = (dict(zip(image, (forward[m] for m in masks), strict=True)), flags,
                              None if form is None else moved_form(form, g, best_t))
            return masks, flags, form
        back = Automorphism(g, best_t).inverse()
        form = None if known[2] is None else moved_form(known[2], back.g, back.t)
        return [STEP_PERM[back.g][known[0][w]] for w in image], known[1], form

    def reason(self, row: int) -> str | None:
        """Why the algorithm has no rule in this configuration (computed on it; None: it has
        one, or it crashed in ``decide``)."""
        try:
            move_sets(self.algorithm, self.configuration(row), self.detection, self.frames)
        except Unhandled as error:
            return str(error) or "no rule for this view"
        except AlgorithmCrash:
            return None
        return None

    def crash_of(self, row: int) -> AlgorithmCrash:
        """The exception of the algorithm in this configuration (computed on it: ``decide``'s
        first, else ``target``'s, as :func:`~gather_verify.properties.facts.configuration_facts`)."""
        c = self.configuration(row)
        try:
            move_sets(self.algorithm, c, self.detection, self.frames)
        except Unhandled:
            pass
        except AlgorithmCrash as crash:
            return crash
        try:
            target_of(self.algorithm, c)
        except Unhandled:
            pass
        except AlgorithmCrash as crash:
            return crash
        raise AssertionError("the orbit crashes, so does every member")  # pragma: no cover

    def flag_codes(self, rows: np.ndarray) -> np.ndarray:
        """Per row, its ``flags`` as one small integer: rows of one code agree on whether the
        algorithm has a rule or crashed, whether they are stuck and gathered (every fact of
        :class:`RowFacts` that does not set its ``read_row``)."""
        f = self.flags[rows].astype(np.int64)
        return f[:, 0] * 4 + f[:, 1] * 2 + f[:, 2]

    def need_in_u(self, rows: np.ndarray) -> np.ndarray:
        for r in np.unique(rows[self.in_u[rows] < 0]).tolist():
            self.in_u_of(r)
        return self.in_u[rows] == 1

    def _settle_asymmetric(self) -> None:
        """The first test of :meth:`in_u_of` (the fact ``in_U`` is ``symmetric_only``), in
        bulk on every row not settled yet: rows whose occupied nodes no element of Aut(M)
        but the identity maps onto themselves are not in U (they get ``in_u`` 0); the others
        are left to :meth:`in_u_of`."""
        rows = np.flatnonzero(self.in_u[:self.size] == -2)
        cells = self.cells[rows].astype(np.int64)
        x = self.enc.x0 + cells // self.enc.height
        y = self.enc.y0 + cells % self.enc.height
        some = np.zeros(len(rows), dtype=bool)
        for a in self.aut_m[1:]:
            m = geometry.MATRICES[a.g]
            ax = m[0] * x + m[1] * y + a.t[0]
            ay = m[2] * x + m[3] * y + a.t[1]
            inside = ((ax[:, :, None] == x[:, None, :]) & (ay[:, :, None] == y[:, None, :]))
            some |= inside.any(axis=2).all(axis=1)
        self.in_u[rows] = np.where(some, -3, 0)  # -3: left to in_u_of's classification

    def in_u_of(self, row: int) -> bool:
        """Whether the configuration of ``row`` is in U (computed once)."""
        known = int(self.in_u[row])
        if known < 0 and self.never_in_u:
            self.in_u[row] = known = 0
        if known == -2 and self.compiled and self.in_u_fact.symmetric_only:
            self._settle_asymmetric()
            known = int(self.in_u[row])
        if known >= 0:
            return known == 1
        # The fact is symmetric_only (in U needs Aut(C) non-trivial), and Aut(C) is inside
        # Aut(M): when no element of Aut(M) but the identity maps the occupied nodes onto
        # themselves, C is not in U.
        aut = self.aut_m
        c = self.configuration(row)
        occupied = set(c.robots)
        if not self.in_u_fact.symmetric_only or any(
                all(a(v) in occupied for v in occupied) for a in aut[1:]):
            self.in_u[row] = self.in_u_fact.of(c, aut_m_all=aut)
        else:
            self.in_u[row] = 0
        return bool(self.in_u[row] == 1)

    def need_target(self, rows: np.ndarray) -> np.ndarray:
        """Target id per row (-1: none)."""
        for r in np.unique(rows[self.target[rows] == -2]).tolist():
            self.target_id_of(r)
        return self.target[rows]

    def _remember_target(self, key: tuple, t: Node | None) -> None:
        if self.memo is None:  # one search: each row keeps its target in ``target``
            return
        if len(self.targets) >= MEMO_SIZE:
            self.targets.clear()
        self.targets[key] = t

    def target_of(self, c: Configuration, remember: bool = True) -> Node | None:
        """The algorithm's target in ``c`` (robots sorted; None: none, or no rule),
        remembered unless ``remember`` is false (a configuration not met again); a crash is
        raised, and not remembered."""
        key = (c.robots, c.meeting_nodes)
        if key in self.targets:
            return self.targets[key]
        try:
            t = target_of(self.algorithm, c)
        except Unhandled:
            t = None
        if remember:
            self._remember_target(key, t)
        return t

    def target_id_of(self, row: int) -> int:
        """The id of the target of ``row`` in ``target_nodes`` (-1: none; computed once)."""
        known = int(self.target[row])
        if known != -2:
            return known
        try:
            t = self.target_of(self.configuration(row, form=True))
        except AlgorithmCrash:  # a crash stops the search at the orbit
            t = None
        self.target[row] = self._target_id(t)
        return int(self.target[row])

    def _target_id(self, t: Node | None) -> int:
        """The id of target ``t`` in ``target_nodes`` (numbered as first met; -1: none)."""
        if t is None:
            return -1
        if t not in self.target_ids:
            self.target_ids[t] = len(self.target_nodes)
            self.target_nodes.append(t)
        return self.target_ids[t]

    def _meeting_target(self, c: Configuration) -> int:
        """The target id of every row when the target reads nothing but the meeting nodes
        (``by_meeting``), asked of the algorithm once, in ``c`` (any configuration over
        them): -1 none, :data:`CRASHED` when it crashed there (so it does everywhere)."""
        if self.meeting_target is None:
            try:
                t = target_of(self.algorithm, c)
            except Unhandled:
                t = None
            except AlgorithmCrash:
                self.meeting_target = CRASHED
                return CRASHED
            self.meeting_target = self._target_id(t)
        return self.meeting_target


class ReadsIdle:
    """State facts that note whether a predicate read ``idle`` (``read_idle``; if not, its
    answer holds for both values); a class using it sets ``_idle`` (None: the facts of a
    configuration, not of a state) and ``read_idle``."""

    __slots__ = ()
    _idle: bool | None
    read_idle: bool

    @property
    def idle(self) -> bool:
        if self._idle is None:
            raise AttributeError("idle: the facts of a configuration, not of a state")
        self.read_idle = True
        return self._idle


class RowFacts(ReadsIdle):
    """The :class:`~gather_verify.properties.facts.Facts` of one row of a :class:`FactsTable`,
    read from the table (class and target computed on first use); with ``idle`` given, also
    a state's facts (:class:`~gather_verify.properties.facts.StateFacts`), and ``read_idle``
    tells whether a predicate read it (if not, its answer holds for both values)."""

    __slots__ = ("table", "row", "initial", "_flags", "_idle", "read_idle", "read_row")

    def __init__(self, table: FactsTable, row: int, initial: Configuration,
                 idle: bool | None = None, flags: Sequence[int] | None = None):
        self.table, self.row, self.initial = table, row, initial
        self._flags = flags  # read from the table on first use
        self._idle = idle
        self.read_idle = False
        self.read_row = False
        """Whether a fact beyond the row's flags was read (:meth:`FactsTable.flag_codes`:
        the rows of one code agree on every other fact read)."""

    @property
    def flags(self) -> Sequence[int]:
        if self._flags is None:
            self._flags = self.table.flags[self.row].tolist()
        return self._flags

    @staticmethod
    def many(table: FactsTable, initial: Configuration, rows: np.ndarray,
             idle: np.ndarray) -> list[RowFacts]:
        """The state facts of many (row, idle) pairs, their flags read in one go."""
        return [RowFacts(table, r, initial, i, f) for r, i, f in
                zip(rows.tolist(), idle.tolist(), table.flags[rows].tolist(), strict=True)]

    @property
    def configuration(self) -> Configuration:
        self.read_row = True
        return self.table.configuration(self.row)

    @property
    def move_sets(self) -> dict[Node, frozenset[Node]] | None:
        if self.flags[0]:
            return None
        self.read_row = True
        out = {}
        for cell, mask in zip(self.table.cells[self.row].tolist(),
                              self.table.masks[self.row].tolist(), strict=True):
            v = self.table.enc.node(cell)
            out[v] = frozenset(geometry.add(v, d) for d, bit in BIT.items() if mask & bit)
        return out

    @property
    def unhandled(self) -> str | None:
        if not self.flags[0]:
            return None
        self.read_row = True
        got = self.table.reason(self.row)
        assert got is not None or self.flags[0] == 2, "the orbit is unhandled, so is every member"
        return got

    @property
    def crash(self) -> AlgorithmCrash | None:
        if self.flags[0] != 2:
            return None
        self.read_row = True
        return self.table.crash_of(self.row)

    @property
    def stuck(self) -> bool:
        return bool(self.flags[1])

    @property
    def gathered(self) -> bool:
        return bool(self.flags[2])

    @property
    def in_U(self) -> bool:
        if not (self.table.never_in_u and self.table.fast_facts):  # else false on every row
            self.read_row = True
        return self.table.in_u_of(self.row)

    @property
    def target(self) -> Node | None:
        if not self.table.by_meeting:  # else every row's
            self.read_row = True
        t = self.table.target_id_of(self.row)
        return None if t < 0 else self.table.target_nodes[t]
