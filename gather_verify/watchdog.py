"""A watchdog over the user's code: an endless loop in ``decide`` (or ``target``, ``phase``,
``move_sets``, a property's functions, the import of an algorithm or property file, an
algorithm's constructor) ends with the time limit instead of hanging the verifier.

:func:`deadline` arms a real-time alarm (``SIGALRM``, through ``signal.setitimer``). When it
rings, the handler raises :class:`Overtime`, but only inside the user's code: the blocks
marked :func:`watched` (or the functions wrapped by :func:`guards`). Rung in the verifier's
own code, which reads its own clock, it only marks the deadline as passed, and the next
block of user code raises as it starts or ends: the verifier's state (a results database,
a cache being filled) is never cut at an arbitrary bytecode. Past the deadline the alarm
rings again every :data:`INTERVAL` seconds, so code that catches the exception and loops on
is stopped again, and an answer returned after the deadline is never used (the block raises
on its way out). ``Overtime`` derives from ``BaseException``: the user's ``except
Exception`` does not swallow it.

Where it does nothing: without ``SIGALRM`` (Windows) and off the main thread (Python runs
signal handlers there only: a Dask worker's task, for one); ``deadline(None)`` or an
infinite one. A single call into C code that never returns is not cut (the handler runs
between bytecodes). Deadlines nest: an inner one is armed only when it ends first, and an
alarm set before (an outer deadline, or another library's, pytest-timeout's) is put back,
with the time it had left, when the inner one ends.

>>> with deadline(0.05):
...     try:
...         with watched():
...             while True:
...                 pass
...     except Overtime as stopped:
...         print(f"stopped after {stopped.seconds:g} s")
stopped after 0.05 s
>>> with deadline(60), watched():  # code that returns in time is left alone
...     sum(range(10))
45
"""

from __future__ import annotations

import functools
import math
import os
import signal
import threading
import time
from collections.abc import Callable
from typing import Any, NoReturn, TypeVar

GRACE_SECONDS = 1.0
"""The least time a check's watchdog adds to its own time limit (``run_check`` arms
``max_seconds + max(max_seconds, GRACE_SECONDS)``): the engines' clock checks end a search
first, and the alarm only catches user code that does not return."""


def allowance(max_seconds: float) -> float:
    """The watchdog's deadline for a check limited to ``max_seconds``: as much again, at
    least :data:`GRACE_SECONDS` more. The engines read their own clock and stop at
    ``max_seconds``; the alarm is only for user code that does not return, and a tiny limit
    (``--max-seconds 1e-9``) gives an INCOMPLETE search, not an algorithm that "did not
    load in time"."""
    return max_seconds + max(max_seconds, GRACE_SECONDS)


INTERVAL = 0.05
"""Seconds between the alarm's rings once the deadline has passed."""

F = TypeVar("F", bound=Callable[..., Any])


class Overtime(BaseException):
    """The user's code was still running when a :func:`deadline` passed (``seconds``: that
    deadline).

    Cause: an algorithm's ``decide`` or ``target`` (or a user's property, scheduler or world)
    took longer than its deadline, most often an endless loop. Fix: make the code return in
    time, or raise the deadline.

    Deliberately *not* a :class:`~gather_verify.errors.GatherVerifyError`: a
    ``BaseException``, as ``KeyboardInterrupt``, so that ``except Exception`` in the
    user's code does not swallow it, and the verifier's crash handling lets it through."""

    def __init__(self, seconds: float):
        super().__init__(f"the code was still running after {seconds:g} s")
        self.seconds = seconds

    def __reduce__(self) -> tuple[Any, ...]:  # crosses process boundaries with its seconds
        return Overtime, (self.seconds,)


class _Deadline:
    __slots__ = ("expired", "seconds")

    def __init__(self, seconds: float):
        self.seconds, self.expired = seconds, False


_ARMED: list[_Deadline] = []
"""The deadlines whose alarm is set, the one ringing next last."""
_inside = 0
"""How deep the user's code is (0: the verifier's own code runs)."""


def available() -> bool:
    """Whether a deadline can be armed here: ``SIGALRM`` exists and this is the main thread."""
    return hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()


