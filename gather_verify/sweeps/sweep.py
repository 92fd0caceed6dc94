"""Exhaustive sweeps: every small configuration, classified and verified, results stored.

A sweep enumerates the configurations exactly as the census does (one per
class of translation + D4, in a fixed order), classifies each, runs the
explorer on every gatherable one, and writes one row per configuration into
the results store as results arrive. Re-running the same sweep resumes; the
work runs in this process, in a local process pool, or on a Dask cluster, and
the stored results are the same whichever ran them.
"""

from __future__ import annotations

import functools
import itertools
import os
import sys
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field, replace
from functools import partial
from typing import Any

from gather_verify.errors import GatherVerifyError, InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.sweeps.classes import ClassDecision, Item, verify_class
from gather_verify.sweeps.store import CAUSE_UNKNOWN, Store, check_row

CHUNK = 8
"""Configurations per task: enough to amortise process overhead, small enough to lose little."""


@dataclass(frozen=True)
class SweepSettings:
    """Everything that decides a sweep's results (and so identifies it in the store)."""

    robots: int
    meeting: int
    box: tuple[int, int]
    algorithm: str
    scheduler: str
    detection: str = "local-weak"
    frames: str = "all"
    properties: tuple[str, ...] = ()
    max_states: int = 2_000_000
    max_seconds: float = 600.0
    move_bound_c: float = 4.0
    reduction: bool = True
    keep_growing: bool = False
    """Grow a configuration's region after a violation too (``run_check``)."""
    extra: dict[str, Any] = field(default_factory=dict)
    max_memory_mb: float | None = None
    """Resident memory limit of each worker process; None: this machine's memory shared
    by the workers (:func:`gather_verify.engine.resources.memory_budget_mb`)."""
    force: bool = False
    """Check the configurations in U or UNCLASSIFIED too (``check --force``): for an
    algorithm that handles what the paper's partition misses."""
    fingerprint_extra: tuple[str, ...] = ()
    """Further files the results depend on (data the algorithm reads): their contents are
    part of the fingerprint (``--fingerprint-extra``)."""
    world: str = "grid"
    """The world (``grid``: Z² and its box; else a finite world, whose nodes replace the
    box). A finite world's sweep also names its ``task`` and the robots' ``visibility``."""
    task: str | None = None
    visibility: int | None = None
    lights: str | None = None
    initial_colours: str | None = None
    """``all``: every initial colouring of the robots (with lights), else all at 0."""

    @property
    def on_plane(self) -> bool:
        """Whether the Z² engines run the sweep's world (its ``entry``): its configurations
        are those of the box, else the world's own."""
        from gather_verify.worlds import PLANE, entry_of

        return entry_of(self.world) == PLANE

    def key(self) -> dict[str, Any]:
        """The identity of the sweep in the store (timing limits excluded only if
        they cannot change a verdict: they can, so they are included; the memory limit
        only when it is given, so the default does not depend on the machine)."""
        out = asdict(self)
        out["box"] = list(self.box)
        out["properties"] = list(self.properties)
        if self.max_memory_mb is None:
            del out["max_memory_mb"]
        if self.keep_growing:  # the rule every store before the field was written with:
            del out["keep_growing"]  # its rows stay found under --keep-growing
        out["fingerprint"] = self.fingerprint()  # never stale
        del out["fingerprint_extra"]
        if self.on_plane:  # the paper's world: keys as every store before worlds
            for name in ("world", "task", "visibility"):
                del out[name]
        else:
            del out["box"], out["move_bound_c"], out["keep_growing"]
        if self.lights is None:  # oblivious robots: keys as every store before lights
            del out["lights"]
        if self.initial_colours is None:
            del out["initial_colours"]
        if not self.force:  # the rule every store before the field was written with
            del out["force"]
        return out

    def check_options(self) -> dict[str, Any]:
        """The options of ``run_check`` on the paper's world that the sweep's settings give,
        for one configuration's check."""
        return dict(algorithm=self.algorithm, scheduler=self.scheduler,
                    detection=self.detection, frames=self.frames,
                    properties=self.properties or None, reduction=self.reduction,
                    max_states=self.max_states, max_seconds=self.max_seconds,
                    move_bound_c=self.move_bound_c, max_memory_mb=self.max_memory_mb,
                    keep_growing=self.keep_growing, force=self.force)

    def fingerprint(self) -> str:
        """The digest of the code and data behind the rows (:mod:`gather_verify.fingerprint`):
        the algorithm's, the graph file's, every property file's, the ``fingerprint_extra``
        files' and gather-verify's own source."""
        from gather_verify.fingerprint import sweep_fingerprint

        return sweep_fingerprint(self.inputs())

    def inputs(self, disk: bool = False) -> dict[str, str]:
        """Each input the rows depend on, with the digest this process computes them from
        (:func:`gather_verify.fingerprint.sweep_inputs`; ``disk``: as a worker sees them
        after a task)."""
        from gather_verify.fingerprint import algorithm_fingerprint, sweep_inputs

        return sweep_inputs(algorithm_fingerprint(self.algorithm)["digest"], self.world,
                            self.properties, self.fingerprint_extra, disk)


