"""One step of a bulk search on the paper's world: a chunk of stored states expanded at once.

The per-configuration bulk search (:mod:`~gather_verify.engine.fast_explore`) and
the union of a meeting-node class (:mod:`~gather_verify.engine.union`) expand their
states the same way, and this module is that way, written once:

- :func:`decode_chunk`: the chunk's keys back to robot codes, each state's
  configuration row in the :class:`~gather_verify.engine.facts_table.FactsTable` (its
  facts computed when new), whether its robots are idle, and where each robot's cell
  sits in its configuration's sorted cells;
- :func:`move_masks`: each robot's move mask, read from its configuration's row, for
  the scheduler's ``bulk_successors`` (handed the states by ``Encoding.frontier``);
- :func:`successor_keys`: the stored keys of the successors the scheduler made
  (:class:`~gather_verify.engine.canonical_keys.Canon` under the reductions).

:class:`PairRows` gives the configuration row each one-robot change reaches, once per
(configuration, robot, step) rather than once per transition. Each step has a compiled
path (:mod:`gather_verify.kernels`) and a numpy one, with the same results.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gather_verify import kernels
from gather_verify.engine.canonical_keys import Canon, decode_keys
from gather_verify.engine.columns import Growing, small_pages
from gather_verify.engine.facts_table import FactsTable
from gather_verify.engine.key_index import KeyIndex
from gather_verify.model.geometry import DEGREE, SLOTS


@dataclass
class Chunk:
    """Stored states decoded, with their configurations' rows in a :class:`FactsTable`."""

    keys: np.ndarray  # (k,) uint64: the states' keys
    codes: np.ndarray  # (k, n): robot codes ``cell * SLOTS + d``
    cells: np.ndarray  # (k, n): ``codes // SLOTS``
    sorted_cells: np.ndarray  # (k, n): each row's cells sorted (its configuration)
    rows: np.ndarray  # (k,): the configuration's row in the table
    idle: np.ndarray  # (k,) bool: every robot idle
    rank: np.ndarray  # (k, n): robot j's cell is ``sorted_cells[rank[j]]`` (the first equal)


def decode_chunk(keys: np.ndarray, table: FactsTable, compiled: bool) -> Chunk:
    """The states of ``keys`` (encoded as ``table.enc``), their configurations looked up
    in ``table`` (rows numbered in order of first occurrence, facts of new ones computed)."""
    n, base = table.n, table.enc.base
    if compiled:
        codes, cells, srt, ck, idle, rank = kernels.decode_chunk(keys, base, n, table.weights)
    else:
        codes = decode_keys(keys, base, n)
        cells = codes // SLOTS
        srt, ck = table.config_keys(cells)
        idle = np.all(codes % SLOTS == 0, axis=1)
        rank = None
    rows = table.rows(ck, srt)
    if rank is None:
        rank = cell_ranks(cells, srt)
    return Chunk(keys, codes, cells, srt, rows, idle, rank)


def cell_ranks(cells: np.ndarray, sorted_cells: np.ndarray) -> np.ndarray:
    """Per robot, the position of its cell among its row's sorted cells (the first equal)."""
    return np.argmax(cells[:, :, None] == sorted_cells[:, None, :], axis=2)


def move_masks(table: FactsTable, rows: np.ndarray, rank: np.ndarray,
               flat: bool = False) -> np.ndarray:
    """Robot ``j``'s move mask in each state: the mask of the ``rank[j]``-th sorted cell of
    its configuration's row. ``flat``: one flat gather (much faster than the two-dimensional
    one in the compiled engine's use; the same values)."""
    if flat:
        return np.take(table.masks.reshape(-1), rows[:, None] * table.n + rank)
    return table.masks[rows[:, None], rank]


def successor_codes(codes: np.ndarray, src: np.ndarray, robot: np.ndarray, new: np.ndarray,
                    event: np.ndarray | None = None) -> np.ndarray:
    """The robot codes of each successor: its source's (``codes[src]``), robot ``robot[c]``
    of event ``event[c]`` given code ``new[c]`` (``event`` None: change ``c`` is event ``c``)."""
    out = codes[src]
    out[np.arange(len(src)) if event is None else event, robot] = new
    return out