def _may_raise(frame: Any) -> bool:
    """Whether a ring may raise here: inside the user's code (or a bounded block), never in
    the watchdog's own bookkeeping (:data:`_COUNTING`) or a clean-up (:data:`_QUIET`), nor
    in anything they call (a thread's join, an event's set: an outer block's ring there
    would leave this one's alarm armed or its watch running)."""
    if not _inside:
        return False
    while frame is not None:
        if frame.f_code in _COUNTING or frame.f_code in _QUIET:
            return False
        frame = frame.f_back
    return True


def _ring(signum: int, frame: Any) -> None:
    if not _ARMED:
        return
    passed = _ARMED[-1]
    passed.expired = True
    if _may_raise(frame):
        raise Overtime(passed.seconds)


def _passed() -> _Deadline | None:
    """The armed deadline that has passed, if any."""
    return _ARMED[-1] if _ARMED and _ARMED[-1].expired else None


class deadline:  # noqa: N801 - a context manager used as a function is
    """Within the block, the user's code (:func:`watched`) raises :class:`Overtime` once
    ``seconds`` have passed. None, an infinite or a non-positive value: no deadline; nor
    where :func:`available` is false.

    A class, not a generator: its entry and exit are the watchdog's bookkeeping
    (:data:`_COUNTING`), where the alarm never raises, so a ring cannot leave an alarm armed
    or a handler not put back, even inside an outer watched block."""

    def __init__(self, seconds: float | None):
        self.seconds = seconds
        self.armed: _Deadline | None = None
        self.previous: Any = None
        self.left = self.interval = self.began = 0.0

    def __enter__(self) -> None:
        seconds = self.seconds
        if seconds is None or not 0 < seconds < math.inf or not available():
            return
        self.left, self.interval = signal.getitimer(signal.ITIMER_REAL)
        if self.left and self.left <= seconds:  # an alarm set before rings first: it stays
            return
        try:
            self.previous = signal.signal(signal.SIGALRM, _ring)
        except (ValueError, OSError):  # pragma: no cover - an embedding that refuses handlers
            return
        self.armed = _Deadline(seconds)
        _ARMED.append(self.armed)
        self.began = time.monotonic()
        signal.setitimer(signal.ITIMER_REAL, seconds, INTERVAL)

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 tb: object) -> None:
        if self.armed is None:
            return
        signal.setitimer(signal.ITIMER_REAL, 0)
        _ARMED.remove(self.armed)
        self.armed = None
        signal.signal(signal.SIGALRM, signal.SIG_DFL if self.previous is None else self.previous)
        if self.left:  # the alarm set before, with the time it has left
            signal.setitimer(signal.ITIMER_REAL,
                             max(self.left - (time.monotonic() - self.began), 1e-6),
                             self.interval)


class _Watched:
    """The context of :func:`watched` (one object, reentrant: it keeps no state of its own)."""

    __slots__ = ()

    def __enter__(self) -> None:
        global _inside
        passed = _passed()
        if passed is not None:  # no user code starts after the deadline
            raise Overtime(passed.seconds)
        _inside += 1

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 tb: object) -> None:
        global _inside
        _inside -= 1
        passed = _passed()
        if passed is not None and not isinstance(error, Overtime | KeyboardInterrupt):
            # whatever the code did after the deadline (an answer, an exception of its own,
            # or the Overtime it caught) is not used
            raise Overtime(passed.seconds) from None


_WATCHED = _Watched()
_COUNTING: set[Any] = {_Watched.__enter__.__code__, _Watched.__exit__.__code__,
                      deadline.__enter__.__code__, deadline.__exit__.__code__}
"""Where the alarm never raises: an exception between the count's change and the block's
start or end would leave the count wrong (the block checks the deadline itself), and one in
:func:`deadline`'s own code would leave an alarm armed or not put back (a block of the
verifier's code watched as a whole, as a synthesis search, nests deadlines in it)."""


def watched() -> _Watched:
    """Marks a block of the user's code: a :func:`deadline` that passes while it runs (or
    before it starts, or before it returns) raises :class:`Overtime` there."""
    return _WATCHED


def guards(function: F) -> F:
    """``function``, every call of it run as the user's code (:func:`watched`)."""

    @functools.wraps(function)
    def guarded(*args: Any, **kwargs: Any) -> Any:
        with _WATCHED:
            return function(*args, **kwargs)

    return guarded  # type: ignore[return-value]


