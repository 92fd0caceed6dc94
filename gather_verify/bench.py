"""Explorer benchmark against SPIN: states/s, bytes per state, time to a verdict.

The bench instance: go-to-target, ASYNC, robots ``0,0 5,1 1,5 6,6 3,0``,
meeting node ``3,3`` (4,939,200 states without reductions); ``quick`` uses the
SEMANTICS.md yardstick (2184 states). Every measurement runs in a fresh Python
process and is timed *whole* (interpreter start, imports, search), as SPIN's
``seconds`` is (``spin -a`` + gcc + ``./pan``):

- ``explore``: reductions off, no properties, no edges kept: states/s and the
  peak resident memory grown during the search divided by the states stored;
- ``verdict``: ``run_check`` with reductions on and every property: the time to
  a verdict, compared with SPIN's whole run on the same instance (SPIN decides
  its safety model in that one run);
- ``full``: ``run_check`` with reductions off and every property (the graph kept for
  ``move-bound`` and ``termination``) on the same space as SPIN's safety search:
  states/s of the whole process beside SPIN's, and the peak resident memory grown
  during the check per state;
- ``spin``: ``bench/spin/run_spin.py`` when ``spin`` and the script are there,
  else the stored result in ``bench/spin/results/`` (labelled ``stored``);
- ``ring``: a finite world beside SPIN. The world check (``run_world_check``, its default engine: bulk) of
  go-to-target on ``ring:14``, robots ``5 6 7 8 9``, meeting node 0, ASYNC, reductions
  off (572,572 states; ``quick``: SEMANTICS.md §9's ``ring:9``, robots ``0 3 5``, meeting
  node 7, 225 states), then ``run_spin.py --world ring:N`` on the same space
  (``bench/spin/make_ring_model.py``; stored: ``ring.json``, ``ring-quick.json``). Our
  states/s whole process (the check with its properties) and of the search alone, beside
  SPIN's whole run and ``./pan`` alone; the start-up (the whole less the check: the
  interpreter, imports, and numba and the kernels, loaded by a check of the quick instance
  before the measured one) and SPIN's whole seconds over our check's;
- ``sweep`` (optional): configurations/s of the paper's algorithm, n=3, m=3,
  4 x 4, ASYNC, one worker, over the first ``sweep_limit`` configurations;
- ``schedulers`` (optional): the ``explore`` measurement under other schedulers (SSYNC,
  FSYNC: rounds) beside ASYNC, on the bench instance, its 3- and 4-robot prefixes and a
  second 5-robot instance (:data:`SECOND`; ``quick``: the quick instance and its 2-robot
  prefix), the runs interleaved: transitions per second whole process, per CPU second of
  the whole process and per CPU second of the search alone, and each one's ratio to ASYNC's.
  The search's CPU seconds include its fixed costs (its setup, the facts of every
  configuration it meets, a few milliseconds per chunk): FSYNC's spaces under go-to-target
  are paths of 58 to 176 states, all fixed cost, so their rate says how small they are, not
  how fast a round is;
- ``union`` (with ``schedulers``): a rate for every scheduler over a space that is not one
  instance's: the sweep of go-to-target over :data:`UNION` (the 4 x 4 box, 3 robots, 1 or 2
  meeting nodes; ``quick``: :data:`UNION_QUICK`), one worker, under ASYNC and each of
  ``schedulers`` the union engine runs, one fresh process each: the union graphs' states
  and transitions (every event whose successor it stored) per CPU second of those searches
  alone, and the sweep's configurations per CPU second of those searches (what a sweep
  under that scheduler costs per configuration decided by the union engine). Under FSYNC
  a union state is mostly a configuration of its own with one or two transitions, and its
  cost is that configuration's facts: the configurations per CPU second are the figure to
  read there.

Before the first child, the project's modules are compiled to bytecode, as an installed
copy's are (pip compiles them when it installs them; a checkout under
``PYTHONDONTWRITEBYTECODE`` never does), so no child pays that compile (about 0.07 CPU s).
The theories' modules, which a search imports on first use, are imported before the timed
search (a once-per-process cost, as the kernels are). Memory per state is measured from a
baseline taken once the compiled kernels the run uses are loaded (:func:`gather_verify.kernels.warm` of :data:`RUN_KERNELS`: numba and the compiled
code are a fixed cost, not a per-state one) and, for ``verdict`` and ``full``, the check's
modules imported (the same). A child exits as soon as its JSON is written, without the
interpreter's teardown (a C program's exit, as SPIN's ``./pan``). Every row also gives the
CPU seconds (user, system) of its whole process tree, which depend less on the machine's
load than the wall-clock seconds. Timings depend on the machine's load: compare runs made
back to back.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from functools import cache
from pathlib import Path
from typing import Any

FULL = ([(0, 0), (5, 1), (1, 5), (6, 6), (3, 0)], [(3, 3)])
SECOND = ([(0, 0), (6, 1), (1, 6), (7, 7), (9, 3)], [(4, 4)])
"""A second 5-robot instance for the ``schedulers`` rows (SSYNC: 691,200 states)."""
UNION = ("4x4", 3, "1-2")
UNION_QUICK = ("3x3", 2, "1")
"""The ``union`` rows' sweep: box, robots, meeting nodes (go-to-target, one worker)."""
QUICK = ([(0, 0), (3, 1), (1, 4)], [(2, 2)])
RING = ("ring:14", [5, 6, 7, 8, 9], 0)
RING_QUICK = ("ring:9", [0, 3, 5], 7)  # SEMANTICS.md §9's test data: 225 states, 560 transitions
ROOT = Path(__file__).resolve().parent.parent
"""The checkout: the project's packages and ``bench/``."""
SPIN_DIR = ROOT / "bench" / "spin"
RUN_KERNELS = {
    "explore": ("find_or_add", "place", "decode_chunk", "async_successors", "successor_keys"),
    "rounds": ("find_or_add", "place", "decode_chunk", "round_counts", "round_keys"),
    "verdict": ("find_or_add", "place", "decode_chunk", "async_successors",
                "successor_canonical_keys", "successor_rows", "longest_path"),
    "full": ("find_or_add", "place", "decode_chunk", "async_successors", "successor_keys",
             "successor_rows", "longest_path"),
}
"""The compiled kernels each Z² measurement runs (``rounds``: ``explore`` under FSYNC, SSYNC
or centralized), loaded before its memory baseline; the others are never loaded
(``tests/test_bench.py`` checks that a run loads none outside its list)."""