def configuration_key(c: Configuration) -> str:
    """Stable text key of a (canonical) configuration: the compact JSON of its sorted robots
    and meeting nodes, written out by hand (json.dumps took seconds over a whole box).

    >>> configuration_key(Configuration([(1, 0), (-1, 2)], [(0, 0)]))
    '[[[-1,2],[1,0]],[[0,0]]]'
    """
    robots = ",".join(f"[{x},{y}]" for x, y in sorted(c.robots))
    meeting = ",".join(f"[{x},{y}]" for x, y in sorted(c.meeting_nodes))
    return f"[[{robots}],[{meeting}]]"


def verify_one(settings: SweepSettings, index: int, c: Configuration) -> dict[str, Any]:
    """Classify and check one configuration; the row the store keeps."""
    from gather_verify.plane_check import run_check

    started = time.perf_counter()
    report = run_check(  # the checks of a sweep meet the same configurations again and again
        c, **settings.check_options(), memo=True)
    return check_row(report, configuration_key(c), index, [list(r) for r in c.robots], c,
                     time.perf_counter() - started)


Verify = Callable[[SweepSettings, int, Configuration], dict[str, Any]]
"""What decides one configuration into one row: :func:`verify_one`, or another row maker of
the same shape (the readings' robustness, :func:`gather_verify.paper.readings.verify_readings_one`)."""


def verify_chunk(settings: SweepSettings, chunk: Sequence[tuple[int, Configuration]],
                 verify: Verify = verify_one) -> list[dict[str, Any]]:
    """Verify a chunk of configurations, in order."""
    return [verify(settings, i, c) for i, c in chunk]


def _chunks(items: list[tuple[int, Configuration]], size: int) -> Iterator[list[tuple[int, Configuration]]]:
    for start in range(0, len(items), size):
        yield items[start:start + size]


class Progress:
    """A one-line progress bar with rate and ETA on a terminal; silent otherwise."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.done, self.enabled = total, 0, enabled and sys.stderr.isatty()
        self.started = time.monotonic()

    def advance(self, k: int) -> None:
        self.done += k
        if not self.enabled:
            return
        elapsed = time.monotonic() - self.started
        rate = self.done / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else float("inf")
        width = 30
        filled = int(width * self.done / max(self.total, 1))
        sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} "
                         f"{rate:6.1f} cfg/s ETA {eta:6.0f}s")
        sys.stderr.flush()

    def close(self) -> None:
        if self.enabled:
            sys.stderr.write("\n")


def run_sweep(
    settings: SweepSettings | Sequence[SweepSettings],
    db_path: str,
    *,
    workers: int | None = None,
    dask: str | None = None,
    progress: bool = True,
    limit: int | None = None,
    where: Callable[[SweepSettings, Configuration], bool] | None = None,
    fresh: bool = False,
    engine: str = "union",
    verify: Verify | None = None,
) -> dict[str, Any]:
    """Run (or resume) one sweep, or several (e.g. every n and m up to a bound) into
    one store; return the summary over all of them (see :func:`summarise`). Rows are
    keyed by the settings and the algorithm's fingerprint, so an edited algorithm is
    checked again; ``fresh`` drops the stored rows of these settings first. ``where``
    keeps only some configurations (the readings of :mod:`gather_verify.paper.readings`; the
    settings of such a sweep must say which, so the store does not mislead).

    ``engine="union"`` decides a meeting-node class at a time from one state graph
    (:mod:`gather_verify.sweeps.mclass`), ``"per-config"`` checks each configuration on
    its own; the rows are the same (timings aside). ``verify`` replaces :func:`verify_one`
    as the maker of each row (per configuration: the union engine does not apply)."""
    from gather_verify.sweeps.mclass import ENGINES

    if engine not in ENGINES:
        raise InvalidInput(f"unknown sweep engine {engine!r}: use one of {', '.join(ENGINES)}")
    batch = [settings] if isinstance(settings, SweepSettings) else list(settings)
    lit = LIT_FALLBACK if any(one.on_plane and one.lights for one in batch) else None
    if lit and verify is None:  # the union engine encodes no colours
        from gather_verify.sweeps.lit_census import verify_lit_one

        verify = verify_lit_one
    if verify is not None:  # a row maker of the caller's: one configuration at a time
        engine = "per-config"
    from gather_verify.algorithms.loading import snapshot
    from gather_verify.inputs import kept

    with kept(), snapshot(code_specs(batch)):  # fingerprinted and run: the same text
        summary = _run_sweep(batch, db_path, workers, dask, progress, limit, where, fresh,
                             engine, verify)
    return summary if lit is None else {**summary, "engine_fallback": lit}


LIT_FALLBACK = ("the union engine encodes no lights: each configuration and initial colouring "
                "was checked on its own, by the bulk engine")
"""What a luminous sweep of the paper's world says of its engine (summary ``engine_fallback``)."""


