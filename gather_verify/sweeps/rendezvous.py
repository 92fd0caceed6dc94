"""The rendezvous table: every algorithm under every synchrony model, rigid and non-rigid,
any and same initial colours (SEMANTICS.md §13), by the one check
(:func:`~gather_verify.rendezvous_check.run_rendezvous_check`), with the SPIN model's stored
verdicts beside ours and a trace for every failure (``gather-verify sweep --world
rendezvous``).

A cell takes milliseconds (the largest has 17,375 states), so the table keeps no database:
it is rebuilt whole, and each failure's trace is written where asked.

>>> t = table(["vig-2cols"], ["ssync", "async"], ["rigid"], ["same"])
>>> [(c["scheduler"], c["verdict"]) for c in t["cells"]]
[('ssync', 'VERIFIED'), ('async', 'VIOLATED')]
"""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from itertools import product
from pathlib import Path
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.rendezvous_check import run_rendezvous_check
from gather_verify.worlds.rendezvous_rules import ALGORITHMS, INITIAL_COLOURS, MOVEMENTS
from schedulers.phases import MODELS

SPIN_VERDICT = {"PASS": "VERIFIED", "FAIL": "VIOLATED"}
"""The SPIN harness's verdicts in ours (an acceptance cycle is a fair run that never gathers)."""


def names(text: str | None, known: Sequence[str], what: str) -> list[str]:
    """A comma-separated list of ``known`` names, or all of them (None or ``all``)."""
    if text is None or text == "all":
        return list(known)
    out = [part.strip() for part in text.split(",")]
    unknown = [n for n in out if n not in known]
    if unknown:
        raise InvalidInput(f"unknown {what} {unknown[0]!r} on the rendezvous world: use all, "
                           f"or some of {', '.join(known)}")
    return out


def load_spin(path: str | Path) -> dict[str, dict[str, Any]]:
    """The SPIN harness's cells (``bench/spin/light/results.json``), by
    ``algorithm|model|movement|colours``; one line when the file is not such a file."""
    from gather_verify.inputs import read_text  # read once, regular files only

    try:
        cells = json.loads(read_text(path, "--spin results"))["cells"]
        assert isinstance(cells, dict) and all(isinstance(c, dict) for c in cells.values())
        return cells
    except InvalidInput:
        raise
    except (ValueError, KeyError, TypeError, AssertionError, RecursionError):
        raise InvalidInput(f"--spin {path}: not the SPIN harness's results (a JSON object with "
                           "'cells', as bench/spin/light/run_light.py writes)") from None


def table(algorithms: Sequence[str], models: Sequence[str], movements: Sequence[str] = MOVEMENTS,
          colours: Sequence[str] = INITIAL_COLOURS, *, spin: dict[str, dict[str, Any]] | None = None,
          traces: Path | None = None, max_states: int = 2_000_000,
          max_seconds: float = 600.0) -> dict[str, Any]:
    """Every cell's verdict, counts and seconds; beside it the SPIN model's verdict and
    seconds (compile included and not) when ``spin`` holds the cell; a failure's trace
    written under ``traces`` (its file name in ``trace``)."""
    cells, disagree = [], []
    for name, model, movement, initial in product(algorithms, models, movements, colours):
        started = time.perf_counter()
        r = run_rendezvous_check(name, model, movement=movement, initial_colours=initial,
                                 max_states=max_states, max_seconds=max_seconds)
        cell: dict[str, Any] = {
            "algorithm": name, "scheduler": model, "movement": movement,
            "initial_colours": initial, "verdict": r["verdict"], "states": r["states"],
            "transitions": r["transitions"], "seconds": time.perf_counter() - started}
        theirs = (spin or {}).get(f"{name}|{model}|{movement}|{initial}")
        if theirs is not None:
            cell["spin"] = SPIN_VERDICT.get(str(theirs.get("verdict")), "INCOMPLETE")
            cell["spin_seconds"] = theirs.get("seconds")
            cell["spin_search_seconds"] = theirs.get("search_seconds")
            if cell["spin"] != "INCOMPLETE" and cell["spin"] != cell["verdict"]:
                disagree.append(cell)
        if r["trace"] is not None and traces is not None:
            traces.mkdir(parents=True, exist_ok=True)
            cell["trace"] = f"{name}-{model}-{movement}-{initial}.json"
            (traces / cell["trace"]).write_text(json.dumps(r["trace"], indent=1) + "\n",
                                                encoding="utf-8")
        cells.append(cell)
    return {"cells": cells, "disagreements": disagree,
            "compared": sum(1 for c in cells if c.get("spin") in SPIN_VERDICT.values())}


MARK = {"VERIFIED": "✓", "VIOLATED": "✗"}


def markdown(result: dict[str, Any]) -> str:
    """The table as Markdown: a row per algorithm, a column per model; per cell one mark per
    (movement, initial colours) in that order (✓ rendezvous, ✗ fails, ? incomplete), then
    ``=`` when SPIN agrees on all of them, ``≠`` when it disagrees on one."""
    cells = result["cells"]
    algorithms = list(dict.fromkeys(c["algorithm"] for c in cells))
    models = list(dict.fromkeys(c["scheduler"] for c in cells))
    lines = ["| algorithm | " + " | ".join(models) + " |", "|---|" + "---|" * len(models)]
    for name in algorithms:
        row = [name]
        for model in models:
            mine = [c for c in cells if c["algorithm"] == name and c["scheduler"] == model]
            marks = "".join(MARK.get(c["verdict"], "?") for c in mine)
            spin = [c.get("spin") for c in mine]
            if all(s in MARK for s in spin):
                marks += " =" if all(c["spin"] == c["verdict"] for c in mine) else " ≠"
            row.append(marks)
        lines.append("| " + " | ".join(row) + " |")
    order = ", ".join(dict.fromkeys(f"{c['movement']}/{c['initial_colours']}" for c in cells))
    lines += ["", f"Marks per cell: {order}. ✓ rendezvous, ✗ a fair run never gathers, "
              "? incomplete; = the SPIN model agrees on every mark, ≠ it disagrees on one.",
              f"Cells compared with SPIN: {result['compared']} of {len(cells)}; "
              f"disagreements: {len(result['disagreements'])}."]
    return "\n".join(lines) + "\n"


def check_known(algorithms: str | None, models: str | None) -> tuple[list[str], list[str]]:
    """The algorithms and models a rendezvous sweep names (all by default)."""
    return names(algorithms, list(ALGORITHMS), "algorithm"), names(models, list(MODELS),
                                                                   "synchrony model")