def _child(kind: str, robots: list, meeting: list, max_seconds: float,
           scheduler: str = "async") -> dict[str, Any]:
    """One measurement, inside the child process (``scheduler``: ``explore``'s only)."""
    import resource

    from gather_verify import kernels
    from gather_verify.engine.explore import Limits, rss_mb
    from gather_verify.engine.search import explore
    from gather_verify.model.configuration import Configuration
    from gather_verify.theory import get_fact

    c = Configuration([tuple(r) for r in robots], [tuple(m) for m in meeting], initial=True)
    if kind != "explore":  # the check's modules: a fixed cost too, not a per-state one
        from gather_verify.plane_check import run_check
    get_fact("in_U")  # the theories' modules, which a search imports on first use: the same
    # a fixed cost (numba and the compiled code), not a per-state one
    kernels.warm(RUN_KERNELS["rounds" if kind == "explore" and scheduler != "async" else kind])
    before = rss_mb()
    if kind == "explore":
        cpu = time.process_time()
        e = explore(c, "go-to-target", scheduler, reduction=False, properties=[], graph=False,
                    limits=Limits(max_seconds=max_seconds))
        cpu = time.process_time() - cpu
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        return {"scheduler": scheduler, "states": e.states, "transitions": e.transitions,
                "complete": e.stopped is None, "search_seconds": e.seconds,
                "search_cpu_seconds": cpu,
                "bytes_per_state": max(peak - before, 0.0) * 2**20 / e.states}
    if kind == "full":
        r = run_check(c, algorithm="go-to-target", scheduler="async", reduction=False,
                      max_states=30_000_000, max_seconds=max_seconds)
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        return {"verdict": r["verdict"], "states": r["states"], "transitions": r["transitions"],
                "max_moves": r["max_moves"], "check_seconds": r["seconds"],
                "properties": {k: v["holds"] for k, v in r["properties"].items()},
                "kernels": kernels.enabled(),
                "bytes_per_state": max(peak - before, 0.0) * 2**20 / r["states"]}
    r = run_check(c, algorithm="go-to-target", scheduler="async", reduction=True,
                  max_states=30_000_000, max_seconds=max_seconds)
    return {"verdict": r["verdict"], "states": r["states"], "transitions": r["transitions"],
            "max_moves": r["max_moves"], "check_seconds": r["seconds"]}


