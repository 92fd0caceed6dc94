"""Regression scenarios from sweeps: one file per distinct counterexample.

A sweep can find hundreds of violations that are the same fault seen from
different starting points. Two violations are *the same counterexample kind*
when they share the sweep's algorithm and scheduler, the initial class, the
failing property and the reason once node coordinates are blanked out
("the target meeting node changes from [2, 1] to [1, 0]" and "... from [0, 1]
to [1, 0]" are one kind). For each kind the smallest witness (fewest robots,
then fewest states, then the sweep's order) becomes a scenario file under
``scenarios/regressions/`` with its trace, its class and its verdict as
expectations, so the scenario suite fails if it stops reproducing and
``gather-verify replay FILE`` re-checks it without the explorer.

>>> reason_kind("the target meeting node changes from [2, 1] to [1, 0]")
'the target meeting node changes from [*] to [*]'
"""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path
from typing import Any

from gather_verify.sweeps.report import load_sweeps

_POINT = re.compile(r"[\[(]-?\d+, ?-?\d+[\])]")
_NUMBER = re.compile(r"-?\d+(\.\d+)?")


def reason_kind(reason: str | None) -> str:
    """The reason with coordinates and numbers blanked: what identifies a kind of fault."""
    text = _POINT.sub("[*]", reason or "")
    return _NUMBER.sub("#", text)


def distinct_counterexamples(db_path: str, algorithm: str | None = None
                             ) -> list[tuple[dict[str, Any], dict[str, Any]]]:
    """``(settings, row)`` for the smallest witness of every counterexample kind in a store
    (of the sweeps of ``algorithm``, when given)."""
    best: dict[tuple, tuple[tuple, dict[str, Any], dict[str, Any]]] = {}
    for settings, rows in load_sweeps(db_path, algorithm):
        for row in rows:
            if row["verdict"] != "VIOLATED" or not row.get("trace"):
                continue
            kind = (settings["algorithm"], settings["scheduler"], row["class"], row["property"],
                    reason_kind(row["reason"]))
            rank = (row["n"], row["states"] or 0, row["key"])
            if kind not in best or rank < best[kind][0]:
                best[kind] = (rank, settings, row)
    return [(settings, row) for _, (_, settings, row) in sorted(best.items())]


def scenario_for(settings: dict[str, Any], row: dict[str, Any],
                 folder: str | Path = "scenarios/regressions") -> dict[str, Any]:
    """The regression scenario of one witness, to be written into ``folder`` (deterministic:
    same row and folder, same text). An algorithm file is named relative to ``folder``."""
    from gather_verify.algorithms.loading import relative_spec

    algorithm, scheduler = settings["algorithm"], settings["scheduler"]
    here = relative_spec(algorithm, folder)
    digest = hashlib.sha256(json.dumps([algorithm, scheduler, row["key"]]).encode()).hexdigest()
    slug = re.sub(r"[^a-z0-9]+", "-", f"{row['class']}-{row['property']}-{algorithm}-{scheduler}".lower())
    name = f"{slug.strip('-')}-{digest[:8]}"
    world = settings.get("world", "grid")
    where = f"--world {world}" if "box" not in settings else \
        "--box {}x{}".format(*settings["box"])
    found_by = (f"gather-verify sweep {where} --robots {settings['robots']} --meeting "
                f"{settings['meeting']} --algorithm {algorithm} --scheduler {scheduler}")
    lit: dict[str, Any] = {}
    robots = row["robots"]
    if settings.get("lights") is not None:  # a luminous sweep: its lights, the row's colours
        every = settings.get("initial_colours") == "all"
        found_by += f" --lights {settings['lights']}" + (" --initial-colours all" if every else "")
        colours = [r[1] for r in robots] if every else [0] * len(robots)
        robots = [r[0] for r in robots] if every else robots
        lit = {"lights": settings["lights"], "colours": colours}
    expect: dict[str, Any] = {"class": row["class"]}
    if "box" not in settings:  # a finite world's: its world and task (no class of the paper's)
        lit = {"world": world, "task": settings.get("task"),
               **({} if settings.get("visibility") is None else
                  {"visibility": settings["visibility"]}), **lit}
        expect = {}
    return {
        "name": name,
        "description": (f"Counterexample found by a sweep ({found_by}): {row['class']}, "
                        f"{row['property']} fails - {row['reason']}. "
                        f"Replay: gather-verify replay {Path(folder).as_posix()}/{name}"
                        f"{SUFFIX}"),
        "robots": robots,
        "meeting_nodes": row["meeting_nodes"],
        **lit,
        "algorithm": here,
        "scheduler": scheduler,
        "multiplicity": settings.get("detection", "local-weak"),
        "frames": settings.get("frames", "all"),
        "expect": {**expect, "verdicts": [
            {"algorithm": here, "scheduler": scheduler, "verdict": "VIOLATED",
             "property": row["property"]}]},
        "trace": row["trace"] if here == algorithm else {**row["trace"], "algorithm": here},
    }


SUFFIX = ".scenario.json"
"""What a regression file is called: the pytest plugin collects ``*.scenario.json``."""


def write_regressions(db_path: str, folder: str | Path,
                      algorithm: str | None = None) -> list[Path]:
    """Write one scenario per counterexample kind into ``folder`` (of the sweeps of
    ``algorithm``, when given); the paths written.

    A file whose name exists already is left alone (its name fixes its witness)."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for settings, row in distinct_counterexamples(db_path, algorithm):
        scenario = scenario_for(settings, row, folder)
        path = out / f"{scenario['name']}{SUFFIX}"
        if not path.exists():
            path.write_text(json.dumps(scenario, indent=1, sort_keys=False) + "\n", encoding="utf-8")
            written.append(path)
    return written
