"""gather-verify: exhaustive verification of gathering over meeting nodes on the infinite grid.

The pipeline, one module per concept: configuration -> symmetry (the paper's
strings -> classes: :mod:`gather_verify.paper`); view -> algorithm -> move sets ->
scheduler -> explorer -> properties -> verdict and trace.

The public surface is small and lazy (PEP 562): ``import gather_verify`` loads
nothing else, and each name below imports its module on first use, so every
module can be imported alone and the package has no import cycle. ``replay`` and
``simulate`` are modules of this package, so their functions are imported from them
(``from gather_verify.replay import replay``): a lazy name may not shadow a module.
``check`` is a plain function, :func:`gather_verify.plane_check.check` (the check of the
paper's world lives in the module ``plane_check``, so no module shadows the name).

>>> import gather_verify as gv
>>> gv.check(robots=[(0, 0), (3, 1), (1, 4)], meeting=[(2, 2)], algorithm="go-to-target").verdict
'VERIFIED'

>>> from gather_verify import classify, run_check, Configuration
>>> classify([(0, 0), (3, 1), (1, 4)], [(2, 2)]).name
'I13'
>>> c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
>>> report = run_check(c, algorithm="go-to-target", scheduler="async", reduction=False,
...                    max_states=10_000, max_seconds=60)
>>> report["verdict"], report["states"], report["transitions"]
('VERIFIED', 2184, 7032)
"""

from __future__ import annotations

import importlib
from typing import Any

_PUBLIC: dict[str, str] = {
    # the model
    "Configuration": "gather_verify.model.configuration",
    "CLASS_NAMES": "gather_verify.paper.classes",
    "Classification": "gather_verify.paper.classes",
    "classify": "gather_verify.paper.classes",
    "classify_configuration": "gather_verify.paper.classes",
    # algorithms
    "Algorithm": "gather_verify.algorithms",
    "Unhandled": "gather_verify.algorithms",
    "AlgorithmCrash": "gather_verify.algorithms",
    "get_algorithm": "gather_verify.algorithms",
    "register": "gather_verify.algorithms",
    # the search and its verdict
    "Exploration": "gather_verify.engine.explore",
    "Limits": "gather_verify.engine.explore",
    "explore": "gather_verify.engine.search",
    "to_networkx": "gather_verify.engine.export",
    "run_check": "gather_verify.plane_check",
    "check": "gather_verify.plane_check",
    "CheckReport": "gather_verify.plane_check",
    "PropertyResult": "gather_verify.plane_check",
    "load_trace": "gather_verify.trace",
    "check_impossibility": "gather_verify.paper.impossibility",
    # inputs and sweeps
    "Scenario": "gather_verify.scenario",
    "load_scenario": "gather_verify.scenario",
    "census": "gather_verify.sweeps.census",
    "SweepSettings": "gather_verify.sweeps.sweep",
    "run_sweep": "gather_verify.sweeps.sweep",
    # errors
    "InvalidInput": "gather_verify.errors",
}

__all__ = sorted(_PUBLIC)


def __getattr__(name: str) -> Any:
    """Import the module of a public name on first use (PEP 562)."""
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'gather_verify' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_PUBLIC})