def _union_child(box: str, robots: int, meeting: str, max_seconds: float,
                 scheduler: str = "async") -> dict[str, Any]:
    """The sweep of ``go-to-target`` over ``box`` with ``robots`` robots and ``meeting`` nodes
    under ``scheduler``, one worker, inside the child process: the union engine's graphs (one
    per meeting-node shape; :func:`gather_verify.engine.union.explore_union`), their states,
    their transitions (the events whose successor keys it computed) and the CPU seconds of
    those searches alone (the sweep's enumeration, its per-configuration checks and its
    database are left out)."""
    from gather_verify.engine import union
    from gather_verify.sweeps.sweep import SweepSettings, run_sweep

    got = {"graphs": 0, "states": 0, "transitions": 0, "search_cpu_seconds": 0.0}
    explore_union, successor_keys = union.explore_union, union.successor_keys

    def timed(*args: Any, **kw: Any) -> Any:
        cpu = time.process_time()
        graph = explore_union(*args, **kw)
        got["search_cpu_seconds"] += time.process_time() - cpu
        if graph is not None:
            got["graphs"] += 1
            got["states"] += graph.states
        return graph

    def counted(keys: Any, codes: Any, src: Any, *rest: Any) -> Any:
        got["transitions"] += len(src)
        return successor_keys(keys, codes, src, *rest)

    union.explore_union, union.successor_keys = timed, counted
    width, height = map(int, box.split("x"))
    low, _, high = meeting.partition("-")
    settings = [SweepSettings(robots=robots, meeting=m, box=(width, height),
                              algorithm="go-to-target", scheduler=scheduler,
                              max_seconds=max_seconds)
                for m in range(int(low), int(high or low) + 1)]
    with tempfile.TemporaryDirectory() as tmp:
        summary = run_sweep(settings, os.path.join(tmp, "s.sqlite"), workers=1, progress=False,
                            engine="union")
    return {"scheduler": scheduler, "configurations": summary["total"], **got}


def _ring_child(world: str, robots: list, meeting: int, max_seconds: float) -> dict[str, Any]:
    """The world check of go-to-target on a ring, reductions off, inside the child process:
    its verdict and counts, the check's and the search's seconds, and the peak resident
    memory grown during the check per state (the graph is kept for ``termination``).

    Measured after a check of the quick ring instance (:data:`RING_QUICK`, 225 states): numba
    and the compiled kernels the check loads are a fixed cost, not a per-state one (as
    :func:`gather_verify.kernels.warm` for the Z² rows); its seconds are ``warm_seconds``."""
    import resource

    from gather_verify.engine.encoding import rss_mb
    from gather_verify.world_check import run_world_check

    warm = time.perf_counter()
    q_world, q_robots, q_meeting = RING_QUICK
    run_world_check(q_world, q_robots, [q_meeting], "go-to-target", "async", reduction=False)
    warm = time.perf_counter() - warm
    before = rss_mb()
    r = run_world_check(world, robots, [meeting], "go-to-target", "async", reduction=False,
                        max_states=30_000_000, max_seconds=max_seconds)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return {"verdict": r["verdict"], "task": r["task"], "reductions": r["reductions"],
            "engine": r["engine"], "states": r["states"], "transitions": r["transitions"],
            "complete": r["stopped"] is None, "check_seconds": r["seconds"],
            "search_seconds": r["search_seconds"], "warm_seconds": warm,
            "bytes_per_state": max(peak - before, 0.0) * 2**20 / r["states"]}


