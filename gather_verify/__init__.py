"""gather-verify: exhaustive verification of gathering over meeting nodes on the infinite grid.

The pipeline, one module per concept: configuration -> symmetry -> strings ->
classes; view -> algorithm -> move sets -> scheduler -> explorer -> properties
-> verdict and trace.

The API in one call (docs/api.md): :func:`check` returns a typed :class:`CheckReport`.

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

from gather_verify.algorithms import Algorithm, AlgorithmCrash, Unhandled, get_algorithm, register
from gather_verify.algorithms.go_to_target import GoToTarget
from gather_verify.algorithms.moves import move_set, move_sets
from gather_verify.algorithms.nearest_centre import NearestCentre
from gather_verify.algorithms.paper import PaperAlgorithm
from gather_verify.algorithms.random_equivariant import RandomEquivariant
from gather_verify.api import CheckReport, PropertyResult
from gather_verify.api import check as _check
from gather_verify.check import run_check
from gather_verify.engine.explore import Exploration, Limits, explore
from gather_verify.impossibility import ImpossibilityResult, check_impossibility
from gather_verify.model.classes import (
    CLASS_NAMES,
    Classification,
    classify,
    classify_configuration,
)
from gather_verify.model.configuration import Configuration
from gather_verify.model.symmetry import Automorphism, automorphisms
from gather_verify.model.view import MultiplicityHidden, View
from gather_verify.properties import PROPERTIES, check_property_names
from gather_verify.replay import replay
from gather_verify.scenario import Scenario, ScenarioError, load_scenario
from gather_verify.simulate import Run, simulate
from gather_verify.sweeps.census import Census, canonical, census, enumerate_configurations
from gather_verify.sweeps.sweep import SweepSettings, run_sweep
from gather_verify.trace import load_trace

check = _check
"""The API's entry point (:func:`gather_verify.api.check`). Bound after the imports above:
importing the module ``gather_verify.check`` binds the package attribute to it, once."""

__all__ = [
    "CLASS_NAMES",
    "PROPERTIES",
    "Algorithm",
    "AlgorithmCrash",
    "Automorphism",
    "Census",
    "CheckReport",
    "Classification",
    "Configuration",
    "Exploration",
    "GoToTarget",
    "ImpossibilityResult",
    "Limits",
    "MultiplicityHidden",
    "NearestCentre",
    "PropertyResult",
    "PaperAlgorithm",
    "RandomEquivariant",
    "Run",
    "Scenario",
    "ScenarioError",
    "SweepSettings",
    "Unhandled",
    "View",
    "automorphisms",
    "canonical",
    "census",
    "check",
    "check_impossibility",
    "check_property_names",
    "classify",
    "classify_configuration",
    "enumerate_configurations",
    "explore",
    "get_algorithm",
    "load_scenario",
    "load_trace",
    "move_set",
    "move_sets",
    "register",
    "replay",
    "run_check",
    "run_sweep",
    "simulate",
]
