"""The tables of ``synthesize --minimum``: the least number of robots, or of colours, for
which an algorithm exists, per world and scheduler, read from its answers (SEMANTICS.md §12).

One cell rule serves the command as it runs and ``report`` reading the results store: a
cell is the least value whose answer is ``exists``; ``>B`` when every value up to B is
``none``; and a ``?`` when a smaller value was ``unknown`` (or, in a store, was never asked),
since the least value may then be smaller.

>>> least_cell([(1, "none"), (2, "exists")]), least_cell([(1, "unknown"), (2, "exists")])
('2', '2?')
>>> least_cell([(1, "none"), (2, "none")]), least_cell([(1, "none"), (3, "none")])
('>2', '>3?')
"""

from __future__ import annotations

from typing import Any

COMMAND = "synthesize --minimum"
"""The ``command`` setting of the sweeps that ``synthesize --minimum`` stores."""
RESOURCES = ("robots", "colours")


def resource(settings: dict[str, Any]) -> str:
    """What a stored ``--minimum`` sweep counts: ``robots`` (also a store written before
    colours were counted, whose settings do not say) or ``colours``."""
    return str(settings.get("minimum") or "robots")


def least_cell(answers: list[tuple[int, str]]) -> str:
    """The cell of one world and scheduler from its answers ``(value, answer)`` in the order
    asked (increasing values): the least value that ``exists``, ``>B`` when none up to the
    last, B, does; ``?`` when an earlier value is ``unknown`` or missing (a gap). ``empty``
    (no configuration selected, on the paper's world) counts as asked, with no algorithm."""
    below = False
    previous = None
    for value, answer in sorted(answers):
        if previous is not None and value != previous + 1:
            below = True  # a value never asked
        previous = value
        if answer == "exists":
            return f"{value}" + ("?" if below else "")
        if answer == "unknown":
            below = True
    if previous is None:
        return "-"
    return f">{previous}" + ("?" if below else "")


def format_table(worlds: list[str], schedulers: list[str], cells: dict[tuple[str, str], str]
                 ) -> list[str]:
    """The table as text lines: a row per world, a column per scheduler (``-``: not asked).

    >>> print("\\n".join(format_table(["ring:5"], ["fsync"], {("ring:5", "fsync"): "2"})))
                  fsync
    ring:5            2
    """
    width = max(len(w) for w in worlds)
    lines = [" " * width + "  " + "  ".join(f"{sc:>11}" for sc in schedulers)]
    for w in worlds:
        lines.append(f"{w:<{width}}  "
                     + "  ".join(f"{cells.get((w, sc), '-'):>11}" for sc in schedulers))
    return lines


def stored_tables(sweeps: list[tuple[dict[str, Any], list[dict[str, Any]]]]
                  ) -> list[dict[str, Any]]:
    """The ``--minimum`` sweeps of a store, as tables: one per group of sweeps whose settings
    differ only in the world and the scheduler, in the order of their first sweep. Each has
    its ``settings`` (those in common), what it counts (``resource``), the ``worlds`` and
    ``schedulers``, each cell (:func:`least_cell` over the stored answers), the values
    stored (``low``, ``high``) and every stored answer (``rows``)."""
    import json

    groups: dict[str, dict[str, Any]] = {}
    for settings, rows in sweeps:
        if settings.get("command") != COMMAND:
            continue
        common = {k: v for k, v in settings.items() if k not in ("world", "scheduler")}
        key = json.dumps(common, sort_keys=True, default=str)
        group = groups.setdefault(key, {"settings": common, "resource": resource(settings),
                                        "worlds": [], "schedulers": [], "cells": {},
                                        "rows": []})
        world, sched = str(settings.get("world")), str(settings.get("scheduler"))
        for name, seen in ((world, group["worlds"]), (sched, group["schedulers"])):
            if name not in seen:
                seen.append(name)
        answers = [(int(r["index"]), str(r["verdict"])) for r in rows]
        group["cells"][world, sched] = least_cell(answers)
        for r in rows:
            group["rows"].append({"world": world, "scheduler": sched,
                                  group["resource"]: int(r["index"]), "answer": r["verdict"],
                                  "limit": r["reason"], "files": r["trace"]})
    out = []
    for group in groups.values():
        values = [r[group["resource"]] for r in group["rows"]]
        group["low"], group["high"] = (min(values), max(values)) if values else (None, None)
        out.append(group)
    return out
