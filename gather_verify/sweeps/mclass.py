"""A sweep's unit of work as one meeting-node class (issue 17, ``sweep --engine union``).

:func:`verify_class` gives the rows of every configuration of one class, the
same rows :func:`gather_verify.sweeps.sweep.verify_one` gives one at a time:
most from one union graph (:mod:`gather_verify.engine.union`), the others
(NOT-APPLICABLE ones, and those the union does not settle exactly) from the
per-configuration check. :func:`class_tasks` cuts a sweep's configurations
into classes, largest first, so a pool starts the long ones early.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from gather_verify.model.configuration import Configuration

ENGINES = ("union", "per-config")


def verify_class(settings: Any, members: Sequence[tuple[int, Configuration]]
                 ) -> list[dict[str, Any]]:
    """The rows of ``members`` (configurations sharing ``M`` up to isometry), in index order."""
    from gather_verify.engine import union
    from gather_verify.sweeps.sweep import verify_one

    if not union.supports(settings.scheduler, settings.reduction, settings.frames):
        return [verify_one(settings, i, c) for i, c in members]
    decided = union.decide_class(settings, members)
    rows = decided.rows + [verify_one(settings, i, c) for i, c in decided.fallback]
    return sorted(rows, key=lambda r: r["index"])


def class_tasks(todo: Sequence[tuple[int, Configuration]]
                ) -> list[list[tuple[int, Configuration]]]:
    """``todo`` as meeting-node classes, the largest first (ties: enumeration order)."""
    from gather_verify.engine.union import meeting_classes

    classes = meeting_classes(todo)
    return sorted(classes, key=lambda members: (-len(members), members[0][0]))