def _run_sweep(batch: list[SweepSettings], db_path: str, workers: int | None, dask: str | None,
               progress: bool, limit: int | None,
               where: Callable[[SweepSettings, Configuration], bool] | None, fresh: bool,
               engine: str, verify: Verify | None) -> dict[str, Any]:
    """:func:`run_sweep` once the algorithm files are snapshotted."""
    store = Store(db_path)
    try:
        plan = []
        census: dict[tuple, list[tuple[int, Configuration, str]]] = {}  # the readings share one
        for one in batch:
            sweep = store.sweep_id(one.key())
            if fresh:
                store.forget(sweep)
            store.refuse_damage(db_path, sweep)  # its rows are read back for the summary
            if one.fingerprint_extra:
                store.note_extra(sweep, one.fingerprint_extra)
            done = store.done_keys(sweep)
            shape = (one.world, one.robots, one.meeting, one.box, one.frames, one.lights,
                     one.initial_colours)
            if shape not in census:  # classes up to the robots' frame group, never more
                census[shape] = _listed(one, limit)
            todo = [(index, c) for index, c, key in census[shape]
                    if key not in done and (where is None or where(one, c))]
            plan.append((one, sweep, todo))
        bar = Progress(sum(len(todo) for _, _, todo in plan), progress)
        fallbacks: dict[str, int] = {}
        expected = {sweep: one.inputs() for one, sweep, _ in plan}
        try:
            for sweep, rows, why, basis in _execute(plan, workers, dask, engine, verify):
                refuse_changed(expected[sweep], basis, len(rows))
                store.add(sweep, rows)
                bar.advance(len(rows))
                for reason, count in why.items():
                    fallbacks[reason] = fallbacks.get(reason, 0) + count
        finally:
            bar.close()
        # counted in the store: reading back every row took seconds a whole box
        groups = [group for _, sweep, _ in plan for group in store.totals(sweep)]
        slowest = _slowest(row for _, sweep, _ in plan for row in store.slowest(sweep, SLOWEST))
        failed = [row for one, sweep, _ in plan if not one.on_plane  # a finite world's: which
                  for row in store.failing(sweep, FAILING)][:FAILING]
    finally:
        store.close()
    summary = summarise_totals(groups, slowest, batch[0] if len(batch) == 1 else None,
                               plane=all(one.on_plane for one in batch))
    if not summary["plane"]:
        summary["failing_configurations"] = failed
    summary["computed"] = sum(len(todo) for _, _, todo in plan)  # the rest was stored before
    if engine == "union":  # of those computed now: why the union left some to their own checks
        summary["union_fallbacks"] = dict(sorted(fallbacks.items(), key=lambda kv: (-kv[1], kv[0])))
    return summary


def refuse_changed(expected: dict[str, str], basis: dict[str, str], rows: int) -> None:
    """A row is stored only if every input it was computed from is the one its key names:
    one line naming the first input that is not (edited while the sweep ran, or another on
    a worker), the rows of the task not stored."""
    for name in sorted(set(expected) | set(basis)):
        if expected.get(name) != basis.get(name):
            raise InvalidInput(
                f"{name} changed while the sweep ran (or since this process first read it, "
                f"or it is another on a worker): the {rows} rows computed from it were not "
                "stored, since their key names the one read at the start; every row stored "
                "before is kept: run the same command again")


def _listed(settings: SweepSettings, limit: int | None) -> list[tuple[int, Any, str]]:
    """The sweep's configurations (the first ``limit``), with their index and stored key. A
    finite world's census (its world, its automorphisms, every class) is bounded by the
    limits of one configuration: past them, :class:`~gather_verify.engine.bounds.SetupStopped`
    (``ring:10000`` has 10,000 nodes and 20,000 automorphisms of 10,000 entries each)."""
    def listed() -> list[tuple[int, Any, str]]:
        return [(index, c, key) for index, (c, key) in itertools.islice(
            enumerate(_census(settings)), limit)]

    if settings.on_plane:  # the box is at most 64 x 64: its census is bounded by its size
        return listed()
    from gather_verify.engine.bounds import setup
    from gather_verify.engine.resources import memory_budget_mb

    with setup(f"listing the configurations of {settings.world}", settings.max_seconds,
               settings.max_memory_mb or memory_budget_mb()):
        return listed()


def _census(settings: SweepSettings) -> Iterator[tuple[Any, str]]:
    """The sweep's configurations in enumeration order, each with its stored key (its
    world's census, :func:`face_of`)."""
    return face_of(settings).census(settings)


def _plane_census(settings: SweepSettings) -> Iterator[tuple[Any, str]]:
    """The paper's world: one configuration per class of the box (translations and the
    robots' frame group), with lights one per initial colouring asked for."""
    from gather_verify.sweeps.census import enumerate_configurations
    from gather_verify.sweeps.lit_census import lit_configurations
    from gather_verify.worlds.moves import parse_lights

    k = parse_lights(settings.lights).colours
    for c in enumerate_configurations(settings.robots, settings.meeting, *settings.box,
                                      settings.frames):
        if settings.lights is None:
            yield c, configuration_key(c)
            continue
        for lit in lit_configurations(c, configuration_key(c), k, settings.frames,
                                      settings.initial_colours == "all"):
            yield lit, lit.key