@cache
def _bytecode() -> None:
    """Write the bytecode of the project's modules once, before the first timed child, as an
    installed copy has it (pip compiles a package's modules when it installs them; a checkout
    run with ``PYTHONDONTWRITEBYTECODE`` set never writes them): else every child compiles
    them from source again, a cost of the checkout, not of the check. Where the checkout is
    read-only this quietly does nothing."""
    import compileall

    for top in ("gather_verify", "schedulers"):
        compileall.compile_dir(ROOT / top, quiet=2)


def _run_child(kind: str, instance: tuple, max_seconds: float,
               scheduler: str = "async") -> dict[str, Any]:
    """One measurement in a fresh process, timed whole; ``instance`` is ``(robots, meeting)``
    on Z², ``(world, robots, meeting)`` for ``ring``."""
    _bytecode()
    started, cpu = time.perf_counter(), _children_cpu()
    out = subprocess.run(
        [sys.executable, "-m", "gather_verify.bench", kind, json.dumps(list(instance)),
         str(max_seconds)] + ([scheduler] if scheduler != "async" else []),
        capture_output=True, text=True, check=True)
    result = json.loads(out.stdout)
    result["seconds"] = time.perf_counter() - started
    result["cpu_user_seconds"], result["cpu_system_seconds"] = _since(cpu)
    return result


def _children_cpu() -> tuple[float, float]:
    """CPU seconds (user, system) of every finished child process so far."""
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime, r.ru_stime


def _since(before: tuple[float, float]) -> tuple[float, float]:
    now = _children_cpu()
    return round(now[0] - before[0], 2), round(now[1] - before[1], 2)


def spin(instance: tuple, quick: bool, run: bool = True) -> dict[str, Any] | None:
    """SPIN's numbers: measured now when possible, else the stored ones (None if neither)."""
    robots, meeting = instance
    return _spin(["--robots", " ".join(f"{x},{y}" for x, y in robots),
                  "--meeting", "{},{}".format(*meeting[0])],
                 "quick.json" if quick else "grid.json", run)


def spin_ring(instance: tuple, quick: bool, run: bool = True) -> dict[str, Any] | None:
    """SPIN on the ring instance ``(world, robots, meeting)``
    (``bench/spin/make_ring_model.py``): measured now when possible, else stored."""
    world, robots, meeting = instance
    return _spin(["--world", world, "--robots", " ".join(map(str, robots)),
                  "--meeting", str(meeting)], "ring-quick.json" if quick else "ring.json", run)


def _spin(args: list[str], stored_name: str, run: bool) -> dict[str, Any] | None:
    script = SPIN_DIR / "run_spin.py"
    if run and shutil.which("spin") and shutil.which("gcc") and script.exists():
        cpu = _children_cpu()
        out = subprocess.run([sys.executable, str(script), *args], capture_output=True,
                             text=True)
        if out.returncode == 0:
            result = json.loads(out.stdout)
            result["source"] = "measured"
            result["cpu_user_seconds"], result["cpu_system_seconds"] = _since(cpu)
            return result
    stored = SPIN_DIR / "results" / stored_name
    if stored.exists():
        result = json.loads(stored.read_text())
        result["source"] = f"stored ({stored.name})"
        return result
    return None


def sweep_rate(limit: int) -> dict[str, Any]:
    """Configurations/s of ``gather-verify sweep`` (paper, n=3, m=3, 4x4, ASYNC, 1 worker),
    whole process, over the first ``limit`` configurations."""
    with tempfile.TemporaryDirectory() as tmp:
        started = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "gather_verify", "sweep", "--robots", "3", "--meeting", "3",
             "--box", "4x4", "--algorithm", "paper", "--scheduler", "async", "--workers", "1",
             "--limit", str(limit), "--db", os.path.join(tmp, "s.sqlite"), "--json"],
            capture_output=True, text=True)
        seconds = time.perf_counter() - started
    return {"configurations": limit, "seconds": seconds, "per_second": limit / seconds}


