"""How long a sweep takes on W workers, from the seconds its tasks took.

A sweep's unit of work is a task (:func:`gather_verify.sweeps.mclass.class_tasks`:
one shape of ``M``, its meeting-node classes in turn), handed out the most
configurations first to whichever worker is free: a process pool and a Dask
cluster both do that. So from the stored seconds of each row, summed per task,
the wall time on W workers is the makespan of that list schedule; no run on a
cluster is needed to see where adding workers stops paying (the largest task,
and the work each one costs beside the others). A class that hands checks off
(``sweeps.sweep.HAND_OFF_SECONDS``) counts as one task here: an upper bound. The seconds are those of the machine that ran the
sweep, under its load.

>>> predict([5.0, 3.0, 2.0, 2.0], [1, 2, 4])
{1: 12.0, 2: 7.0, 4: 5.0}
>>> task_seconds([{"sweep": 1, "index": k, "meeting_nodes": [], "seconds": 1.0}
...               for k in range(10)])  # a finite world's: tasks of 8 configurations
[8.0, 2.0]
"""

from __future__ import annotations

import heapq
from collections.abc import Iterable, Sequence
from typing import Any

from gather_verify.model.canonical import canonical_form

WORLD_CHUNK = 8
"""Configurations per task of a finite world's sweep (``sweeps.sweep.CHUNK``)."""


def task_seconds(rows: Iterable[dict[str, Any]]) -> list[float]:
    """The seconds of each task of a sweep's stored rows (one task per shape of ``M`` and
    per sweep), in the order a sweep hands them out: the most configurations first (ties:
    the sweep, then the first configuration's index), as :func:`gather_verify.sweeps.sweep`
    sorts them. That order knows the size of a task, not its cost."""
    tasks: dict[tuple[Any, Any], list[float]] = {}  # seconds, -members, first index
    shapes: dict[tuple, Any] = {}  # a sweep's rows share few meeting-node sets
    for row in rows:
        nodes = row["meeting_nodes"] or ()
        if not nodes or not isinstance(nodes[0], list | tuple):
            # a finite world's row (its nodes are numbers): its checks go out in chunks of
            # ``sweeps.sweep.CHUNK`` configurations in enumeration order
            key = (row.get("sweep"), ("chunk", row.get("index", 0) // WORLD_CHUNK))
        else:
            meeting = tuple(tuple(m) for m in nodes)
            if meeting not in shapes:
                shapes[meeting] = canonical_form((), meeting).key
            key = (row.get("sweep"), shapes[meeting])
        task = tasks.setdefault(key, [0.0, 0, float("inf")])
        task[0] += float(row.get("seconds") or 0.0)
        task[1] -= 1
        task[2] = min(task[2], row.get("index", 0))
    order = sorted(tasks, key=lambda k: (tasks[k][1], k[0] or 0, tasks[k][2]))
    return [tasks[k][0] for k in order]


def makespan(seconds: Sequence[float], workers: int) -> float:
    """Wall time of the tasks handed out in the given order, each to the first free worker."""
    free = [0.0] * max(1, workers)
    for s in seconds:
        heapq.heapreplace(free, free[0] + s)
    return max(free)


def predict(seconds: Sequence[float], workers: Iterable[int]) -> dict[int, float]:
    """The makespan for each number of workers (``seconds``: task costs, in hand-out order)."""
    return {w: round(makespan(seconds, w), 3) for w in workers}


def format_prediction(seconds: Sequence[float], curve: dict[int, float],
                      write: Any = print) -> None:
    """The curve as a table, with what bounds it."""
    total = sum(seconds)
    write(f"{len(seconds)} tasks, {total:.1f} s of work in all, the largest {max(seconds):.1f} s"
          if seconds else "no stored rows")
    write(f"{'workers':>8}{'wall s':>10}{'speed-up':>10}{'efficiency':>12}")
    for w, t in curve.items():
        speed = total / t if t else 0.0
        write(f"{w:>8}{t:>10.1f}{speed:>10.2f}{speed / w:>12.0%}")
