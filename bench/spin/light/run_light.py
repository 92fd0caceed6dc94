#!/usr/bin/env python3
"""Run the public SPIN model of two robots with lights (``xdefago/spin-light``) on every
cell it supports, and record its verdicts and times as data.

    python3 bench/spin/light/run_light.py PATH/TO/spin-light --out bench/spin/light/results.json
    python3 bench/spin/light/run_light.py PATH --algorithms vig-2cols --schedulers ssync async

PATH is a checkout of that repository (its ``src/promela/*.pml``); this repository holds
none of it. A cell is (algorithm, scheduler, movement, initial colours); per cell the
harness copies the model's files into a fresh directory and runs, as the model's own
``src/python/verify.py`` does (gcc in place of clang, one core):

    spin -a -DALGO=A -DSCHEDULER=S -DMOVEMENT=M [-DQUASISS] MainGathering.pml
    gcc -DMEMLIM=4096 -DXUSAFE -DNOREDUCE -O2 -w -o pan pan.c
    ./pan -m100000 -a -f -E -n gathering

and, when pan writes a trail, ``spin -t`` for the counterexample (its STEP and CONF lines
and the start of the cycle are kept). Verdict: ``FAIL`` (a trail: an acceptance cycle, a
fair execution that never stays at SAME), ``PASS`` (no error, search complete), or
``INCOMPLETE`` (pan stopped early: depth, memory, or the harness's timeout).

The model names ALGO_REGULAR4/5/6 without giving them numbers, so ``-DALGO=ALGO_REGULAR4``
selects the first of them in the file, ALGO_REGULAR6 (the C preprocessor reads an unknown
name as 0). The harness defines the three numbers on the command line (``-DALGO_REGULAR4=
104`` ...), so each name checks its own algorithm; ``algorithm_name`` in each cell is what
the model printed, the proof of which one ran. Results are written after every cell, and
cells already in ``--out`` are skipped (a long run may be resumed). Standard library only.
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
sys.path.insert(0, os.path.dirname(HERE))
sys.dont_write_bytecode = True  # leave no __pycache__ in the repository
from run_spin import machine_info, parse_pan  # noqa: E402

ALGORITHMS = ("ALGO_NO_MOVE", "ALGO_TO_HALF", "ALGO_TO_OTHER", "ALGO_VIG_2COLS",
              "ALGO_VIG_3COLS", "ALGO_OPTIMAL", "ALGO_FLO_ALGO3EXT", "ALGO_FLO_ALGO3EXT_PRIME",
              "ALGO_3EXT_NONQSS", "ALGO_WADA_4EXT", "ALGO_WADA_5EXT", "ALGO_TIXEUIL_EXTRA",
              "ALGO_REGULAR4", "ALGO_REGULAR5", "ALGO_REGULAR6")
"""Every algorithm of the model's Algorithms.pml, in its order."""
SCHEDULERS = ("CENTRALIZED", "FSYNC", "SSYNC", "ASYNC", "ASYNC_REGULAR", "ASYNC_SAFE",
              "ASYNC_LC_ATOMIC", "ASYNC_LC_STRICT", "ASYNC_CM_ATOMIC", "ASYNC_MOVE_ATOMIC",
              "ASYNC_MOVE_REGULAR", "ASYNC_MOVE_SAFE")
"""Every synchrony model of the model's Schedulers.pml."""
MOVEMENTS = ("RIGID", "NON_RIGID")
COLOURS = ("all", "same")
NUMBERS = ("-DALGO_REGULAR4=104", "-DALGO_REGULAR5=105", "-DALGO_REGULAR6=106")
GCC = ["gcc", "-DMEMLIM=4096", "-DXUSAFE", "-DNOREDUCE", "-O2", "-w", "-o", "pan", "pan.c"]
PAN = ["./pan", "-m100000", "-a", "-f", "-E", "-n", "gathering"]
HEAD, CYCLE = 20, 40


def name(symbol: str) -> str:
    """A model's symbol as the project writes it: ALGO_VIG_2COLS -> vig-2cols."""
    return symbol.removeprefix("ALGO_").lower().replace("_", "-")