def _world_census(settings: SweepSettings) -> Iterator[tuple[Any, str]]:
    """A finite world: one configuration per class under its symmetries."""
    from gather_verify.sweeps.world_census import world_configurations, world_key
    from gather_verify.worlds import finite_world
    from gather_verify.worlds.moves import parse_lights

    world = finite_world(settings.world)
    k = parse_lights(settings.lights).colours if settings.initial_colours == "all" else 1
    for c in world_configurations(world, settings.robots, settings.meeting, settings.frames, k):
        yield c, world_key(world, c)


Task = tuple[int, SweepSettings, list[tuple[int, Configuration]]]
"""One unit of work: the sweep's id in the store, its settings, a chunk of configurations."""
Done = tuple[int, list[dict[str, Any]], list[Task], dict[str, int], dict[str, str]]
"""What a task gives back: the sweep's id, its rows, the tasks it hands off, how many of its
configurations the union engine left to their own checks, by reason, and the digest of each
input its rows were computed from (:meth:`SweepSettings.inputs`)."""
Finished = tuple[int, list[dict[str, Any]], dict[str, int], dict[str, str]]
"""What :func:`_execute` yields per task: the sweep's id, its rows, its fallbacks by reason,
its inputs' digests."""

def warm_kernels(schedulers: Iterable[str]) -> None:
    """Compile (or load from numba's cache) the bulk engine's kernels before any row is
    timed, with a tiny check per scheduler: the first configuration of a sweep is then not
    charged the compile time."""
    from gather_verify.plane_check import run_check

    tiny = Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True)
    for scheduler in sorted(schedulers):
        for reduction in (True, False):
            run_check(tiny, algorithm="go-to-target", scheduler=scheduler, reduction=reduction,
                      max_seconds=60.0)


"""The engine of a finite world's sweep under ``engine="union"``: one state graph per
meeting-node class (:mod:`gather_verify.sweeps.world_union`)."""

HAND_OFF_SECONDS = 30.0
"""With several workers, a meeting-node class that has run this long hands its remaining
per-configuration checks to the other workers, one task each
(:func:`gather_verify.sweeps.classes.verify_class`)."""


def _execute(
    plan: list[tuple[SweepSettings, int, list[tuple[int, Configuration]]]],
    workers: int | None,
    dask: str | None,
    engine: str = "per-config",
    verify: Verify | None = None,
) -> Iterator[Finished]:
    """Every chunk of every sweep of the plan, as ``(sweep id, rows, fallbacks)`` when done. One pool
    (or cluster) runs them all, so its workers keep what they learnt (the algorithm's plans,
    the shared configuration facts) from one sweep to the next and none waits idle at the
    end of each sweep; the checks a long class hands off go out after the tasks before them."""
    local = dask is None and workers == 1
    if any(todo for _, _, todo in plan):  # forked workers inherit the compiled kernels
        warm_kernels({settings.scheduler for settings, _, _ in plan  # (none: finite worlds,
                      if face_of(settings).warm and not settings.lights})  # lights)
    tasks: list[Task] = []
    for settings, sweep, todo in plan:
        if engine == "union":  # a task is a meeting-node class, the largest first
            chunks = face_of(settings).class_tasks(settings, todo)
        else:
            chunks = list(_chunks(todo, CHUNK))
        if settings.max_memory_mb is None:  # the machine's memory, shared by the workers
            from gather_verify.engine.resources import memory_budget_mb

            settings = replace(settings, max_memory_mb=memory_budget_mb(
                1 if local else (workers or os.cpu_count() or 1)))
        tasks.extend((sweep, settings, chunk) for chunk in chunks)
    run: Callable[..., Done] = _run_task if verify is None else partial(_run_task, verify=verify)
    if engine == "union":
        tasks.sort(key=lambda task: -len(task[2]))  # the largest classes of every sweep first
        run = _run_class_task if local else partial(_run_class_task, hand_off=HAND_OFF_SECONDS)
    if dask is not None:
        yield from _execute_dask(tasks, dask, workers, run)
    elif local or not tasks:
        for task in tasks:
            sweep, rows, _, why, basis = run(task)  # nothing is handed off in this process
            yield sweep, rows, why, basis
    else:
        yield from _execute_pool(tasks, workers or os.cpu_count() or 1, run)


def _execute_pool(tasks: list[Task], workers: int, run: Callable[..., Done]
                  ) -> Iterator[Finished]:
    """The tasks on a local process pool, in order, and the ones they hand off after them."""
    import multiprocessing
    import queue

    done: queue.SimpleQueue = queue.SimpleQueue()
    pool = multiprocessing.get_context("fork").Pool(workers, initializer=_pool_worker,
                                                    initargs=(os.getpid(),))
    # the workers as the pool started them, before any task: they live as long as the pool,
    # so one that is gone, or replaced by a new one, was killed
    first = list(pool._pool)  # noqa: SLF001 - to notice a lost one, and how it ended
    started = {p.pid for p in first}

    def lost() -> bool:
        return {p.pid for p in pool._pool if p.exitcode is None} != started  # noqa: SLF001

    def submit(fn: Callable[..., Done], task: Task) -> None:
        pool.apply_async(fn, (task,), callback=done.put, error_callback=done.put)

    try:
        for task in tasks:
            submit(run, task)
        waiting = len(tasks)
        while waiting:
            try:
                got = done.get(timeout=1.0)  # (a timeout, so Ctrl-C is heard at once)
            except queue.Empty:
                # a worker killed never reports the task it held (the pool may have started
                # another in its place already): say so instead of waiting for ever
                if lost():
                    raise InvalidInput(_lost_worker(first)) from None
                continue
            waiting -= 1
            if isinstance(got, BaseException):
                raise got
            sweep, rows, more, why, basis = got
            for task in more:
                submit(_run_task, task)
            waiting += len(more)
            yield sweep, rows, why, basis
    finally:
        if lost():
            _abandon(pool)
        pool.terminate()