def schedulers_bench(schedulers: list[str], quick: bool = False, max_seconds: float = 3600.0
                     ) -> list[dict[str, Any]]:
    """The ``schedulers`` rows: per prefix of the bench instance (3, 4 and 5 robots; quick:
    2 and 3), ``explore`` under ASYNC and under each of ``schedulers``, one fresh process
    each, in that order; each row gives transitions per second (whole process, per CPU second
    of the whole process, per CPU second of the search) and its ratios to ASYNC's."""
    robots, meeting = QUICK if quick else FULL
    instances = [(robots[:k], meeting) for k in (
        range(len(robots) - 1, len(robots) + 1) if quick else (3, 4, 5))]
    rows: list[dict[str, Any]] = []
    for instance in instances if quick else [*instances, SECOND]:
        k = len(instance[0])
        base: dict[str, float] = {}
        for name in ["async", *schedulers]:
            r = _run_child("explore", instance, max_seconds, name)
            cpu = r["cpu_user_seconds"] + r["cpu_system_seconds"]
            rates = {"whole": r["transitions"] / r["seconds"],
                     "whole_cpu": r["transitions"] / max(cpu, 1e-9),
                     "search_cpu": r["transitions"] / max(r["search_cpu_seconds"], 1e-9)}
            if name == "async":
                base = rates
            rows.append({"robots": k, "instance": instance, **r,
                         "transitions_per_second": rates,
                         "ratio_to_async": {key: rates[key] / base[key] for key in rates}})
    return rows


def union_bench(schedulers: list[str], quick: bool = False, max_seconds: float = 3600.0
                ) -> list[dict[str, Any]]:
    """The ``union`` rows: the sweep of :data:`UNION` (quick: :data:`UNION_QUICK`) under ASYNC
    and each of ``schedulers`` that the union engine runs, one fresh process each: the union
    graphs' transitions per CPU second of their searches, and the ratio to ASYNC's."""
    from schedulers import get_scheduler

    box, robots, meeting = UNION_QUICK if quick else UNION
    rows: list[dict[str, Any]] = []
    base: dict[str, float] = {}
    for name in ["async", *schedulers]:
        if not getattr(get_scheduler(name), "union", False):
            continue
        r = _run_child("union", (box, robots, meeting), max_seconds, name)
        cpu = max(r["search_cpu_seconds"], 1e-9)
        rates = {"transitions": r["transitions"] / cpu, "states": r["states"] / cpu,
                 "configurations": r["configurations"] / cpu}
        base = rates if name == "async" else base
        rows.append({"box": box, "robots": robots, "meeting": meeting, **r,
                     "per_search_cpu": rates,
                     "ratio_to_async": {key: rates[key] / base[key] for key in rates}})
    return rows


def bench(quick: bool = False, max_seconds: float = 3600.0, run_spin: bool = True,
          sweep_limit: int = 0, schedulers: list[str] | None = None,
          schedulers_only: bool = False) -> dict[str, Any]:
    """Every measurement, as one JSON-able dict (see the module docstring); with
    ``schedulers_only``, only the ``schedulers`` rows."""
    if schedulers_only:
        return {"schedulers": schedulers_bench(schedulers or [], quick, max_seconds),
                "union": union_bench(schedulers or [], quick, max_seconds)}
    instance = QUICK if quick else FULL
    ours = _run_child("explore", instance, max_seconds)
    ours["states_per_second"] = ours["states"] / ours["seconds"]
    verdict = _run_child("verdict", instance, max_seconds)
    full = _run_child("full", instance, max_seconds)
    full["states_per_second"] = full["states"] / full["seconds"]
    theirs = spin(instance, quick, run_spin)
    out: dict[str, Any] = {
        "instance": {"name": "quick" if quick else "grid", "robots": instance[0],
                     "meeting": instance[1], "algorithm": "go-to-target", "scheduler": "async"},
        "explore": ours, "verdict": verdict, "full": full, "spin": None,
        "ratio_states_per_second": None, "ratio_time_to_verdict": None,
        "ratio_full_states_per_second": None, "sweep": None,
    }
    if theirs is not None:
        out["spin"] = {k: theirs.get(k) for k in (
            "source", "states", "edges", "seconds", "search_seconds", "states_per_second",
            "bytes_per_state", "cpu_user_seconds", "cpu_system_seconds")}
        out["ratio_states_per_second"] = ours["states_per_second"] / theirs["states_per_second"]
        out["ratio_time_to_verdict"] = theirs["seconds"] / verdict["seconds"]
        out["ratio_full_states_per_second"] = (full["states_per_second"]
                                               / theirs["states_per_second"])
    out["ring"] = ring_bench(quick, max_seconds, run_spin)
    if sweep_limit:
        out["sweep"] = sweep_rate(sweep_limit)
    if schedulers:
        out["schedulers"] = schedulers_bench(schedulers, quick, max_seconds)
        out["union"] = union_bench(schedulers, quick, max_seconds)
    return out