def cell_key(algo: str, sched: str, movement: str, colours: str) -> str:
    return f"{name(algo)}|{name(sched)}|{name(movement)}|{colours}"


def defines(algo: str, sched: str, movement: str, colours: str) -> list[str]:
    quasi = ["-DQUASISS"] if colours == "same" else []
    return [f"-DALGO={algo}", f"-DSCHEDULER={sched}", f"-DMOVEMENT={movement}",
            *NUMBERS, *quasi]


def compact_trace(text: str) -> list[str]:
    """The counterexample in short: each step with the configuration after it on one line
    (the model's README greps STEP and CONF), white space collapsed; its first ``HEAD``
    steps, then, from the line that marks the start of the acceptance cycle, at most
    ``CYCLE`` steps (``...`` where steps are left out). ``spin -t`` with the same
    definitions replays the whole trail."""
    steps: list[str] = []
    for line in text.splitlines():
        line = " ".join(line.replace("Never claim moves to line 3", "").split())
        if line.startswith("CONF") and steps and steps[-1].startswith("STEP"):
            steps[-1] += " -> " + line.removeprefix("CONF: ")
        elif "<<<" in line or line.startswith("STEP"):
            steps.append(line.split("[(")[0].strip())
    cycle = next((i for i, line in enumerate(steps) if "<<<" in line), None)
    if cycle is None:
        return steps[:HEAD] + (["..."] if len(steps) > HEAD else [])
    head = steps[:min(HEAD, cycle)] + (["..."] if cycle > HEAD else [])
    rest = steps[cycle:cycle + CYCLE + 1]
    return head + rest + (["..."] if len(steps) > cycle + CYCLE + 1 else [])


def run_cell(promela: str, algo: str, sched: str, movement: str, colours: str,
             timeout: float) -> dict:
    """One cell in a fresh directory: spin -a, gcc, pan (and spin -t on a trail)."""
    flags = defines(algo, sched, movement, colours)
    with tempfile.TemporaryDirectory(prefix="spin-light-") as work:
        for f in os.listdir(promela):
            if f.endswith(".pml"):
                shutil.copy(os.path.join(promela, f), work)
        t0 = time.perf_counter()
        spin = subprocess.run(["spin", "-a", *flags, "MainGathering.pml"], cwd=work,
                              capture_output=True, text=True)
        t1 = time.perf_counter()
        if spin.returncode != 0:
            return {"verdict": "ERROR", "reason": spin.stdout[-2000:] + spin.stderr[-2000:]}
        gcc = subprocess.run(GCC, cwd=work, capture_output=True, text=True)
        t2 = time.perf_counter()
        if gcc.returncode != 0:
            return {"verdict": "ERROR", "reason": gcc.stderr[-2000:]}
        try:
            pan = subprocess.run(PAN, cwd=work, capture_output=True, text=True,
                                 timeout=timeout)
            out = pan.stdout + pan.stderr
        except subprocess.TimeoutExpired:
            return {"verdict": "INCOMPLETE", "reason": f"timeout after {timeout:g} s",
                    "spin_seconds": round(t1 - t0, 3), "compile_seconds": round(t2 - t1, 3)}
        t3 = time.perf_counter()
        cell = {"spin_seconds": round(t1 - t0, 3), "compile_seconds": round(t2 - t1, 3),
                "search_seconds": round(t3 - t2, 3), "seconds": round(t3 - t0, 3),
                **parse_pan(out)}
        trail = os.path.join(work, "MainGathering.pml.trail")
        if os.path.exists(trail):
            replay = subprocess.run(["spin", "-t", *flags, "MainGathering.pml"], cwd=work,
                                    capture_output=True, text=True)
            cell["verdict"] = "FAIL"
            cell["reason"] = _first(r"pan:\d+: (.*)", out) or "error"
            cell["trace"] = compact_trace(replay.stdout)
        elif "Search not completed" in out or "max search depth too small" in out \
                or "out of memory" in out.lower() or pan.returncode != 0:
            cell["verdict"] = "INCOMPLETE"
            cell["reason"] = out[-1500:]
        else:
            cell["verdict"] = "PASS"
        sim = subprocess.run(["spin", "-u50", *flags, "MainGathering.pml"], cwd=work,
                             capture_output=True, text=True)
        cell["algorithm_name"] = _first(r"ALGORITHM:\s*(\w+)", sim.stdout)
        cell["scheduler_name"] = _first(r"SCHEDULER:\s*([A-Za-z_()]+)", sim.stdout)
        return cell