def _lost_worker(processes: list[Any]) -> str:
    """The line that says a pool worker died, how (a signal, an exit status) and what to do."""
    how = ""
    for p in processes:
        code = p.exitcode
        if code is not None and code < 0:
            import signal

            try:
                how = f" (killed by {signal.Signals(-code).name})"
            except ValueError:
                how = f" (killed by signal {-code})"
        elif code is not None:
            how = f" (it exited with status {code})"
    return (f"a worker process died{how} while it checked configurations: killed by the system "
            "for lack of memory, or ended by the algorithm's code in a way the verifier "
            "cannot catch (a signal, a crash of C code: docs/reliability.md); every finished "
            "row is kept: run the same command again to resume, perhaps with fewer --workers "
            "or a lower --max-memory-mb")


def _abandon(pool: Any) -> None:
    """Stop a pool that lost a worker, without its own clean-up: that waits for the lock of
    the task queue, which a worker killed while taking a task holds for ever (the sweep
    would hang on its way out). Its threads are daemons; its workers are killed here."""
    from multiprocessing.pool import TERMINATE

    pool._worker_handler._state = TERMINATE  # noqa: SLF001 - no worker started in their place
    for p in pool._pool:  # noqa: SLF001
        if p.exitcode is None:
            p.kill()
    pool._terminate.cancel()  # noqa: SLF001 - the clean-up the pool would run on exit


def _pool_worker(parent: int) -> None:
    """Pool workers leave Ctrl-C to the parent, which stops the pool and says how to resume
    (otherwise every worker prints its own traceback); and they end, quietly, when the
    parent ``parent`` (a process id) is killed, instead of finishing their task and printing
    the broken pipe they could not send it back through: at once on Linux (the kernel kills
    them), within a second elsewhere."""
    import signal
    import threading

    from gather_verify.watchdog import interrupts_unreachable

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    interrupts_unreachable()  # so a KeyboardInterrupt here is the user's code's: a crash
    if sys.platform.startswith("linux"):
        import ctypes
        from contextlib import suppress

        with suppress(OSError, AttributeError):  # prctl(PR_SET_PDEATHSIG, SIGKILL)
            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)

    def orphaned() -> None:
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(1)

    threading.Thread(target=orphaned, name="gather-verify parent watch", daemon=True).start()


Shipped = tuple[dict[str, dict[str, str]] | None, dict[str, bytes] | None]
"""What a worker needs that it may not see: the code files of the sweep's snapshot
(:func:`gather_verify.algorithms.loading.ship`) and the input files its parent read once
(:func:`gather_verify.inputs.export`: graph files, extras)."""


class WorkerFailed(GatherVerifyError, RuntimeError):
    """A sweep's worker failed with an exception that is no verdict and no bad input: a bug
    of gather-verify (the message holds the worker's traceback).

    Cause: an exception escaped the verifier's own code in a worker process. Fix: report it
    with the command line; every row stored before is kept."""


def worker_task(run: Callable[..., tuple[Any, ...]]) -> Callable[..., Done]:
    """A worker's entry point from ``run(task, **options) -> (sweep, rows, more, why)``:
    the task runs on the parent's snapshot (``shipped``: the code it ran, the input files it
    read), reports the digest of every input its rows were computed from
    (:meth:`SweepSettings.inputs` with ``disk``), and an exception that would end the worker
    process (with a traceback of its own) comes back to the parent as :class:`WorkerFailed`.
    Picklable: it is looked up by its module-level name."""

    @functools.wraps(run)
    def entry(task: Task, shipped: Shipped = (None, None), **options: Any) -> Done:
        import threading
        import traceback

        from gather_verify.algorithms.loading import receive
        from gather_verify.inputs import adopt, kept
        from gather_verify.watchdog import interrupts_unreachable

        if threading.current_thread() is not threading.main_thread():
            interrupts_unreachable()  # a Dask task: no Ctrl-C reaches this thread
        sources, files = shipped
        settings = task[1]
        with kept():
            if sources:
                receive(sources)
            adopt(files or {})
            try:
                sweep, rows, more, why = run(task, **options)
                return sweep, Store.encode(rows), more, why, settings.inputs(disk=True)
            except (GatherVerifyError, OSError):
                raise  # bad input, one line in the parent as anywhere
            except BaseException as error:  # never a worker's own traceback on the terminal
                raise WorkerFailed(f"a sweep worker failed: {type(error).__name__}: {error}\n"
                                   + "".join(traceback.format_exception(error))) from None

    return entry


