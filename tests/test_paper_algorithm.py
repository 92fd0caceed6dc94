"""The paper's Gathering() (gather_verify.paper.algorithm): targets, guards and moves per phase."""

from __future__ import annotations

import pytest

from gather_verify.algorithms import Unhandled, get_algorithm
from gather_verify.algorithms.moves import move_set, move_sets
from gather_verify.model.canonical import canonical
from gather_verify.model.configuration import Configuration
from gather_verify.paper import strings
from gather_verify.paper.algorithm import PaperAlgorithm, analyse, ordering_O_second
from gather_verify.paper.classes import classify_configuration
from gather_verify.scenario import load_scenario

PAPER = PaperAlgorithm()
FIG_STRING2 = "001001400004000000000000404000400401000000100"


def moving(algorithm, c: Configuration) -> dict:
    """Robots that may move, with their sorted move sets."""
    return {v: sorted(s) for v, s in move_sets(algorithm, c).items() if s != {v}}


def closer(v, m):
    d = abs(v[0] - m[0]) + abs(v[1] - m[1])
    return sorted(u for u in [(v[0] + 1, v[1]), (v[0] - 1, v[1]), (v[0], v[1] + 1),
                              (v[0], v[1] - 1)] if abs(u[0] - m[0]) + abs(u[1] - m[1]) < d)


# -- I1 -------------------------------------------------------------------------------------


@pytest.mark.parametrize("alpha", ["mer", "mer_f"])
def test_i11_every_robot_heads_for_the_last_node_of_O(alpha):
    c = Configuration([(0, 0), (4, 1), (2, 5)], [(1, 0), (3, 3), (0, 2)], initial=True)
    assert classify_configuration(c).name == "I11"
    algorithm = get_algorithm(f"paper:alpha={alpha}")
    target = strings.ordering_O(c, alpha)[-1]
    assert algorithm.target(c) == target
    assert moving(algorithm, c) == {r: closer(r, target) for r in c.robots}


def test_i11_figure_order1_alpha_over_mer_versus_mer_f():
    c = load_scenario("scenarios/paper/order1.json").configuration
    assert get_algorithm("paper").target(c) == strings.ordering_O(c, "mer")[-1]
    assert get_algorithm("paper:alpha=mer_f").target(c) == strings.ordering_O(c, "mer_f")[-1]


def test_i12_heads_for_the_last_meeting_node_of_O_prime_on_L():
    c = Configuration([(0, 2), (3, 3)], [(0, 0), (1, 1), (2, 0)], initial=True)
    assert classify_configuration(c).name == "I12"
    assert PAPER.target(c) == (1, 1)
    assert moving(PAPER, c) == {(0, 2): [(0, 1), (1, 2)], (3, 3): [(2, 3), (3, 2)]}


def test_i13_heads_for_the_meeting_node_on_c():
    c = Configuration([(0, 3), (4, 0)], [(0, 0), (2, 0), (1, 0)], initial=True)
    assert classify_configuration(c).name == "I13"
    assert PAPER.target(c) == (1, 0)
    assert moving(PAPER, c) == {(0, 3): [(0, 2), (1, 3)], (4, 0): [(3, 0)]}


# -- I2: GatheringAsym ------------------------------------------------------------------------


def test_figure_string2_guard_selection():
    """Every robot inside MER_F; the unique farthest from L (x = 4) is (1, 1): it steps away."""
    c = strings.from_string(FIG_STRING2, 5)
    assert classify_configuration(c).name == "I21"
    plan = PAPER.plan(c)
    assert (plan.phase, plan.guard, plan.target) == ("I2 guard selection", (1, 1), None)
    assert moving(PAPER, c) == {(1, 1): [(0, 1)]}


def test_guard_selection_ties_broken_by_the_maximum_configuration_view():
    # M (a trapezoid) symmetric about x = 1.5 only; (0, 1) and (3, 2) equally far from L
    c = Configuration([(0, 1), (3, 2), (1, 0)], [(0, 0), (3, 0), (1, 2), (2, 2)], initial=True)
    assert classify_configuration(c).name == "I21"
    guard = strings.max_view(c, [(0, 1), (3, 2)])
    plan = PAPER.plan(c)
    assert plan.guard == guard
    assert moving(PAPER, c) == {guard: [(guard[0] - 1 if guard[0] == 0 else guard[0] + 1,
                                         guard[1])]}


def test_guard_placement_moves_parallel_to_L_towards_the_closest_corner():
    c = Configuration([(5, 1), (1, 3), (2, 0)], [(0, 0), (3, 0), (0, 2), (3, 2)])
    plan = PAPER.plan(c)
    assert (plan.phase, plan.guard) == ("I2 guard placement", (5, 1))
    assert moving(PAPER, c) == {(5, 1): [(5, 0)]}


def test_guard_placement_two_closest_corners_is_the_adversarys_choice():
    c = Configuration([(1, 0), (0, 1), (2, -1), (1, 3)], [(0, 0), (2, 0)])
    plan = PAPER.plan(c)
    assert (plan.phase, plan.guard) == ("I2 guard placement", (1, 3))
    assert moving(PAPER, c) == {(1, 3): [(0, 3), (2, 3)]}