# -- the verifier's own setup, bounded --------------------------------------------------
# Building what a search needs (a world of a million nodes, the automorphisms of a graph
# file, a synthesis's tables, a certificate's views) is the verifier's own code, but it
# keeps no state a stop could leave half written (a result is kept only when it is whole):
# it may be cut anywhere, as the user's code is.


class OverMemory(BaseException):
    """The resident memory passed the limit of a :func:`bounded` block (``limit_mb``).

    Cause: a setup step (building a world, its automorphisms, a synthesis's views) needs
    more memory than the limit (``--max-memory-mb``) allows. Fix: a smaller world, or a
    larger limit; the command reports INCOMPLETE (or ``unknown``) with this reason.

    Deliberately *not* a :class:`~gather_verify.errors.GatherVerifyError`: a
    ``BaseException``, as :class:`Overtime`, so that no ``except Exception`` on the way
    swallows it; raised in the user's code, it is a limit, never that code's crash (the
    handlers that make what ``decide`` or an import raises a crash or bad input let both
    through)."""

    limit_mb = 0.0


MEMORY_SIGNAL = getattr(signal, "SIGUSR1", None)
"""The signal by which a :class:`bounded` block's memory watch rings the main thread."""
_WATCHING: list[bounded] = []
"""The bounded blocks whose memory is watched, innermost last."""


def _ring_memory(signum: int, frame: Any) -> None:
    over = next((block for block in reversed(_WATCHING) if block.fired), None)
    if over is not None and _may_raise(frame):
        OverMemory.limit_mb = float(over.memory_mb)  # type: ignore[arg-type]
        raise OverMemory


class bounded:  # noqa: N801 - a context manager used as a function is
    """Within the block, :class:`Overtime` once ``seconds`` have passed and
    :class:`OverMemory` once ``rss()`` (MiB) passes ``memory_mb`` (read every
    :data:`INTERVAL` by a thread), raised wherever the block's code is: it is watched as
    the user's code is (:func:`watched`). On the main thread only, as :func:`deadline`.

    Both limits ring as signals (the alarm; :data:`MEMORY_SIGNAL` sent by the watching
    thread), handled where the alarm's rules apply (never in the watchdog's bookkeeping or a
    clean-up), and both ring again every :data:`INTERVAL` until the block ends: a stop that
    lands where Python ignores exceptions (a garbage collector's callback, a ``__del__``)
    or that code catches is raised again.

    A class, not a generator: on the way out it leaves the watched region first, in a frame
    where the alarm never raises (:func:`quiet`), so a second ring cannot cut its own
    clean-up."""

    def __init__(self, seconds: float | None, memory_mb: float | None,
                 rss: Callable[[], float]):
        self.seconds, self.memory_mb, self.rss = seconds, memory_mb, rss
        self.on = available()
        self.stop, self.fired = threading.Event(), False
        self.thread: threading.Thread | None = None
        self.timer: Any = None
        self.previous: Any = None

    def _watch(self, main: int) -> None:
        while not self.stop.wait(INTERVAL):
            if self.fired or self.rss() > self.memory_mb:  # type: ignore[operator]
                self.fired = True
                signal.pthread_kill(main, MEMORY_SIGNAL)  # type: ignore[arg-type]

    def __enter__(self) -> None:
        if not self.on:
            return
        global _inside
        try:
            if (self.memory_mb is not None and 0 < self.memory_mb < math.inf
                    and MEMORY_SIGNAL is not None):
                self.previous = signal.signal(MEMORY_SIGNAL, _ring_memory)
                _WATCHING.append(self)
                self.thread = threading.Thread(target=self._watch,
                                               args=(threading.get_ident(),),
                                               name="gather-verify memory watch", daemon=True)
                self.thread.start()
            self.timer = deadline(self.seconds)
            self.timer.__enter__()
        except BaseException:  # (a KeyboardInterrupt): nothing left armed or running
            self._release()
            raise
        _inside += 1

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 tb: object) -> None:
        if not self.on:
            return
        global _inside
        _inside -= 1  # first: no ring raises in this block's clean-up
        self._release()
        passed = _passed()
        if passed is not None and error is None:  # the block ended after its deadline
            raise Overtime(passed.seconds)

    def _release(self) -> None:
        if self in _WATCHING:
            _WATCHING.remove(self)  # a late memory ring is this block's: it raises nowhere
        if self.timer is not None:
            self.timer.__exit__(None, None, None)
        self.stop.set()
        if self.thread is not None:
            self.thread.join()
            signal.signal(MEMORY_SIGNAL,  # type: ignore[arg-type]
                          signal.SIG_DFL if self.previous is None else self.previous)