@worker_task
def _run_task(task: Task, verify: Verify | None = None) -> tuple[Any, ...]:
    """Worker entry point (picklable for process pools and Dask): each configuration of the
    chunk checked on its own; ``verify``: the row maker (by default the world's,
    :func:`face_of`)."""
    sweep, settings, chunk = task
    return sweep, verify_chunk(settings, chunk, verify or face_of(settings).verify_one), [], {}


@worker_task
def _run_class_task(task: Task, hand_off: float | None = None) -> tuple[Any, ...]:
    """Worker entry point of ``engine="union"``: the chunk is one meeting-node class, decided
    by its world's union engine; the per-configuration checks left after ``hand_off`` seconds
    come back as tasks, for the other workers."""
    sweep, settings, chunk = task
    fallbacks: dict[str, int] = {}
    face = face_of(settings)
    rows, rest = verify_class(settings, chunk, face.decide_class, face.verify_one, hand_off,
                              fallbacks)
    return sweep, rows, [(sweep, settings, part) for part in _chunks(rest, face.hand_off_chunk)], \
        fallbacks


def _execute_dask(tasks: list[Task], address: str, workers: int | None,
                  run: Callable[..., Done] = _run_task,
                  ) -> Iterator[Finished]:
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InvalidInput("--dask needs the dask extra: pip install 'gather-verify[dask]'") from None
    cluster = client = None
    try:
        if address == "local":
            import logging

            with _workers_stderr_discarded():
                cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1,
                                       threads_per_worker=1, processes=True,
                                       dashboard_address=None,
                                       # no nanny warnings at close, nor a worker's heartbeat
                                       # failing while an interrupted sweep stops the cluster
                                       silence_logs=logging.CRITICAL)
            client = Client(cluster)
        else:
            try:
                client = Client(address, timeout=30)
            except (OSError, ValueError, TypeError) as error:  # a bad or unreachable address
                raise InvalidInput(f"--dask {address}: cannot reach a Dask scheduler there "
                                   f"({type(error).__name__}: {error}); give 'local' or "
                                   "tcp://HOST:PORT") from None
        shipped = _shipped([settings for _, settings, _ in tasks])
        pending = as_completed(client.map(run, tasks, shipped=shipped, pure=False))
        for future in pending:
            try:
                sweep, rows, more, why, basis = future.result()
            except Exception as error:
                if type(error).__name__ == "KilledWorker":  # the task's worker died, again
                    raise InvalidInput(f"Dask: {_lost_worker([])}") from None
                raise
            for task in more:
                pending.add(client.submit(_run_task, task, shipped=shipped, pure=False))
            yield sweep, rows, why, basis
    except KeyboardInterrupt:  # stop the workers quietly; the command says what was kept
        _quiet_dask_logs()
        if address == "local" and cluster is None:
            _leave_unstarted_clusters()
        raise
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()


def _shipped(batch: Iterable[SweepSettings]) -> Shipped:
    """What workers on other machines need of the sweeps ``batch``: the snapshot of their
    code files (algorithms, property files) and of the graph and extra files they read."""
    from gather_verify.algorithms.loading import ship
    from gather_verify.inputs import export

    batch = list(batch)
    files = [f for one in batch for f in one.fingerprint_extra]
    files += [one.world.partition(":")[2] for one in batch if one.world.startswith("graph:")]
    return ship(code_specs(batch)) or None, export(files) or None


def code_specs(batch: Iterable[SweepSettings]) -> set[str]:
    """The algorithm and property files of the sweeps ``batch`` (what a snapshot copies)."""
    return {spec for one in batch for spec in (one.algorithm, *one.properties)}


@contextmanager
def _workers_stderr_discarded() -> Iterator[None]:
    """While a local Dask cluster starts, its worker processes take /dev/null as their
    standard error (a spawned process inherits the parent's): a terminal's Ctrl-C reaches the
    whole process group, and each worker would print its traceback (every one at its own
    stage of starting: no signal mask or handler set in time covers them all). The parent
    alone says what was kept and how to resume, as the process pool's workers leave it to
    the parent; a worker's failure still reaches the parent through its task."""
    try:
        saved = os.dup(2)
    except OSError:  # no standard error to begin with
        yield
        return
    sys.stderr.flush()
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 2)
    os.close(null)
    try:
        yield
    except BaseException:  # interrupted while it starts: its threads may spawn workers yet,
        # so they keep /dev/null, and this process writes on through the saved descriptor
        sys.stderr = open(saved, "w", buffering=1, encoding=sys.stderr.encoding,  # noqa: SIM115
                          errors="backslashreplace")
        raise
    sys.stderr.flush()
    os.dup2(saved, 2)
    os.close(saved)


