#!/usr/bin/env python3
"""Run the SPIN yardstick: generate the Promela model, `spin -a`, gcc, `./pan`.

    python3 bench/spin/run_spin.py --robots "0,0 5,1 1,5 6,6 3,0" --meeting 3,3
    python3 bench/spin/run_spin.py --quick      # robots 0,0 3,1 1,4, M 2,2
    python3 bench/spin/run_spin.py --ring       # ring:14, robots 5 6 7 8 9, m 0
    python3 bench/spin/run_spin.py --ring --quick   # ring:9, robots 0 3 5, m 7
    python3 bench/spin/run_spin.py --world ring:9 --robots "0 3 5" --meeting 7

Everything happens in a fresh temporary directory (unless --keep DIR). Prints
one JSON object on stdout; the fields are documented in bench/spin/README.md.
The main ones:

  instance                  algorithm, scheduler, reductions, robots, meeting
                            (and world, for a ring)
  states                    pan's "states, stored"
  transitions               pan's "transitions (= stored+matched)"
  edges                     transitions - 1 = adversary actions (one d_step each)
  seconds                   whole run: generate + spin -a + gcc + pan (wall)
  search_seconds            ./pan alone (wall)
  states_per_second         states / seconds
  search_states_per_second  states / search_seconds
  memory_mb                 pan's "total actual memory usage"
  expected_states/edges, validated   closed-form counts and whether pan agrees

Exit status: 0 on success; 2 if spin or gcc is missing; 1 on any other
failure (pan error, truncated depth, memory limit hit, counts that disagree
with the closed form). Diagnostics go to stderr. Standard library only;
nothing from the rest of the repository is used.
"""
from __future__ import annotations

import time

T_PROCESS = time.perf_counter()

import argparse  # noqa: E402
import datetime  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import re  # noqa: E402
import shutil  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # leave no __pycache__ in the repository
import make_model  # noqa: E402
import make_ring_model  # noqa: E402

QUICK = ("0,0 3,1 1,4", "2,2")                  # SEMANTICS.md §4 yardstick
GRID = ("0,0 5,1 1,5 6,6 3,0", "3,3")         # the grid instance: the measuring stick
RING_QUICK = ("ring:9", "0 3 5", "7")           # SEMANTICS.md §9 test data
RING = ("ring:14", "5 6 7 8 9", "0")            # the ring instance of gather-verify bench
GCC_FLAGS = ["-O2", "-DNOREDUCE", "-DSAFETY"]


class Failure(Exception):
    pass


def _num(pattern: str, text: str, cast=int):
    m = re.search(pattern, text, re.MULTILINE)
    return cast(m.group(1)) if m else None


def parse_pan(out: str) -> dict:
    return {
        "states": _num(r"^\s*(\d+) states, stored", out),
        "matched": _num(r"^\s*(\d+) states, matched", out),
        "transitions": _num(r"^\s*(\d+) transitions \(= stored\+matched\)", out),
        "atomic_steps": _num(r"^\s*(\d+) atomic steps", out),
        "memory_mb": _num(r"^\s*([\d.]+)\s+total actual memory usage", out, float),
        "state_memory_mb": _num(r"^\s*([\d.]+)\s+actual memory usage for states",
                                out, float),
        "hash_table_mb": _num(r"^\s*([\d.]+)\s+memory used for hash table", out, float),
        "pan_elapsed_seconds": _num(r"pan: elapsed time ([\d.e+-]+) seconds", out, float),
        "state_vector_bytes": _num(r"State-vector (\d+) byte", out),
        "depth_reached": _num(r"depth reached (\d+)", out),
        "errors": _num(r"errors: (\d+)", out),
        "hash_conflicts": _num(r"hash conflicts:\s+(\d+)", out),
    }


def _cmd(cmd: list[str], cwd: str) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)


def machine_info() -> dict:
    def first_line(cmd):
        try:
            out = subprocess.run(cmd, capture_output=True, text=True).stdout
            return out.strip().splitlines()[0]
        except (OSError, IndexError):
            return "unknown"

    cpu = "unknown"
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        nproc = len(os.sched_getaffinity(0))
    except AttributeError:
        nproc = os.cpu_count()
    return {
        "nproc": nproc,
        "cpu": cpu,
        "spin_version": first_line(["spin", "-V"]),
        "gcc_version": first_line(["gcc", "--version"]),
        "date": datetime.datetime.now(datetime.UTC)
                        .strftime("%Y-%m-%dT%H:%M:%SZ"),
    }


def grid_longest_path(robots, meeting) -> int:
    """Length of the longest execution: a Look and a Move per unit distance."""
    return sum(2 * (abs(x - meeting[0]) + abs(y - meeting[1])) for x, y in robots)