_QUIET: set[Any] = {bounded.__exit__.__code__, bounded._release.__code__}
_COUNTING.add(bounded.__enter__.__code__)
"""Code objects in which the alarm never raises (the clean-up of a bounded block)."""


def quiet(function: Callable[..., Any]) -> Callable[..., Any]:
    """Mark ``function`` as a place where the alarm never raises (the ``__exit__`` of a
    context manager around a :class:`bounded` block: it must run to its end)."""
    _QUIET.add(function.__code__)
    return function


# -- what ends the verifier: a real Ctrl-C only ------------------------------------------
# A KeyboardInterrupt, a SystemExit or a call of os._exit raised in the user's code is a bug
# of that code (the ``crash`` counterexample), never an interrupt of the verifier: only a
# SIGINT that reached this process is one. The command line counts them.

_interrupts = 0
"""SIGINTs this process received since :func:`count_interrupts`."""
_counting = False
"""Whether SIGINTs are counted here (or cannot reach this code at all)."""


def _interrupted(signum: int, frame: Any) -> None:
    global _interrupts
    _interrupts += 1
    raise KeyboardInterrupt


def count_interrupts() -> None:
    """Count the SIGINTs this process receives (the command line, on its main thread), each
    still raising KeyboardInterrupt as Python's own handler does: a KeyboardInterrupt raised
    while none was received is the user's code's (:func:`real_interrupt`). Also makes a
    call of ``os._exit`` in the user's code an exception (:func:`guard_exits`)."""
    global _counting
    guard_exits()
    if threading.current_thread() is not threading.main_thread():
        return  # (SIGINT reaches the main thread only: there it is counted, or never)
    try:
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, _interrupted)
        _counting = _counting or signal.getsignal(signal.SIGINT) is _interrupted
    except (ValueError, OSError):  # pragma: no cover - an embedding that refuses handlers
        return


def interrupts_unreachable() -> None:
    """This process (or thread) receives no Ctrl-C: a pool worker ignores SIGINT, a Dask
    task runs off the main thread. Any KeyboardInterrupt here is the user's code's."""
    global _counting
    _counting = True
    guard_exits()


def real_interrupt(error: BaseException) -> bool:
    """Whether ``error`` is a Ctrl-C the verifier must stop for: a KeyboardInterrupt where a
    SIGINT was received (or where they are not counted: a library caller's process)."""
    return isinstance(error, KeyboardInterrupt) and (_interrupts > 0 or not _counting)


class ExitCalled(SystemExit):
    """The user's code called ``os._exit``: in the verifier's process that would end it with
    no verdict (exit 0 and no output, for ``os._exit(0)``), so inside the user's code it
    raises this instead, and the check reports the ``crash`` counterexample.

    Cause: an algorithm (or a property) that ends its process. Fix: return a move; raise an
    exception to report a problem.

    Deliberately *not* a :class:`~gather_verify.errors.GatherVerifyError`: a ``SystemExit``
    (a ``BaseException``), as what the user's code called would have ended it with."""

    def __init__(self, status: int):
        super().__init__(f"os._exit({status}) called: it would end the verifier's process")
        self.status = status

    def __reduce__(self) -> tuple[Any, ...]:
        return ExitCalled, (self.status,)


_real_exit = os._exit


def _exit(status: int) -> NoReturn:
    if _inside and threading.current_thread() is threading.main_thread():
        raise ExitCalled(status)
    _real_exit(status)


def guard_exits() -> None:
    """Make ``os._exit`` raise :class:`ExitCalled` inside the user's code (:func:`watched`)
    on the main thread; everywhere else it ends the process as before."""
    os._exit = _exit


__all__ = ["GRACE_SECONDS", "INTERVAL", "ExitCalled", "OverMemory", "Overtime", "allowance",
           "available", "bounded", "count_interrupts", "deadline", "guard_exits", "guards", "interrupts_unreachable",
           "quiet", "real_interrupt", "watched"]