def _first(pattern: str, text: str) -> str | None:
    m = re.search(pattern, text)
    return m.group(1).strip() if m else None


def checkout_commit(path: str) -> str | None:
    try:
        out = subprocess.run(["git", "-C", path, "rev-parse", "HEAD"], capture_output=True,
                             text=True)
        return out.stdout.strip() or None
    except OSError:
        return None


def pick(given: list[str] | None, known: tuple[str, ...]) -> list[str]:
    """The model's symbols named by ``given`` (project names or symbols); all when None."""
    if not given:
        return list(known)
    by = {name(k): k for k in known} | {k: k for k in known}
    unknown = [g for g in given if g not in by]
    if unknown:
        raise SystemExit(f"unknown: {' '.join(unknown)} (known: {' '.join(map(name, known))})")
    return [by[g] for g in given]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("checkout", help="a checkout of xdefago/spin-light")
    ap.add_argument("--out", help="results JSON (read first: its cells are skipped)")
    ap.add_argument("--algorithms", nargs="*")
    ap.add_argument("--schedulers", nargs="*")
    ap.add_argument("--movements", nargs="*", choices=("rigid", "non-rigid"))
    ap.add_argument("--initial-colours", nargs="*", choices=COLOURS)
    ap.add_argument("--timeout", type=float, default=1800.0, help="pan's seconds per cell")
    ap.add_argument("--redo", action="store_true", help="run cells already in --out again")
    args = ap.parse_args(argv)
    promela = os.path.join(args.checkout, "src", "promela")
    if not os.path.exists(os.path.join(promela, "MainGathering.pml")):
        print(f"{args.checkout}: no src/promela/MainGathering.pml", file=sys.stderr)
        return 2
    if shutil.which("spin") is None or shutil.which("gcc") is None:
        print("spin and gcc are needed (apt-get install spin gcc)", file=sys.stderr)
        return 2
    data = {"tool": "spin-light", "commit": checkout_commit(args.checkout),
            "commands": {"spin": "spin -a -DALGO=A -DSCHEDULER=S -DMOVEMENT=M [-DQUASISS] "
                                 + " ".join(NUMBERS) + " MainGathering.pml",
                         "gcc": " ".join(GCC), "pan": " ".join(PAN)},
            "machine": machine_info(), "cells": {}}
    if args.out and os.path.exists(args.out):
        with open(args.out, encoding="utf-8") as fh:
            data["cells"] = json.load(fh).get("cells", {})
    movements = pick([m.upper().replace("-", "_") for m in args.movements or []], MOVEMENTS)
    for algo in pick(args.algorithms, ALGORITHMS):
        for sched in pick(args.schedulers, SCHEDULERS):
            for movement in movements:
                for colours in args.initial_colours or COLOURS:
                    key = cell_key(algo, sched, movement, colours)
                    if key in data["cells"] and not args.redo:
                        continue
                    cell = run_cell(promela, algo, sched, movement, colours, args.timeout)
                    data["cells"][key] = cell
                    print(f"{key:55} {cell['verdict']:10} {cell.get('states')} states "
                          f"{cell.get('seconds')} s", flush=True)
                    if args.out:
                        _write(args.out, data)
    if not args.out:
        json.dump(data, sys.stdout, indent=1)
    return 0


def _write(path: str, data: dict) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1, sort_keys=False)
        fh.write("\n")
    os.replace(tmp, path)


if __name__ == "__main__":
    sys.exit(main())
