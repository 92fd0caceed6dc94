"""The Python API: :func:`check` with defaults, returning a typed :class:`CheckReport`.

JSON stays at the edge: ``CheckReport.to_json()`` is the object ``gather-verify
check --json --timings`` prints (the dict of :func:`gather_verify.check.run_check`).
docs/api.md walks through it with runnable examples.

>>> r = check(robots=[(0, 0), (3, 1), (1, 4)], meeting=[(2, 2)], algorithm="go-to-target")
>>> r.verdict, r.configuration_class, r.max_moves, r.properties["termination"].holds
('VERIFIED', 'I13', 9, True)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from gather_verify.algorithms.base import Algorithm
from gather_verify.engine.explore import DEFAULT_MAX_SECONDS, DEFAULT_MAX_STATES
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import Node


@dataclass(frozen=True)
class PropertyResult:
    """One property: ``holds`` (None: not decided, the search stopped), why, and the numbers
    some properties add (``move-bound``: ``max_moves`` and ``bound``)."""

    holds: bool | None
    reason: str | None = None
    numbers: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"holds": self.holds}
        if self.reason is not None:
            out["reason"] = self.reason
        return {**out, **self.numbers}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> PropertyResult:
        rest = {k: v for k, v in data.items() if k not in ("holds", "reason")}
        return cls(data["holds"], data.get("reason"), rest)


@dataclass(frozen=True)
class CheckReport:
    """What a check found. ``verdict`` is VERIFIED, VIOLATED, INCOMPLETE or NOT-APPLICABLE;
    ``property`` the first failing one (``failing``: every one), with its ``reason`` and
    ``trace`` (a JSON object, docs/traces.md: it is a file format)."""

    verdict: str
    property: str | None
    reason: str | None
    configuration_class: str
    n: int
    D: int
    states: int
    transitions: int
    max_moves: int | None
    max_moves_infinite: bool
    ratio: float | None
    bound: float
    properties: dict[str, PropertyResult]
    trace: dict[str, Any] | None
    algorithm: str
    scheduler: str
    detection: str
    frames: str
    reduction: bool
    limits: dict[str, Any]
    seconds: float
    peak_rss_mb: float | None = None

    @property
    def failing(self) -> list[str]:
        """Every property that fails."""
        return [name for name, r in self.properties.items() if r.holds is False]

    def to_json(self) -> dict[str, Any]:
        """The report as ``run_check`` returns it (and ``check --json --timings`` prints it)."""
        out = {
            "class": self.configuration_class, "verdict": self.verdict, "property": self.property,
            "reason": self.reason, "states": self.states, "transitions": self.transitions,
            "max_moves": self.max_moves, "max_moves_infinite": self.max_moves_infinite,
            "D": self.D, "n": self.n, "ratio": self.ratio, "bound": self.bound,
            "seconds": self.seconds, "trace": self.trace,
            "properties": {name: r.to_json() for name, r in self.properties.items()},
            "limits": dict(self.limits), "algorithm": self.algorithm,
            "scheduler": self.scheduler, "detection": self.detection, "frames": self.frames,
            "reduction": self.reduction,
        }
        if self.peak_rss_mb is not None:
            out["peak_rss_mb"] = self.peak_rss_mb
        return out

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> CheckReport:
        return cls(
            verdict=data["verdict"], property=data["property"], reason=data["reason"],
            configuration_class=data["class"], n=data["n"], D=data["D"], states=data["states"],
            transitions=data["transitions"], max_moves=data["max_moves"],
            max_moves_infinite=data["max_moves_infinite"], ratio=data["ratio"],
            bound=data["bound"], trace=data["trace"],
            properties={k: PropertyResult.from_json(v) for k, v in data["properties"].items()},
            algorithm=data["algorithm"], scheduler=data["scheduler"],
            detection=data["detection"], frames=data["frames"], reduction=data["reduction"],
            limits=data["limits"], seconds=data["seconds"], peak_rss_mb=data.get("peak_rss_mb"))


def check(
    configuration: Configuration | None = None,
    *,
    robots: Iterable[Node] | None = None,
    meeting: Iterable[Node] | None = None,
    algorithm: str | Algorithm = "paper",
    scheduler: str = "async",
    detection: str = "local-weak",
    frames: str = "all",
    properties: Sequence[str] | None = None,
    reduction: bool = True,
    max_states: int = DEFAULT_MAX_STATES,
    max_seconds: float = DEFAULT_MAX_SECONDS,
    move_bound_c: float = 4.0,
    force: bool = False,
    **limits: Any,
) -> CheckReport:
    """Check ``algorithm`` from a configuration (or ``robots`` and ``meeting``) against every
    adversary of ``scheduler``; the same search as ``gather-verify check``.

    ``algorithm`` is a spec (``"paper"``, ``"my_alg.py:MyAlgorithm"``,
    ``"package.module:NAME"``) or an object with ``name`` and ``decide(view)``. The limits
    default to the command line's; ``max_memory_mb`` and ``margin`` may be given too."""
    from gather_verify.check import run_check

    if configuration is None:
        if robots is None or meeting is None:
            raise ValueError("give a configuration, or both robots and meeting")
        configuration = Configuration(list(robots), list(meeting), initial=True)
    name = algorithm if isinstance(algorithm, str) else getattr(algorithm, "name", None)
    if not isinstance(name, str):
        raise ValueError("an algorithm object needs a name (a string attribute)")
    report = run_check(configuration, algorithm=algorithm,  # type: ignore[arg-type]
                       scheduler=scheduler, detection=detection, frames=frames,
                       properties=properties, reduction=reduction, max_states=max_states,
                       max_seconds=max_seconds, move_bound_c=move_bound_c, force=force, **limits)
    report["algorithm"] = name
    return CheckReport.from_json(report)