def ring_bench(quick: bool = False, max_seconds: float = 3600.0,
               run_spin: bool = True) -> dict[str, Any]:
    """The ring row: our world check, then SPIN on the same space, back to back."""
    world, robots, meeting = instance = RING_QUICK if quick else RING
    ours = _run_child("ring", instance, max_seconds)
    ours["states_per_second"] = ours["states"] / ours["seconds"]
    ours["search_states_per_second"] = ours["states"] / ours["search_seconds"]
    # the start-up: interpreter, imports, numba and the kernels (warm_seconds), the JSON out
    ours["startup_seconds"] = ours["seconds"] - ours["check_seconds"]
    theirs = spin_ring(instance, quick, run_spin)
    out: dict[str, Any] = {
        "instance": {"name": "ring-quick" if quick else "ring", "world": world,
                     "robots": robots, "meeting": meeting, "algorithm": "go-to-target",
                     "scheduler": "async"},
        "ours": ours, "spin": None, "same_space": None, "ratio_states_per_second": None,
        "ratio_search_states_per_second": None, "ratio_check_seconds": None,
    }
    if theirs is not None:
        out["spin"] = {k: theirs.get(k) for k in (
            "source", "states", "edges", "seconds", "search_seconds", "states_per_second",
            "search_states_per_second", "bytes_per_state", "cpu_user_seconds",
            "cpu_system_seconds")}
        out["same_space"] = (ours["states"], ours["transitions"]) == (theirs["states"],
                                                                      theirs["edges"])
        out["ratio_states_per_second"] = ours["states_per_second"] / theirs["states_per_second"]
        out["ratio_search_states_per_second"] = (ours["search_states_per_second"]
                                                 / theirs["search_states_per_second"])
        # each without its start-up: our check (search and properties) beside ./pan's run
        # (SPIN's start-up is spin -a and gcc, ours the interpreter, imports and numba)
        out["ratio_check_seconds"] = theirs["search_seconds"] / ours["check_seconds"]
    return out


def num(x: Any, fmt: str = ",.0f") -> str:
    """A number of the table, or ``-`` when there is none (SPIN not available)."""
    return "-" if x is None else format(x, fmt)