def _leave_unstarted_clusters() -> None:
    """A local cluster interrupted while it starts cannot be closed (Dask's own exit hook
    fails on its half-started workers, with a traceback): it is left to end with this
    process, as its workers do (each watches its parent)."""
    from distributed.deploy.spec import SpecCluster

    for cluster in list(getattr(SpecCluster, "_instances", ())):
        cluster.shutdown_on_close = False


def _quiet_dask_logs() -> None:
    """Dask's own logs at CRITICAL: an interrupted sweep closes its cluster without the
    warnings of futures cancelled and connections closed on the way."""
    import logging

    for name in ("distributed", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL)


def summarise(rows: list[dict[str, Any]], settings: SweepSettings | None = None) -> dict[str, Any]:
    """Totals per class and verdict, failing properties (``failing_properties``: the one each
    configuration names first; ``failing_every``: every one that fails), worst ratios,
    slowest configurations."""
    groups = [(r["class"], r["verdict"], r.get("property"), r.get("failing"), 1, r.get("ratio"),
               r.get("cause")) for r in rows]
    from gather_verify.theory import get_fact

    plane = settings.on_plane if settings is not None else all(
        r["class"] in get_fact("class").values for r in rows)
    summary = summarise_totals(groups, _slowest(rows), settings, plane=plane)
    if not plane:  # a finite world's: which configurations failed
        summary["failing_configurations"] = [
            {k: r[k] for k in ("robots", "meeting_nodes", "class", "property")}
            for r in rows if r["verdict"] == "VIOLATED"][:FAILING]
    return summary


SLOWEST = 5
"""How many of the slowest configurations a summary names."""


