"""The rendezvous table by the naive referee, beside the SPIN model's verdicts.

    python tests/rendezvous_table.py --spin bench/spin/light/results.json \\
        --out bench/spin/light/referee.json --markdown table.md

Per cell (algorithm, synchrony model, movement, initial colours): the referee's verdict
under §13 (fairness: every robot completes infinitely many cycles; goal: gathered), under
the SPIN model's own notions (bounded starvation; goal ``<>[] same``), its state and
transition counts and seconds, and the SPIN model's verdict from the harness's results
(``bench/spin/light/run_light.py``). Disagreements are listed at the end.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from rendezvous_referee import MODELS, check, starvation_needed  # noqa: E402

from gather_verify.worlds.rendezvous_rules import ALGORITHMS  # noqa: E402

MOVEMENTS = ("rigid", "non-rigid")
COLOURS = ("all", "same")


def cell(name: str, model: str, movement: str, colours: str) -> dict:
    alg = ALGORITHMS[name]
    t0 = time.perf_counter()
    ours = check(alg, model, movement, colours)
    t1 = time.perf_counter()
    spin_like = check(alg, model, movement, colours, fairness="bounded", goal="same")
    t2 = time.perf_counter()
    return {"verdict": ours.verdict, "states": ours.states, "transitions": ours.transitions,
            "seconds": round(t1 - t0, 4), "bounded_verdict": spin_like.verdict,
            "bounded_states": spin_like.states, "bounded_seconds": round(t2 - t1, 4),
            "starvation_needed": starvation_needed(alg, model, movement, colours),
            "spin_bound": (1 + alg.colours) * MODELS[model].spin_steps}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spin", help="the SPIN harness's results.json")
    ap.add_argument("--out", help="write the referee's cells here (JSON)")
    ap.add_argument("--markdown", help="write the side-by-side table here")
    args = ap.parse_args(argv)
    spin = {}
    if args.spin:
        spin = json.loads(Path(args.spin).read_text(encoding="utf-8"))["cells"]
    cells: dict[str, dict] = {}
    disagree = []
    lines = ["| algorithm | " + " | ".join(MODELS) + " |", "|---|" + "---|" * len(MODELS)]
    for name in ALGORITHMS:
        row = [name]
        for model in MODELS:
            marks, agree = "", True
            for movement in MOVEMENTS:
                for colours in COLOURS:
                    key = f"{name}|{model}|{movement}|{colours}"
                    c = cells[key] = cell(name, model, movement, colours)
                    theirs = spin.get(key, {}).get("verdict", "?")
                    c["spin_verdict"] = theirs
                    marks += _mark(c["verdict"])
                    if theirs in ("PASS", "FAIL") and theirs != c["verdict"]:
                        disagree.append(key)
                        agree = False
                    elif theirs not in ("PASS", "FAIL"):
                        agree = False
            row.append(marks + (" =" if agree else " ≠" if any(
                k.startswith(f"{name}|{model}|") for k in disagree) else " ?"))
        lines.append("| " + " | ".join(row) + " |")
    lines += ["", "Per cell: rigid (all colours, same colour), non-rigid (all, same); ✓ "
              "rendezvous, ✗ fails; = SPIN agrees on all four, ≠ it disagrees on one, ? "
              "not all four compared.",
              f"Disagreements: {', '.join(disagree) or 'none'}."]
    compared = sum(1 for c in cells.values() if c["spin_verdict"] in ("PASS", "FAIL"))
    needed = [(c["starvation_needed"] / c["spin_bound"], c["starvation_needed"], key)
              for key, c in cells.items() if c["starvation_needed"]]
    ratio, most, where = max(needed)
    lines.append(f"Cells compared with SPIN: {compared} of {len(cells)}. In every cell a "
                 f"counterexample needs at most {ratio:.0%} of the consecutive steps of one "
                 f"robot that the SPIN model allows (the most: "
                 f"{max(n for _, n, _ in needed)} steps; the tightest cell: {where}, "
                 f"{most} step(s)).")
    text = "\n".join(lines) + "\n"
    if args.markdown:
        Path(args.markdown).write_text(text, encoding="utf-8")
    print(text)
    if args.out:
        Path(args.out).write_text(json.dumps({"cells": cells, "disagreements": disagree},
                                             indent=1) + "\n", encoding="utf-8")
    return 0


def _mark(verdict: str) -> str:
    return {"PASS": "✓", "FAIL": "✗"}.get(verdict, "?")


if __name__ == "__main__":
    sys.exit(main())