def test_make_multiplicity_closest_non_guards_move_first():
    c = Configuration([(5, 3), (1, 3), (2, 0), (0, 0)], [(0, 0), (3, 0), (0, 2), (3, 2)])
    plan = PAPER.plan(c)
    assert (plan.phase, plan.guard, plan.target) == ("I2 make multiplicity", (5, 3), (3, 2))
    # (1, 3) and (2, 0) are both 3 from the target; (0, 0) is 5 away and waits
    assert moving(PAPER, c) == {(1, 3): [(1, 2), (2, 3)], (2, 0): [(2, 1), (3, 0)]}


def test_make_multiplicity_tie_broken_by_O_second():
    # guard (0, 4) on a MER corner; meeting nodes (1, 2) and (2, 3) are both 3 away
    c = Configuration([(0, 4), (3, 0), (2, 1)], [(1, 2), (2, 3), (3, 2), (2, 1)])
    plan = PAPER.plan(c)
    assert (plan.phase, plan.guard) == ("I2 make multiplicity", (0, 4))
    order = ordering_O_second(c, (0, 4))
    assert order.index((2, 3)) < order.index((1, 2))
    assert plan.target == (2, 3)
    assert moving(PAPER, c) == {(2, 1): [(2, 2)]}  # the closest non-guard moves first


def test_finalization_guard_moves_multiplicity_stays():
    c = Configuration([(5, 3), (3, 2), (3, 2)], [(0, 0), (3, 0), (0, 2), (3, 2)])
    plan = PAPER.plan(c)
    assert (plan.phase, plan.target) == ("I2 finalization", (3, 2))
    assert moving(PAPER, c) == {(5, 3): [(4, 3), (5, 2)]}


def test_finalization_reads_only_the_robots_own_multiplicity_bit():
    # n1 = 2, neither position on a meeting node is not finalization; here the robot off
    # the meeting node is itself a multiplicity: Algorithm 4 keeps it still
    c = Configuration([(5, 3), (5, 3), (3, 2)], [(0, 0), (3, 0), (0, 2), (3, 2)])
    assert move_set(PAPER, c, (5, 3)) == {(5, 3)}


# -- I3: SymmetryBreaking ----------------------------------------------------------------------


def test_i31_robot_on_L_with_maximum_view_steps_off_L():
    c = load_scenario("scenarios/classes/i31.json").configuration
    assert classify_configuration(c).name == "I31"
    assert moving(PAPER, c) == {(1, 2): [(0, 2), (2, 2)]}


def test_i32_robot_on_c_steps_anywhere():
    c = Configuration([(1, 0), (0, 1), (2, -1)], [(0, 0), (2, 0)], initial=True)
    assert classify_configuration(c).name == "I32"
    assert moving(PAPER, c) == {(1, 0): [(0, 0), (1, -1), (1, 1), (2, 0)]}


@pytest.mark.parametrize("path", ["scenarios/classes/i41.json", "scenarios/classes/i42.json"])
def test_ungatherable_inputs_are_unhandled(path):
    c = load_scenario(path).configuration
    with pytest.raises(Unhandled, match="ungatherable"):
        move_sets(PAPER, c)
    assert PAPER.target(c) is None


def test_unclassified_is_unhandled_with_the_option():
    c = load_scenario("scenarios/classes/unclassified.json").configuration
    with pytest.raises(Unhandled, match="UNCLASSIFIED"):
        move_sets(get_algorithm("paper:unclassified=unhandled"), c)


def test_gathered_is_final_in_I2():
    c = Configuration([(0, 0), (0, 0)], [(0, 0), (3, 0)])
    assert moving(PAPER, c) == {}


def test_bad_options_are_rejected():
    with pytest.raises(ValueError, match="alpha"):
        get_algorithm("paper:alpha=foo")
    with pytest.raises(ValueError, match="bad options"):
        get_algorithm("paper:colour=red")


# -- recorded faults: the paper's rules allow these moves (see scenarios/algorithm/) ------------


def test_finding_make_multiplicity_may_step_onto_the_guard():
    s = load_scenario("scenarios/algorithm/i22-make-multiplicity-onto-guard.json")
    c = s.configuration
    plan = PAPER.plan(c)
    assert plan.phase == "I2 make multiplicity" and plan.guard == (0, 0)
    assert (0, 0) in move_set(PAPER, c, (1, 0))


def test_canonical_form_is_invariant():
    c = strings.from_string(FIG_STRING2, 5)
    key = canonical(c.occupied, c.meeting_nodes)[0]
    for g in range(8):
        d = c.transformed(g, (3, -7))
        assert canonical(d.occupied, d.meeting_nodes)[0] == key


def test_analyse_matches_plan_on_a_canonical_snapshot():
    c = strings.from_string(FIG_STRING2, 5)
    assert analyse(c).guard == PAPER.plan(c).guard


def test_outside_mer_f_two_readings():
    """Algorithm 2's "outside MER_F": beyond d1 from L (default) or outside the rectangle."""
    c = Configuration([(1, 5), (0, 1), (2, 0)], [(0, 0), (3, 0), (1, 2), (2, 2)], initial=True)
    assert classify_configuration(c).name == "I21"
    assert moving(PAPER, c) == {(0, 1): [(-1, 1)]}  # farthest from L = {x = 1.5}
    literal = get_algorithm("paper:outside=mer_f")
    assert literal.plan(c).guard == (1, 5)  # the only robot outside the rectangle MER_F
    assert moving(literal, c) == {(1, 5): [(0, 5)]}
