"""Every step bounded by the limits, setup included (docs/reliability.md, "Honest limits").

A search reads its own clock, state count and memory as it goes. What comes before it is
the verifier's own code too: building a world (``torus:1000x1000`` is a million nodes),
the automorphisms of a graph file (the isomorphism matcher on a long path), a synthesis's
views and tables, a certificate's checks. :func:`setup` runs such a step under the same
limits: past ``max_seconds`` or ``max_memory_mb`` it stops, wherever it is, and says which
step and which limit (:class:`SetupStopped`); the command turns that into INCOMPLETE, or
``unknown``, with the reason, never into a verdict and never into a hang.
"""

from __future__ import annotations

from gather_verify.engine.encoding import Stop, rss_mb
from gather_verify.errors import GatherVerifyError
from gather_verify.watchdog import OverMemory, Overtime, bounded, quiet


class SetupStopped(GatherVerifyError):
    """A limit stopped a step before the search (``stop``: the limit, ``reason``: which
    step, in words, as a verdict's reason reads: ``time (building torus:1000x1000: past 5
    s)``).

    Cause: the world, its automorphisms or a synthesis's tables take longer or more memory
    than the limits given. Fix: a smaller instance, or larger limits; the command reports
    INCOMPLETE (``unknown`` for synthesis) with this reason."""

    def __init__(self, stop: Stop, reason: str):
        super().__init__(reason)
        self.stop, self.reason = stop, reason


class setup:  # noqa: N801 - a context manager used as a function is
    """Run the block (``doing``: what it does, in words) within ``max_seconds`` and
    ``max_memory_mb`` of resident memory; :class:`SetupStopped` past either."""

    def __init__(self, doing: str, max_seconds: float | None, max_memory_mb: float | None):
        self.doing, self.memory_mb = doing, max_memory_mb
        self.bounded = bounded(max_seconds, max_memory_mb, rss_mb)

    def __enter__(self) -> None:
        self.bounded.__enter__()

    @quiet
    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 tb: object) -> None:
        try:
            self.bounded.__exit__(kind, error, tb)
        except Overtime as over:  # the block ended past its deadline
            error = over
        if isinstance(error, Overtime):
            raise SetupStopped(Stop.TIME, f"time ({self.doing}: past {error.seconds:g} s)") \
                from None
        if isinstance(error, OverMemory):
            raise SetupStopped(Stop.MEMORY,
                               f"memory ({self.doing}: past {self.memory_mb:g} MB)") from None
