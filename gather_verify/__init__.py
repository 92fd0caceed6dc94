"""gather-verify: exhaustive verification of gathering over meeting nodes on the infinite grid.

The pipeline, one module per concept: configuration -> symmetry -> strings ->
classes; view -> algorithm -> move sets -> scheduler -> explorer -> properties
-> verdict and trace.

>>> from gather_verify import classify
>>> classify([(0, 0), (3, 1), (1, 4)], [(2, 2)]).name
'I13'
"""

from gather_verify.algorithms import Algorithm, Unhandled, get_algorithm, register
from gather_verify.classes import Classification, classify, classify_configuration
from gather_verify.configuration import Configuration
from gather_verify.moves import move_set, move_sets
from gather_verify.scenario import Scenario, ScenarioError, load_scenario
from gather_verify.symmetry import Automorphism, automorphisms
from gather_verify.view import MultiplicityHidden, View

__all__ = [
    "Algorithm",
    "Automorphism",
    "Classification",
    "Configuration",
    "MultiplicityHidden",
    "Scenario",
    "ScenarioError",
    "Unhandled",
    "View",
    "automorphisms",
    "classify",
    "classify_configuration",
    "get_algorithm",
    "load_scenario",
    "move_set",
    "move_sets",
    "register",
]