def successor_keys(keys: np.ndarray, codes: np.ndarray, src: np.ndarray, robot: np.ndarray,
                   new: np.ndarray, event: np.ndarray | None, canon: Canon, reduced: bool,
                   compiled: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The stored key of each successor (event ``e`` from state ``src[e]`` of the chunk;
    ``event`` as in :func:`successor_codes`), the old code of each changed robot, and the
    successors' codes when they were computed (numpy path: under a reduction, or several
    changes per event; the compiled path computes none)."""
    single = event is None
    if compiled:
        if reduced and single:  # each successor's key from its source's images
            succ, old = kernels.successor_canonical_keys(codes, src, robot, new, canon.powers,
                                                         canon.table_rows, canon.anonymity,
                                                         canon.ordered)
        elif reduced:
            succ, old = kernels.event_canonical_keys(codes, src, robot, new, event, canon.powers,
                                                     canon.table_rows, canon.anonymity)
        elif single:
            succ, old = kernels.successor_keys(keys, codes, src, robot, new, canon.powers)
        else:
            succ, old = kernels.event_keys(keys, codes, src, robot, new, event, canon.powers)
        return succ, old, None
    old = (codes[src, robot] if single else codes[src[event], robot]).astype(new.dtype,
                                                                              copy=False)
    if reduced or not single:
        succ_codes = successor_codes(codes, src, robot, new, event)
        return canon.keys(succ_codes), old, succ_codes
    delta = (new - old).astype(np.uint64) * canon.powers[robot]
    return keys[src] + delta, old, None  # wraps correctly for negative deltas


class PairRows:
    """The configuration row a one-robot change reaches, kept per (configuration row, sorted
    position of the robot's cell, step): a configuration and its few moves are met by many
    states (the robots' pending steps differ), so the successor's configuration is sorted
    and looked up once per such triple, not once per transition. A direct table (16 bytes
    per row and robot) while the rows are few; beyond, a hash index of the triples."""

    DIRECT_ROWS = 1 << 20
    """Rows the direct table may cover (80 MB with five robots); beyond: the hash index."""
    FIRST_ROWS = 1 << 10
    """Rows the direct table starts with room for."""
    SMALL_ROWS = 1 << 14
    """Rows up to which the direct table doubles (in the heap: a search of a few
    configurations maps no fresh pages); past them it is reserved whole (untouched pages
    cost no memory, so it is copied once)."""

    def __init__(self, table: FactsTable):
        self.table = table
        # one more than the row reached, 0 while unknown
        self.succ = np.zeros((self.FIRST_ROWS, table.n, DEGREE), dtype=np.int32)
        self.neighbour = table.enc.neighbour
        self.index = KeyIndex(bits=12, capacity=1 << 12)
        self.rows = Growing(np.int64, 1 << 12)
        self.stride = table.n * table.enc.cells

    def after(self, rows: np.ndarray, cells: np.ndarray, rank: np.ndarray, src: np.ndarray,
              robot: np.ndarray, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        """The row of each transition's successor configuration (``src``: source states of
        the chunk; robot ``robot`` goes from code ``old`` to code ``new``)."""
        if self.table.size > self.DIRECT_ROWS:
            return self._hashed(rows, cells, rank, src, robot, old, new)
        if self.table.size > len(self.succ):
            size = 2 * len(self.succ)
            while size < self.table.size:
                size *= 2
            grown = np.zeros((size if size <= self.SMALL_ROWS else self.DIRECT_ROWS,)
                             + self.succ.shape[1:], dtype=np.int32)
            if len(grown) == self.DIRECT_ROWS:
                small_pages(grown)  # written by row: only the rows met are resident
            grown[:len(self.succ)] = self.succ
            self.succ = grown
        out, miss, slot = kernels.successor_rows(rows, rank, src, robot, old, new,
                                                 self.neighbour, self.succ)
        if len(miss):
            succ = cells[src[miss]].copy()
            succ[np.arange(len(miss)), robot[miss]] = new[miss] // SLOTS
            srt, k = self.table.config_keys(succ)
            got = self.table.rows(k, srt)
            out[miss] = got
            known = slot >= 0
            self.succ.reshape(-1)[slot[known]] = got[known] + 1
        return out

    def _hashed(self, rows: np.ndarray, cells: np.ndarray, rank: np.ndarray, src: np.ndarray,
                robot: np.ndarray, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        out = rows[src]
        moved, key = kernels.pair_keys(rows, rank, src, robot, old, new, self.stride,
                                       self.table.enc.cells)
        if not len(moved):
            return out
        ids, first = self.index.find_or_add(key)
        if len(first):
            f = moved[first]
            succ = cells[src[f]].copy()
            succ[np.arange(len(f)), robot[f]] = new[f] // SLOTS
            srt, k = self.table.config_keys(succ)
            self.rows.extend(self.table.rows(k, srt))
        out[moved] = self.rows.array()[ids]
        return out

