"""The one chunk loop of the bulk searches: the paper's world's
(:func:`~gather_verify.engine.bulk_loop.bulk_search`) and the finite worlds'
(:func:`~gather_verify.engine.world_bulk.search`).

A bulk search is a run of :class:`Chunks`: it keeps its stored states and columns, and
expands the next chunk of them in one :meth:`~Chunks.step` (its own kernels: Z²'s region,
properties and lit robots; a finite world's neighbour table and round weighing).
:func:`drive` steps it under the limits of time and memory, written once for both.
"""

from __future__ import annotations

import time
from typing import Protocol

from gather_verify.engine.encoding import Limits, Stop


class Chunks(Protocol):
    """A bulk search as :func:`drive` steps it."""

    stopped: Stop | str | None
    """Why the search stopped (None while it runs)."""

    def pending(self) -> bool:
        """Whether stored states are left to expand."""

    def rss(self) -> float:
        """The memory in use now (MB), read before each chunk for the limit."""

    def step(self, limits: Limits) -> None:
        """Expand the next chunk; ``stopped`` set when the search stops in it."""

    def chunk_done(self) -> None:
        """After a chunk in which the search did not stop (progress, a settled check)."""


def drive(run: Chunks, limits: Limits, started: float) -> None:
    """Step ``run`` a chunk at a time until no state is left or it stops: at the time or
    memory limit before a chunk, or inside one (a limit, a halt, a settled search)."""
    while run.pending():
        if time.perf_counter() - started > limits.max_seconds:
            run.stopped = Stop.TIME
            return
        if run.rss() > limits.max_memory_mb:
            run.stopped = Stop.MEMORY
            return
        run.step(limits)
        if run.stopped is not None:
            return
        run.chunk_done()
        if run.stopped is not None:
            return