def format_bench(r: dict[str, Any], write: Any = print) -> None:
    """The side-by-side table."""
    if "explore" not in r:  # the schedulers' rows only
        format_schedulers(r["schedulers"], write)
        format_union(r.get("union") or [], write)
        return
    i, e, v, s = r["instance"], r["explore"], r["verdict"], r["spin"]
    write(f"instance {i['name']}: {i['algorithm']}, {i['scheduler']}, robots "
          + " ".join(f"{x},{y}" for x, y in i["robots"]) + ", meeting "
          + " ".join(f"{x},{y}" for x, y in i["meeting"]))
    label = f"SPIN ({s['source']})" if s else "SPIN (not available)"
    write(f"{'':34}{'gather-verify':>16}{label:>34}{'ratio':>8}")

    def row(name: str, ours: str, theirs: str, ratio: str = "") -> None:
        write(f"{name:34}{ours:>16}{theirs:>34}{ratio:>8}")

    row("states (reductions off)", num(e["states"]), num(s and s["states"]))
    row("transitions", num(e["transitions"]), num(s and s["edges"]))
    row("seconds, whole process", num(e["seconds"], ".2f"), num(s and s["seconds"], ".2f"))
    row("states/s, whole process", num(e["states_per_second"]),
        num(s and s["states_per_second"]), num(r["ratio_states_per_second"], ".2f"))
    row("bytes per stored state", num(e["bytes_per_state"], ".1f"),
        num(s and s["bytes_per_state"], ".1f"))
    row("time to verdict, reductions on (s)", num(v["seconds"], ".2f"),
        num(s and s["seconds"], ".2f"), num(r["ratio_time_to_verdict"], ".2f"))
    write(f"  verdict {v['verdict']}, {v['states']:,} states with reductions on, max moves "
          f"{v['max_moves']}; ratio = SPIN seconds / ours (goal >= 10)")
    f = r["full"]
    write("full verdict, reductions off, every property, beside SPIN's safety search:")
    row("  states", num(f["states"]), num(s and s["states"]))
    row("  seconds, whole process", num(f["seconds"], ".2f"), num(s and s["seconds"], ".2f"))
    row("  CPU seconds, user", num(f["cpu_user_seconds"], ".2f"),
        num(s and s.get("cpu_user_seconds"), ".2f"))
    row("  states/s, whole process", num(f["states_per_second"]),
        num(s and s["states_per_second"]), num(r["ratio_full_states_per_second"], ".2f"))
    row("  bytes per state, graph kept", num(f["bytes_per_state"], ".1f"),
        num(s and s["bytes_per_state"], ".1f"))
    write(f"  verdict {f['verdict']}, max moves {f['max_moves']}, compiled kernels "
          f"{'on' if f['kernels'] else 'off'}; ratio = our states/s / SPIN's (goal >= 1.5)")
    if not e["complete"]:
        write("  the reductions-off search hit --max-seconds: INCOMPLETE, rates are partial")
    if r.get("ring"):
        format_ring(r["ring"], write)
    if r["sweep"]:
        w = r["sweep"]
        write(f"sweep paper n=3 m=3 4x4 async, first {w['configurations']} configurations, "
              f"1 worker: {w['seconds']:.1f} s, {w['per_second']:.1f} configurations/s")
    if r.get("schedulers"):
        format_schedulers(r["schedulers"], write)
        format_union(r.get("union") or [], write)


def format_schedulers(rows: list[dict[str, Any]], write: Any = print) -> None:
    """The ``schedulers`` rows: transitions per second beside ASYNC's."""
    write("explore (go-to-target, reductions off, no properties) under each scheduler; "
          "transitions/s and ratio to ASYNC:")
    write(f"{'robots':>6} {'scheduler':>11} {'states':>11} {'transitions':>12} "
          f"{'whole s':>8} {'CPU s':>6} {'search CPU':>10} {'/s whole':>10} {'/CPU s':>10} "
          f"{'/search CPU s':>13} {'ratios: whole, CPU, search':>26}")
    instance = None
    for x in rows:
        if x.get("instance") != instance:
            instance = x.get("instance")
            if instance is not None:
                write("robots " + " ".join(f"{a},{b}" for a, b in instance[0]) + ", meeting "
                      + " ".join(f"{a},{b}" for a, b in instance[1]) + ":")
        t, q = x["transitions_per_second"], x["ratio_to_async"]
        cpu = x["cpu_user_seconds"] + x["cpu_system_seconds"]
        ratios = "" if x["scheduler"] == "async" else \
            f"{q['whole']:.2f} {q['whole_cpu']:.2f} {q['search_cpu']:.2f}"
        write(f"{x['robots']:>6} {x['scheduler']:>11} {x['states']:>11,} {x['transitions']:>12,} "
              f"{x['seconds']:>8.2f} {cpu:>6.2f} {x['search_cpu_seconds']:>10.2f} "
              f"{t['whole']:>10,.0f} {t['whole_cpu']:>10,.0f} {t['search_cpu']:>13,.0f} "
              f"{ratios:>26}")
        if not x["complete"]:
            write("  (stopped at a limit, --max-seconds or the states': INCOMPLETE, rates are "
                  "partial)")


