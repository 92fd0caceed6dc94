"""Progress of a long check: what it has done so far, and a line on stderr every few seconds.

:data:`PROGRESS` is one small process-wide object. The engines set ``states`` where they
already read the clock (the reference engine at every state, the bulk engine at every chunk,
the finite-world search every 64 states: an attribute store, nothing more), and ``run_check``
and the finite-world check name what is being done (``doing``): exploring, lifting the graph
to check its cycles, searching the longest walk... A :class:`Reporter` (``check --progress
SECONDS``) is a daemon thread that reads them and prints one line every ``SECONDS``; nothing
in the search waits for it.

>>> PROGRESS.begin("exploring"); PROGRESS.states = 1234567
>>> progress_line(PROGRESS, 12.4)
'… 1,234,567 states, 12 s, exploring'
"""

from __future__ import annotations

import sys
import threading
import time
from typing import Any, TextIO


class Progress:
    """What a long check has done so far (written by the search, read by a reporter thread:
    plain attribute stores and loads, atomic under the interpreter's lock)."""

    __slots__ = ("doing", "lines", "reporting", "states")

    def __init__(self) -> None:
        self.states = 0
        """States the current search has stored (it starts again at 0 for the next one)."""
        self.doing = "starting"
        """What is being done, in a few words."""
        self.reporting = False
        """Whether a :class:`Reporter` is running."""
        self.lines = 0
        """Progress lines the running (or last) :class:`Reporter` has printed."""

    def begin(self, doing: str) -> None:
        """A new search: ``doing``, its states counted from 0."""
        self.doing, self.states = doing, 0


PROGRESS = Progress()
"""The process-wide progress of the check being run."""


def progress_line(progress: Progress, seconds: float) -> str:
    """One progress line: ``… 1,234,567 states, 12 s, exploring``."""
    return f"… {progress.states:,} states, {seconds:.0f} s, {progress.doing}"


def default_every(stream: Any = None) -> float:
    """``check --progress``'s default: every 2 s when ``stream`` (stderr) is a terminal,
    never otherwise (a log or a pipe gets no progress lines unless asked)."""
    stream = sys.stderr if stream is None else stream
    try:
        return 2.0 if stream.isatty() else 0.0
    except (AttributeError, ValueError):  # a closed or unusual stream: no progress
        return 0.0


class Reporter:
    """A daemon thread that prints :func:`progress_line` to ``stream`` every ``every`` seconds
    while the ``with`` block runs (``every`` 0: nothing at all). On a terminal the line is
    rewritten in place and erased at the end; elsewhere each is a line of its own."""

    def __init__(self, every: float, stream: TextIO | None = None,
                 progress: Progress = PROGRESS) -> None:
        self.every = every
        self.stream = sys.stderr if stream is None else stream
        self.progress = progress
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        try:
            self._tty = bool(self.stream.isatty())
        except (AttributeError, ValueError):
            self._tty = False
        self._shown = False

    def __enter__(self) -> Reporter:
        if self.every > 0:
            self._started = time.monotonic()
            self.progress.begin("starting")
            self.progress.lines = 0
            self.progress.reporting = True
            self._thread = threading.Thread(target=self._run, name="gather-verify progress",
                                            daemon=True)
            self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        if self._thread is None:
            return
        self._stop.set()
        self._thread.join()
        self.progress.reporting = False
        if self._tty and self._shown:
            self._write("\r\033[K")

    def _run(self) -> None:
        while not self._stop.wait(self.every):
            text = progress_line(self.progress, time.monotonic() - self._started)
            self._write(f"\r{text}\033[K" if self._tty else text + "\n")
            self._shown = True
            self.progress.lines += 1

    def _write(self, text: str) -> None:
        try:
            self.stream.write(text)
            self.stream.flush()
        except (OSError, ValueError):  # stderr closed: the check goes on without progress
            self._stop.set()
