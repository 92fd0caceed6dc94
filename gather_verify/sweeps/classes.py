"""A sweep's task of one meeting-node class (``sweep --engine union``), for every world.

A world's union engine decides what one state graph of the class settles
(:class:`ClassDecision`: rows, and the members left to their own checks, each with why);
:func:`verify_class` runs those checks, or hands them back to the other workers once the
task has run ``hand_off`` seconds. The paper's world decides in
:func:`gather_verify.sweeps.mclass.decide_class`, a finite world in
:func:`gather_verify.sweeps.world_union.decide_world_class`; the sweep reaches both
through its world's face (:class:`gather_verify.sweeps.sweep.SweepFace`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

Row = dict[str, Any]
Item = tuple[int, Any]
"""A configuration of a sweep with its index in the enumeration."""


@dataclass
class ClassDecision:
    """Rows decided from the union graph, and the members left to the per-configuration check."""

    rows: list[Row]
    fallback: list[Item]
    union_states: int = 0
    reasons: dict[int, str] = field(default_factory=dict)
    """Per member of ``fallback`` (by index): why the union left it to its own check."""

    def fall_back(self, items: Sequence[Item], why: str) -> ClassDecision:
        """``items`` added to ``fallback``, each with the reason ``why``; ``self``."""
        self.fallback.extend(items)
        self.reasons.update((index, why) for index, _ in items)
        return self


def verify_class(settings: Any, members: Sequence[Item],
                 decide: Callable[[Any, Sequence[Item]], ClassDecision],
                 verify_one: Callable[[Any, int, Any], Row],
                 hand_off: float | None = None, fallbacks: dict[str, int] | None = None,
                 ) -> tuple[list[Row], list[Item]]:
    """The rows of ``members`` (one class, as the world's ``class_tasks`` makes them), in
    index order: those ``decide`` settles from one union graph, the others from
    ``verify_one`` (a configuration on its own, the sweep's). With ``hand_off`` (seconds),
    the per-configuration checks left once the task has run that long are not run here but
    returned, for other workers (a few runs that walk away from ``M`` would otherwise make
    one class the whole sweep's floor); without it the second list is empty. ``fallbacks``:
    counts, by reason (:attr:`ClassDecision.reasons`), of the members the union left to
    their own checks, added to (those checked here and those handed off)."""
    started = time.perf_counter()
    decided = decide(settings, members)
    rows, rest = decided.rows, decided.fallback
    done = 0
    while done < len(rest) and (hand_off is None or time.perf_counter() - started < hand_off):
        rows.append(verify_one(settings, *rest[done]))
        done += 1
    if fallbacks is not None:
        for index, _ in rest:
            why = decided.reasons[index]
            fallbacks[why] = fallbacks.get(why, 0) + 1
    return sorted(rows, key=lambda r: r["index"]), rest[done:]
