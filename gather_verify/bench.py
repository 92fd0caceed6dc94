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
- ``sweep`` (optional): configurations/s of the paper's algorithm, n=3, m=3,
  4 x 4, ASYNC, one worker, over the first ``sweep_limit`` configurations.

Memory per state is measured from a baseline taken once the compiled kernels are loaded
(:func:`gather_verify.kernels.warm`: numba and the compiled code are a fixed cost, not a
per-state one). Every row also gives the CPU seconds (user, system) of its whole process tree, which
depend less on the machine's load than the wall-clock seconds. Timings depend on the
machine's load: compare runs made back to back.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

FULL = ([(0, 0), (5, 1), (1, 5), (6, 6), (3, 0)], [(3, 3)])
QUICK = ([(0, 0), (3, 1), (1, 4)], [(2, 2)])
SPIN_DIR = Path(__file__).resolve().parent.parent / "bench" / "spin"


def _child(kind: str, robots: list, meeting: list, max_seconds: float) -> dict[str, Any]:
    """One measurement, inside the child process."""
    import resource

    from gather_verify import kernels
    from gather_verify.engine.explore import Limits, rss_mb
    from gather_verify.engine.search import explore
    from gather_verify.model.configuration import Configuration

    c = Configuration([tuple(r) for r in robots], [tuple(m) for m in meeting], initial=True)
    kernels.warm()  # a fixed cost (numba and the compiled code), not a per-state one
    before = rss_mb()
    if kind == "explore":
        e = explore(c, "go-to-target", "async", reduction=False, properties=[], graph=False,
                    limits=Limits(max_seconds=max_seconds))
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        return {"states": e.states, "transitions": e.transitions, "complete": e.stopped is None,
                "search_seconds": e.seconds,
                "bytes_per_state": max(peak - before, 0.0) * 2**20 / e.states}
    from gather_verify.check import run_check

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


def _run_child(kind: str, instance: tuple, max_seconds: float) -> dict[str, Any]:
    robots, meeting = instance
    started, cpu = time.perf_counter(), _children_cpu()
    out = subprocess.run(
        [sys.executable, "-m", "gather_verify.bench", kind, json.dumps([robots, meeting]),
         str(max_seconds)], capture_output=True, text=True, check=True)
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
    script = SPIN_DIR / "run_spin.py"
    if run and shutil.which("spin") and shutil.which("gcc") and script.exists():
        cpu = _children_cpu()
        out = subprocess.run(
            [sys.executable, str(script), "--robots", " ".join(f"{x},{y}" for x, y in robots),
             "--meeting", "{},{}".format(*meeting[0])], capture_output=True, text=True)
        if out.returncode == 0:
            result = json.loads(out.stdout)
            result["source"] = "measured"
            result["cpu_user_seconds"], result["cpu_system_seconds"] = _since(cpu)
            return result
    stored = SPIN_DIR / "results" / ("quick.json" if quick else "issue8.json")
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


def bench(quick: bool = False, max_seconds: float = 3600.0, run_spin: bool = True,
          sweep_limit: int = 0) -> dict[str, Any]:
    """Every measurement, as one JSON-able dict (see the module docstring)."""
    instance = QUICK if quick else FULL
    ours = _run_child("explore", instance, max_seconds)
    ours["states_per_second"] = ours["states"] / ours["seconds"]
    verdict = _run_child("verdict", instance, max_seconds)
    full = _run_child("full", instance, max_seconds)
    full["states_per_second"] = full["states"] / full["seconds"]
    theirs = spin(instance, quick, run_spin)
    out: dict[str, Any] = {
        "instance": {"name": "quick" if quick else "issue-8", "robots": instance[0],
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
    if sweep_limit:
        out["sweep"] = sweep_rate(sweep_limit)
    return out


def format_bench(r: dict[str, Any], write: Any = print) -> None:
    """The side-by-side table."""
    i, e, v, s = r["instance"], r["explore"], r["verdict"], r["spin"]
    write(f"instance {i['name']}: {i['algorithm']}, {i['scheduler']}, robots "
          + " ".join(f"{x},{y}" for x, y in i["robots"]) + ", meeting "
          + " ".join(f"{x},{y}" for x, y in i["meeting"]))
    label = f"SPIN ({s['source']})" if s else "SPIN (not available)"
    write(f"{'':34}{'gather-verify':>16}{label:>34}{'ratio':>8}")

    def row(name: str, ours: str, theirs: str, ratio: str = "") -> None:
        write(f"{name:34}{ours:>16}{theirs:>34}{ratio:>8}")

    def num(x: Any, fmt: str = ",.0f") -> str:
        return "-" if x is None else format(x, fmt)

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
    if r["sweep"]:
        w = r["sweep"]
        write(f"sweep paper n=3 m=3 4x4 async, first {w['configurations']} configurations, "
              f"1 worker: {w['seconds']:.1f} s, {w['per_second']:.1f} configurations/s")


if __name__ == "__main__":  # the child of _run_child
    robots, meeting = json.loads(sys.argv[2])
    print(json.dumps(_child(sys.argv[1], robots, meeting, float(sys.argv[3]))))