def run_once(model, depth: int, hash_log2: int, memlim: int | None,
             workdir: str, t0: float) -> dict:
    """One pipeline run; ``model()`` gives the Promela text (generated inside the timing)."""
    with open(os.path.join(workdir, "model.pml"), "w", encoding="ascii") as fh:
        fh.write(model())

    gcc_flags = list(GCC_FLAGS) + ([f"-DMEMLIM={memlim}"] if memlim else [])
    t_c0 = time.perf_counter()
    r = _cmd(["spin", "-a", "model.pml"], workdir)
    if r.returncode != 0:
        raise Failure(f"spin -a failed: {(r.stderr or r.stdout).strip()}")
    r = _cmd(["gcc", *gcc_flags, "-o", "pan", "pan.c"], workdir)
    if r.returncode != 0:
        raise Failure(f"gcc failed: {r.stderr.strip()}")
    compile_seconds = time.perf_counter() - t_c0

    pan_args = ["-E", f"-m{depth}", f"-w{hash_log2}"]
    t_p0 = time.perf_counter()
    r = _cmd(["./pan", *pan_args], workdir)
    search_seconds = time.perf_counter() - t_p0
    seconds = time.perf_counter() - t0
    out = r.stdout + r.stderr
    with open(os.path.join(workdir, "pan.out"), "w") as fh:
        fh.write(out)

    # Fail loudly on anything that means the search was not exhaustive.
    for bad, why in (("max search depth too small", "depth truncated, raise -m"),
                     ("reached -DMEMLIM bound", "memory limit hit"),
                     ("out of memory", "out of memory"),
                     ("Search not completed", "search not completed")):
        if bad in out:
            raise Failure(f"pan: {why}\n{out}")
    info = parse_pan(r.stdout)
    if r.returncode != 0 or info["states"] is None or info["transitions"] is None:
        raise Failure(f"pan failed (rc={r.returncode}):\n{out}")
    if info["errors"]:
        raise Failure(f"pan reported {info['errors']} error(s):\n{out}")
    if info["depth_reached"] is None or info["depth_reached"] >= depth - 1:
        raise Failure(f"pan: depth reached {info['depth_reached']} is at the "
                      f"-m{depth} limit; the search may be truncated")
    info.update(compile_seconds=compile_seconds, search_seconds=search_seconds,
                seconds=seconds, gcc_flags=" ".join(gcc_flags),
                pan_args=" ".join(pan_args))
    return info


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description="SPIN yardstick: go-to-target on Z x Z or ring:N, ASYNC, "
                    "identities kept, no reduction. Prints one JSON object.")
    ap.add_argument("--world", default="grid",
                    help="grid (Z x Z, the default) or ring:N")
    ap.add_argument("--robots", default=None,
                    help=f'robot nodes: "x,y ..." on the grid (default, the grid instance: '
                         f'"{GRID[0]}"), "v ..." on a ring')
    ap.add_argument("--meeting", default=None,
                    help=f"meeting node: x,y on the grid (default, the grid instance: "
                         f"{GRID[1]}), v on a ring")
    ap.add_argument("--quick", action="store_true",
                    help=f'the small instance: robots "{QUICK[0]}", M {QUICK[1]} '
                         "(2184 states, 7032 transitions); with --ring, "
                         f'{RING_QUICK[0]}, robots "{RING_QUICK[1]}", m {RING_QUICK[2]} '
                         "(225 states, 560 transitions)")
    ap.add_argument("--ring", action="store_true",
                    help=f'the ring instance of gather-verify bench: {RING[0]}, robots '
                         f'"{RING[1]}", m {RING[2]} (572572 states, 2670668 transitions)')
    ap.add_argument("-w", "--hash-log2", type=int, default=None,
                    help="pan -w (log2 of hash slots); default: bit length of "
                         "the exact state count, so the load factor is < 1")
    ap.add_argument("-m", "--depth", type=int, default=None,
                    help="pan -m max search depth; default: longest "
                         "execution + 1000 (the run fails if pan truncates)")
    ap.add_argument("--memlim", type=int, default=None, metavar="MB",
                    help="compile with -DMEMLIM=MB (default: no limit)")
    ap.add_argument("--repeat", type=int, default=1, metavar="N",
                    help="run the whole pipeline N times (fresh directory each "
                         "time) and report the run with the median seconds")
    ap.add_argument("--keep", metavar="DIR",
                    help="work in DIR and keep model.pml, pan.c, pan.out")
    ap.add_argument("--out", metavar="FILE",
                    help="also write the JSON (indented) to FILE")
    args = ap.parse_args(argv)

    if args.ring or args.quick:
        if args.robots is not None or args.meeting is not None or args.world != "grid":
            ap.error("--quick and --ring take no --world/--robots/--meeting")
        args.world, robots, meeting = (
            (RING_QUICK if args.quick else RING) if args.ring
            else ("grid", *QUICK))
    elif args.world == "grid":
        robots = GRID[0] if args.robots is None else args.robots
        meeting = GRID[1] if args.meeting is None else args.meeting
    elif args.robots is None or args.meeting is None:
        ap.error(f"--world {args.world} needs --robots and --meeting")
    else:
        robots, meeting = args.robots, args.meeting
    try:
        if args.world == "grid":
            args.robots = make_model.parse_robots(robots)
            args.meeting = make_model.parse_point(meeting)
            expected_states, expected_edges = make_model.closed_form_counts(
                args.robots, args.meeting)
            longest = grid_longest_path(args.robots, args.meeting)
            robots, meeting = args.robots, args.meeting

            def model():
                return make_model.make_model(robots, meeting)
        else:
            n = make_ring_model.parse_world(args.world)
            args.robots = make_ring_model.parse_nodes(robots)
            args.meeting = int(meeting)
            expected_states, expected_edges = make_ring_model.closed_form_counts(
                n, args.robots, args.meeting)
            longest = make_ring_model.longest_path(n, args.robots, args.meeting)
            robots, meeting = args.robots, args.meeting

            def model():
                return make_ring_model.make_model(n, robots, meeting)
    except (argparse.ArgumentTypeError, ValueError) as exc:
        ap.error(str(exc))

    for tool in ("spin", "gcc"):
        if shutil.which(tool) is None:
            print(f"run_spin: '{tool}' not found on PATH "
                  f"(apt-get install -y spin gcc)", file=sys.stderr)
            return 2

    if args.depth is None:
        args.depth = longest + 1000
    if args.depth <= longest + 1:
        print(f"run_spin: -m{args.depth} is too small, the longest execution "
              f"has {longest} steps", file=sys.stderr)
        return 1
    if args.hash_log2 is None:
        args.hash_log2 = max(18, min(30, expected_states.bit_length()))

    runs = []
    try:
        for k in range(max(1, args.repeat)):
            t0 = T_PROCESS if k == 0 else time.perf_counter()
            if args.keep:
                os.makedirs(args.keep, exist_ok=True)
                runs.append(run_once(model, args.depth, args.hash_log2,
                                     args.memlim, args.keep, t0))
            else:
                with tempfile.TemporaryDirectory(prefix="spin-bench-") as tmp:
                    runs.append(run_once(model, args.depth, args.hash_log2,
                                         args.memlim, tmp, t0))
    except Failure as exc:
        print(f"run_spin: {exc}", file=sys.stderr)
        return 1

    median = statistics.median_low([r["seconds"] for r in runs])
    info = next(r for r in runs if r["seconds"] == median)
    edges = info["transitions"] - 1
    validated = (info["states"] == expected_states and edges == expected_edges)
    result = {
        "tool": "spin",
        "instance": {
            "algorithm": "go-to-target",
            "scheduler": "ASYNC",
            "reductions": "none",
            "robots": [list(p) for p in args.robots],
            "meeting": list(args.meeting),
        } if args.world == "grid" else {
            "world": args.world,
            "algorithm": "go-to-target",
            "scheduler": "ASYNC",
            "reductions": "none",
            "robots": args.robots,
            "meeting": args.meeting,
        },
        "states": info["states"],
        "transitions": info["transitions"],
        "edges": edges,
        "seconds": round(info["seconds"], 3),
        "search_seconds": round(info["search_seconds"], 3),
        "compile_seconds": round(info["compile_seconds"], 3),
        "states_per_second": round(info["states"] / info["seconds"], 1),
        "search_states_per_second": round(info["states"] / info["search_seconds"], 1),
        "memory_mb": info["memory_mb"],
        "state_memory_mb": info["state_memory_mb"],
        "hash_table_mb": info["hash_table_mb"],
        "bytes_per_state": round(info["state_memory_mb"] * 2**20 / info["states"], 1)
        if info["state_memory_mb"] is not None else None,
        "expected_states": expected_states,
        "expected_edges": expected_edges,
        "validated": validated,
        "pan_elapsed_seconds": info["pan_elapsed_seconds"],
        "matched": info["matched"],
        "atomic_steps": info["atomic_steps"],
        "state_vector_bytes": info["state_vector_bytes"],
        "depth_reached": info["depth_reached"],
        "longest_execution": longest,
        "hash_conflicts": info["hash_conflicts"],
        "errors": info["errors"],
        "gcc_flags": info["gcc_flags"],
        "pan_args": info["pan_args"],
        "runs": [{"seconds": round(r["seconds"], 3),
                  "search_seconds": round(r["search_seconds"], 3)} for r in runs],
        "machine": machine_info(),
    }
    print(json.dumps(result))
    if args.out:
        with open(args.out, "w", encoding="utf-8") as fh:
            json.dump(result, fh, indent=2)
            fh.write("\n")
    if not validated:
        print(f"run_spin: counts disagree with the closed form: states "
              f"{info['states']} vs {expected_states}, edges {edges} vs "
              f"{expected_edges}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