def _slowest(rows: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    return sorted(rows, key=lambda r: -(r.get("seconds") or 0.0))[:SLOWEST]


FAILING = 20
"""How many VIOLATED configurations a finite world's summary names (in enumeration order)."""


def summarise_totals(groups: Iterable[tuple[Any, ...]], slowest: list[dict[str, Any]],
                     settings: SweepSettings | None = None, plane: bool = True
                     ) -> dict[str, Any]:
    """:func:`summarise` from rows counted in groups (``Store.totals``: ``(class, verdict,
    property, failing, count, largest ratio, cause)``, in order of first row) and the slowest
    rows. ``causes``: per failing property (the one each configuration names first), its
    count per cause; a row with none (stored before causes, or a finite world's) counts under
    :data:`~gather_verify.sweeps.store.CAUSE_UNKNOWN`."""
    from gather_verify.theory import get_fact

    # the paper's classes on its world; a finite world's rows are counted by world
    classes = dict.fromkeys(get_fact("class").values if plane else (), 0)
    verdicts: dict[str, dict[str, int]] = {}
    failing: dict[str, dict[str, int]] = {}
    every: dict[str, dict[str, int]] = {}
    worst: dict[str, float] = {}
    total = 0
    causes: dict[str, dict[str, int]] = {}
    for name, verdict, prop, fails, count, ratio, *cause in groups:
        total += count
        classes[name] = classes.get(name, 0) + count
        by = verdicts.setdefault(name, {})
        by[verdict] = by.get(verdict, 0) + count
        if verdict == "VIOLATED" and prop:
            f = failing.setdefault(name, {})
            f[prop] = f.get(prop, 0) + count
            why = (cause[0] if cause else None) or CAUSE_UNKNOWN
            by_cause = causes.setdefault(prop, {})
            by_cause[why] = by_cause.get(why, 0) + count
            e = every.setdefault(name, {})
            for one in fails or [prop]:
                e[one] = e.get(one, 0) + count
        if ratio is not None:
            worst[name] = max(worst.get(name, 0.0), float(ratio))
    return {
        "settings": settings.key() if settings else None,
        "plane": plane,
        "total": total,
        "classes": classes,
        "verdicts": verdicts,
        "failing_properties": failing,
        "failing_every": every,
        "causes": {p: dict(sorted(c.items(), key=lambda kv: (-kv[1], kv[0])))
                   for p, c in sorted(causes.items())},
        "max_ratio": worst,
        "slowest": [{"robots": r["robots"], "meeting_nodes": r["meeting_nodes"],
                     "class": r["class"], "seconds": round(r.get("seconds") or 0.0, 3)}
                    for r in slowest],
    }


def format_summary(summary: dict[str, Any], write: Callable[[str], Any] = print) -> None:
    """The report as text tables."""
    from gather_verify.scenario import VERDICTS

    computed = summary.get("computed")
    write(f"{summary['total']} configurations" + ("" if computed is None else
          f" ({computed} computed now, {summary['total'] - computed} reused from the database)"))
    from gather_verify.theory import get_fact, preconditions

    worlds = not summary.get("plane", True) or any(
        k and name not in get_fact("class").values for name, k in summary["classes"].items())
    header = (f"{'world' if worlds else 'class':<13}{'count':>7}"
              + "".join(f"{v:>16}" for v in VERDICTS) + ("" if worlds else f"{'max ratio':>11}"))
    write(header)
    write("-" * len(header))
    for name, count in summary["classes"].items():
        if not count:
            continue
        by = summary["verdicts"].get(name, {})
        ratio = summary["max_ratio"].get(name)
        write(f"{name:<13}{count:>7}" + "".join(f"{by.get(v, 0):>16}" for v in VERDICTS)
              + ("" if worlds else f"{ratio:>11.2f}" if ratio is not None else f"{'-':>11}"))
    if not worlds:  # and what each precondition's NOT-APPLICABLE means (gather_verify.theory)
        write("; ".join(["max ratio: the largest total moves / (D·n) of the class",
                         *(p.legend for p in preconditions() if p.legend)]))
    if summary["failing_properties"]:
        write("")
        write("failing properties (the first of each configuration, whose trace is stored; "
              "check it with --property P for another's):")
        for name, props in summary["failing_properties"].items():
            write(f"  {name}: " + ", ".join(f"{p} x{k}" for p, k in sorted(props.items())))
    if summary.get("failing_every", summary["failing_properties"]) != summary["failing_properties"]:
        write("every failing property (a configuration counts once for each):")
        for name, props in summary["failing_every"].items():
            write(f"  {name}: " + ", ".join(f"{p} x{k}" for p, k in sorted(props.items())))
    if any(set(by) != {CAUSE_UNKNOWN} for by in summary.get("causes", {}).values()):
        write("")
        write("failing properties by cause (the first failing property of each configuration):")
        for prop, by in summary["causes"].items():
            write(f"  {prop} x {sum(by.values())}: "
                  + ", ".join(f"{why} {k}" for why, k in by.items()))
    if summary.get("engine_fallback"):
        write("")
        write(f"engine: {summary['engine_fallback']}")
    if summary.get("union_fallbacks"):
        write("")
        write("checked on their own, not from the union engine's shared graph (of those "
              "computed now), by reason:")
        for why, k in summary["union_fallbacks"].items():
            write(f"  {k:>6}  {why}")
    failed = summary.get("failing_configurations")
    if failed:
        count = sum(by.get("VIOLATED", 0) for by in summary["verdicts"].values())
        write("")
        write(f"failing configurations ({'the first ' + str(len(failed)) + ' of ' if count > len(failed) else ''}"
              f"{count}, in enumeration order):")
        for r in failed:
            write(f"  {r['class']}  robots={r['robots']} meeting={r['meeting_nodes']}: "
                  f"{r['property']}")
    if summary["slowest"]:
        write("")
        write("slowest configurations:")
        for r in summary["slowest"]:
            write(f"  {r['seconds']:8.3f}s  {r['class']:<5} robots={r['robots']} meeting={r['meeting_nodes']}")


@dataclass(frozen=True)
class SweepFace:
    """What a world supplies to the one sweep (its ``entry`` names it,
    :func:`~gather_verify.worlds.entry_of`): its census (the configurations with their stored
    keys, in enumeration order), the row of one configuration, and its union engine (the
    configurations grouped by meeting-node class, the largest first, and what one state
    graph of a class decides, :class:`~gather_verify.sweeps.classes.ClassDecision`: the rest
    are checked on their own, by :func:`~gather_verify.sweeps.classes.verify_class`, handed
    off ``hand_off_chunk`` at a time); ``warm``: its checks run the compiled kernels, to be
    compiled before the first row is timed."""

    census: Callable[[SweepSettings], Iterator[tuple[Any, str]]]
    verify_one: Verify
    class_tasks: Callable[[SweepSettings, list[Item]], list[list[Item]]]
    decide_class: Callable[[SweepSettings, Sequence[Item]], ClassDecision]
    hand_off_chunk: int
    warm: bool


def _plane_class_tasks(settings: SweepSettings, todo: list[Item]) -> list[list[Item]]:
    from gather_verify.sweeps.mclass import class_tasks

    return class_tasks(todo, settings.frames)


def _plane_class(settings: SweepSettings, chunk: Sequence[Item]) -> ClassDecision:
    from gather_verify.sweeps.mclass import decide_class

    return decide_class(settings, chunk, configuration_key)


def _world_one(settings: SweepSettings, index: int, c: Any) -> dict[str, Any]:
    from gather_verify.sweeps.world_census import verify_world_one

    return verify_world_one(settings, index, c)


def _world_class_tasks(settings: SweepSettings, todo: list[Item]) -> list[list[Item]]:
    from gather_verify.sweeps.world_union import world_class_tasks

    return world_class_tasks(settings, todo)


def _world_class(settings: SweepSettings, chunk: Sequence[Item]) -> ClassDecision:
    from gather_verify.sweeps.world_union import decide_world_class

    return decide_world_class(settings, chunk)


SWEEP_FACES: dict[str, SweepFace] = {
    "plane": SweepFace(_plane_census, verify_one, _plane_class_tasks, _plane_class, 1, True),
    "finite": SweepFace(_world_census, _world_one, _world_class_tasks, _world_class, CHUNK,
                        False),
}
"""Each world entry's face (:data:`gather_verify.worlds.base.PLANE`,
:data:`~gather_verify.worlds.base.FINITE`): a world with an entry of its own adds one line."""


def face_of(settings: SweepSettings) -> SweepFace:
    """The face of the sweep's world."""
    from gather_verify.worlds import entry_of

    return SWEEP_FACES[entry_of(settings.world)]