def format_union(rows: list[dict[str, Any]], write: Any = print) -> None:
    """The ``union`` rows: the union graphs' transitions per CPU second of their searches."""
    if not rows:
        return
    x = rows[0]
    write(f"union engine, sweep of go-to-target, box {x['box']}, {x['robots']} robots, "
          f"meeting {x['meeting']}, 1 worker: per CPU second of the union searches, "
          "transitions, states and configurations")
    write(f"{'scheduler':>11} {'configurations':>14} {'graphs':>6} {'states':>10} "
          f"{'transitions':>12} {'search CPU':>10} {'transitions/s':>13} {'states/s':>10} "
          f"{'configs/s':>10} {'ratios: transitions, states, configs':>37} {'whole s':>8}")
    for x in rows:
        t, q = x["per_search_cpu"], x["ratio_to_async"]
        ratios = f"{q['transitions']:.2f} {q['states']:.2f} {q['configurations']:.2f}"
        write(f"{x['scheduler']:>11} {x['configurations']:>14,} {x['graphs']:>6} "
              f"{x['states']:>10,} {x['transitions']:>12,} {x['search_cpu_seconds']:>10.2f} "
              f"{t['transitions']:>13,.0f} {t['states']:>10,.0f} {t['configurations']:>10,.0f} "
              f"{ratios:>37} {x['seconds']:>8.2f}")


def format_ring(g: dict[str, Any], write: Any = print) -> None:
    """The ring row: our world check beside SPIN on the same space."""
    i, o, s = g["instance"], g["ours"], g["spin"]
    write(f"ring instance {i['world']}: {i['algorithm']}, {i['scheduler']}, robots "
          + " ".join(map(str, i["robots"])) + f", meeting {i['meeting']}, reductions off")
    label = f"SPIN ({s['source']})" if s else "SPIN (not available)"
    write(f"{'':34}{'gather-verify':>16}{label:>34}{'ratio':>8}")

    def row(name: str, ours: str, theirs: str, ratio: str = "") -> None:
        write(f"{name:34}{ours:>16}{theirs:>34}{ratio:>8}")

    row("  states", num(o["states"]), num(s and s["states"]))
    row("  transitions", num(o["transitions"]), num(s and s["edges"]))
    row("  seconds, whole process", num(o["seconds"], ".2f"), num(s and s["seconds"], ".2f"))
    row("  states/s, whole process", num(o["states_per_second"]),
        num(s and s["states_per_second"]), num(g["ratio_states_per_second"], ".3f"))
    row("  seconds, start-up", num(o.get("startup_seconds"), ".2f"), "")
    row("  seconds, check; ./pan (no start-up)", num(o["check_seconds"], ".2f"),
        num(s and s["search_seconds"], ".2f"), num(g.get("ratio_check_seconds"), ".3f"))
    row("  seconds, search only", num(o["search_seconds"], ".2f"),
        num(s and s["search_seconds"], ".2f"))
    row("  states/s, search only", num(o["search_states_per_second"]),
        num(s and s["search_states_per_second"]), num(g["ratio_search_states_per_second"], ".3f"))
    row("  bytes per state, graph kept", num(o["bytes_per_state"], ".1f"),
        num(s and s["bytes_per_state"], ".1f"))
    same = {None: "", True: ", the same space as SPIN's",
            False: ", NOT the same space as SPIN's"}[g["same_space"]]
    write(f"  verdict {o['verdict']} (task {o['task']}){same}")
    engine = {"bulk": "the bulk search (compiled kernels)",
              "reference": "the reference search (Python)"}.get(o.get("engine"), "the search")
    write(f"  ours: {engine}, then the task's properties; start-up: interpreter, imports, "
          "numba and the kernels (loaded by a check of ring:9 first); search only: our search, "
          "SPIN's ./pan; ratio = our states/s / SPIN's (check: ./pan's seconds / our check's)")
    if not o["complete"]:
        write("  the ring check hit --max-seconds: INCOMPLETE, rates are partial")


if __name__ == "__main__":  # the child of _run_child
    args = json.loads(sys.argv[2])
    if sys.argv[1] == "ring":
        result = _ring_child(*args, float(sys.argv[3]))
    elif sys.argv[1] == "union":
        result = _union_child(*args, float(sys.argv[3]), *sys.argv[4:5])
    else:  # an optional fourth argument: explore's scheduler
        result = _child(sys.argv[1], *args, float(sys.argv[3]), *sys.argv[4:5])
    print(json.dumps(result), flush=True)
    # The measurement is out: leave without the interpreter's teardown (freeing the search's
    # objects one by one: up to 0.4 s of a ring run), as a C program's exit does.
    sys.stderr.flush()
    os._exit(0)
