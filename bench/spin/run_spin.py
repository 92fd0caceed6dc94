#!/usr/bin/env python3
"""Run the SPIN yardstick: generate the Promela model, `spin -a`, gcc, `./pan`.

Prints one JSON object on stdout:
  states, transitions         -- as reported by pan (transitions = stored+matched)
  seconds, states_per_second  -- pan's own search time (wall clock of ./pan)
  memory_mb                   -- pan's "total actual memory usage"
  spin_version                -- first line of `spin -V`
  compile_seconds             -- spin -a + gcc
  total_seconds, states_per_second_total -- generation + spin -a + gcc + pan
plus a few informative extras (pan_elapsed_seconds, state_vector_bytes,
depth_reached, errors, hash_size_log2, gcc_flags, pan_args).

Exit status: 0 on success, 2 if spin or gcc is missing, 1 on any other failure
(one line on stderr in both error cases). Standard library only.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_model  # noqa: E402

GCC_FLAGS = ["-O2", "-DNOREDUCE", "-DSAFETY"]


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
        "pan_elapsed_seconds": _num(r"pan: elapsed time ([\d.e+-]+) seconds", out, float),
        "state_vector_bytes": _num(r"State-vector (\d+) byte", out),
        "depth_reached": _num(r"depth reached (\d+)", out),
        "errors": _num(r"errors: (\d+)", out),
    }


def run(cmd: list[str], cwd: str) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", required=True, type=make_model.parse_robots,
                    help='robot nodes, e.g. "0,0 5,1 1,5 6,6 3,0"')
    ap.add_argument("--meeting", required=True, type=make_model.parse_point,
                    help="meeting node, e.g. 3,3")
    ap.add_argument("-w", "--hash-log2", type=int, default=None,
                    help="pan -w (log2 hash slots); default: sized from "
                         "the product bound of the state space")
    ap.add_argument("-m", "--depth", type=int, default=100000,
                    help="pan -m max search depth (default 100000)")
    ap.add_argument("--keep", metavar="DIR",
                    help="work in DIR and keep model.pml, pan.c, pan output")
    args = ap.parse_args(argv)

    for tool in ("spin", "gcc"):
        if shutil.which(tool) is None:
            print(f"run_spin: '{tool}' not found on PATH "
                  f"(apt-get install -y spin gcc)", file=sys.stderr)
            return 2

    t_start = time.perf_counter()
    ver = run(["spin", "-V"], cwd=".").stdout.strip().splitlines()
    spin_version = ver[0] if ver else "unknown"

    if args.hash_log2 is None:
        # Robots do not interact, so the reachable state count is the product
        # of per-robot counts: every node of the robot's box towards M, once
        # idle plus once per strictly-closer neighbour (M itself: idle only).
        # 2**w > count keeps the hash load factor below 1.
        bound = 1
        for (x, y) in args.robots:
            dx, dy = abs(x - args.meeting[0]), abs(y - args.meeting[1])
            per = sum(1 + (i > 0) + (j > 0)
                      for i in range(dx + 1) for j in range(dy + 1))
            bound *= per
        args.hash_log2 = max(18, min(30, bound.bit_length()))

    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
        workdir, tmp = args.keep, None
    else:
        tmp = tempfile.TemporaryDirectory(prefix="spin-bench-")
        workdir = tmp.name
    try:
        pml = os.path.join(workdir, "model.pml")
        with open(pml, "w", encoding="ascii") as fh:
            fh.write(make_model.make_model(args.robots, args.meeting))

        t_c0 = time.perf_counter()
        r = run(["spin", "-a", "model.pml"], workdir)
        if r.returncode != 0:
            print(f"run_spin: spin -a failed: {(r.stderr or r.stdout).strip()}",
                  file=sys.stderr)
            return 1
        r = run(["gcc", *GCC_FLAGS, "-o", "pan", "pan.c"], workdir)
        if r.returncode != 0:
            print(f"run_spin: gcc failed: {r.stderr.strip().splitlines()[:1]}",
                  file=sys.stderr)
            return 1
        compile_seconds = time.perf_counter() - t_c0

        pan_args = ["-E", f"-m{args.depth}", f"-w{args.hash_log2}"]
        t_p0 = time.perf_counter()
        r = run(["./pan", *pan_args], workdir)
        pan_seconds = time.perf_counter() - t_p0
        total_seconds = time.perf_counter() - t_start
        with open(os.path.join(workdir, "pan.out"), "w") as fh:
            fh.write(r.stdout + r.stderr)
        info = parse_pan(r.stdout)
        if r.returncode != 0 or info["states"] is None:
            print(f"run_spin: pan failed (rc={r.returncode}): "
                  f"{(r.stdout + r.stderr).strip().splitlines()[:1]}",
                  file=sys.stderr)
            return 1
        if "max search depth too small" in r.stdout:
            print("run_spin: max search depth too small, raise -m", file=sys.stderr)
            return 1
    finally:
        if tmp is not None:
            tmp.cleanup()

    result = {
        "states": info["states"],
        "transitions": info["transitions"],
        "seconds": round(pan_seconds, 3),
        "states_per_second": round(info["states"] / pan_seconds, 1),
        "memory_mb": info["memory_mb"],
        "spin_version": spin_version,
        "compile_seconds": round(compile_seconds, 3),
        "total_seconds": round(total_seconds, 3),
        "states_per_second_total": round(info["states"] / total_seconds, 1),
        "pan_elapsed_seconds": info["pan_elapsed_seconds"],
        "matched": info["matched"],
        "state_vector_bytes": info["state_vector_bytes"],
        "depth_reached": info["depth_reached"],
        "errors": info["errors"],
        "hash_size_log2": args.hash_log2,
        "gcc_flags": " ".join(GCC_FLAGS),
        "pan_args": " ".join(pan_args),
    }
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
