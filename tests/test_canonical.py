"""Canonical forms: invariant under the grid isometries, and the shortcuts built on them
(a view's canonical form from its snapshot's, configuration facts shared by the
searches of a sweep) give exactly what the direct computation gives."""

from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.engine.explore import Limits
from gather_verify.engine.fast_explore import explore_fast
from gather_verify.model import geometry
from gather_verify.model.canonical import canonical, canonical_form
from gather_verify.model.configuration import Configuration
from gather_verify.model.view import View

nodes = st.tuples(st.integers(-3, 3), st.integers(-3, 3))
configurations = st.builds(
    Configuration,
    st.lists(nodes, min_size=1, max_size=5),  # repeats: multiplicities
    st.lists(nodes, min_size=1, max_size=4, unique=True),
)
isometries = st.tuples(st.sampled_from(geometry.ALL), nodes)
ALGORITHMS = ("paper", "paper:alpha=mer_f", "go-to-target", "nearest-centre", "random:seed=3")


@settings(max_examples=200, deadline=None)
@given(configurations, isometries)
def test_canonical_form_is_invariant_and_reaches_its_key(c, iso):
    g, t = iso
    form = canonical_form(c.occupied, c.meeting_nodes)
    moved = c.transformed(g, t)
    assert canonical_form(moved.occupied, moved.meeting_nodes).key == form.key
    for h, (tx, ty) in form.minimisers:
        image = c.transformed(h, (tx, ty))
        assert (tuple(sorted(image.occupied)), tuple(sorted(image.meeting_nodes))) == form.key


@settings(max_examples=300, deadline=None)
@given(configurations, st.sampled_from(geometry.ALL), st.data())
def test_view_canonical_is_the_canonical_form_of_what_it_shows(c, frame, data):
    node = data.draw(st.sampled_from(sorted(c.counts)))
    view = View(c, node, frame, "local-weak")
    assert view.canonical() == canonical(view.robots, view.meeting_nodes)


initial = st.builds(
    lambda rs, ms: Configuration(rs, ms, initial=True),
    st.lists(st.tuples(st.integers(0, 2), st.integers(0, 2)), min_size=2, max_size=3, unique=True),
    st.lists(st.tuples(st.integers(0, 2), st.integers(0, 2)), min_size=1, max_size=3, unique=True),
)


@settings(max_examples=60, deadline=None)
@given(initial, isometries, st.sampled_from(ALGORITHMS),
       st.sampled_from(("all", "chirality", "compass")))
def test_shared_facts_memo_changes_nothing(c, iso, spec, frames):
    """Searches that share the memo (a sweep's) give exactly the searches that do not,
    also when the memo was filled by an isometric configuration."""
    def run(config, memo):
        e = explore_fast(config, spec, "async", frames=frames, memo=memo,
                         limits=Limits(max_states=20_000))
        return (list(e.keys), list(e.parents), list(e.targets), list(e.weights), e.stopped,
                {k: (v.state, v.reason) for k, v in e.violations.items()})

    for config in (c.transformed(*iso), c):  # the second meets what the first stored
        assert run(config, True) == run(config, False)


@settings(max_examples=200, deadline=None)
@given(configurations)
def test_canonical_form_is_the_least_normalised_image(c):
    """The integer-coded search against the definition: the least of the 8 images
    translated to the origin, and exactly the elements that reach it."""
    images = []
    for g in geometry.ALL:
        image = c.transformed(g)
        x0, y0, _, _ = image.mer()
        key = (tuple(sorted({(x - x0, y - y0) for x, y in image.robots})),
               tuple(sorted((x - x0, y - y0) for x, y in image.meeting_nodes)))
        images.append((key, g, (-x0, -y0)))
    best = min(key for key, _, _ in images)
    form = canonical_form(c.occupied, c.meeting_nodes)
    assert form.key == best
    assert form.minimisers == tuple((g, t) for key, g, t in images if key == best)


def test_a_process_keeps_the_memos_of_few_algorithms():
    """A sweep under every reading runs many algorithms in one worker: the memos of the least
    recently used are dropped, so they cannot fill the worker's memory limit."""
    from gather_verify.algorithms import get_algorithm
    from gather_verify.engine import facts_table

    algorithms = [get_algorithm(f"paper:finalize={v}") for v in ("closest", "target", "n1")]
    first = facts_table.facts_memo(algorithms[0], "local-weak", "all")
    first["seen"] = True
    for algorithm in algorithms[1:]:
        facts_table.facts_memo(algorithm, "local-weak", "all")
        facts_table.target_memo(algorithm)
    assert len(facts_table._MEMOS) <= facts_table.MEMO_ALGORITHMS
    assert len(facts_table._TARGETS) <= facts_table.MEMO_ALGORITHMS
    assert facts_table.facts_memo(algorithms[0], "local-weak", "all") == {}  # dropped
    recent = facts_table.facts_memo(algorithms[2], "local-weak", "all")
    assert facts_table.facts_memo(algorithms[2], "local-weak", "all") is recent  # kept


def test_a_process_keeps_few_algorithm_instances():
    """The instances (and the plans they remember) of the least recently used algorithms
    are dropped; the recent ones are shared."""
    from gather_verify import algorithms

    specs = [f"paper:finalize={v}" for v in ("closest", "target", "n1", "literal")] + [
        "paper:outside=mer_f"]
    first = algorithms.get_algorithm(specs[0])
    assert algorithms.get_algorithm(specs[0]) is first
    for spec in specs[1:]:
        algorithms.get_algorithm(spec)
    assert len(algorithms._INSTANCES) <= algorithms.INSTANCES_KEPT
    assert algorithms.get_algorithm(specs[-1]) is algorithms.get_algorithm(specs[-1])
    assert algorithms.get_algorithm(specs[0]) is not first  # dropped, made again


def test_memos_are_dropped_when_the_process_is_over_half_its_memory_limit():
    """A check must not stop INCOMPLETE (memory) because of what earlier checks memoised."""
    from gather_verify.algorithms import get_algorithm
    from gather_verify.engine import facts_table

    facts_table.facts_memo(get_algorithm("paper"), "local-weak", "all")["seen"] = True
    facts_table.make_room(1e9)  # far under the limit: kept
    assert facts_table._MEMOS
    facts_table.make_room(1.0)  # over half of 1 MB: dropped
    assert not facts_table._MEMOS and not facts_table._TARGETS


@settings(max_examples=300, deadline=None)
@given(configurations, isometries, st.booleans())
def test_an_image_carries_the_canonical_form_it_would_find(c, iso, known):
    """``transformed`` derives the image's form from a known one (``moved_form``): it must be
    the form a search of the image finds, minimisers and their order included."""
    g, t = iso
    if known:
        c.canonical_form  # noqa: B018
    image = c.transformed(g, t)
    assert ("canonical_form" in image.__dict__) == known
    fresh = Configuration(image.robots, image.meeting_nodes)
    assert image.canonical_form == fresh.canonical_form


small_nodes = st.tuples(st.integers(0, 3), st.integers(0, 3))


@settings(max_examples=60, deadline=None)
@given(st.lists(small_nodes, min_size=1, max_size=4, unique=True),
       st.lists(st.lists(small_nodes, min_size=3, max_size=3), min_size=1, max_size=4))
def test_facts_table_rows_carry_the_canonical_form_a_search_finds(meeting, robot_sets):
    """A table row's form is moved from its orbit representative's (computed by the
    paper's own analysis, or kept in the shared memo): for every row, images under
    ``Aut(M)`` included, and through a second table that finds every orbit in the memo,
    it must be the form a search finds, minimisers and their order included."""
    import numpy as np

    from gather_verify.algorithms import get_algorithm
    from gather_verify.algorithms.moves import frames_for
    from gather_verify.engine.encoding import Encoding, region_box
    from gather_verify.engine.facts_table import FactsTable
    from gather_verify.model.symmetry import meeting_automorphisms

    configs = [Configuration(r, meeting) for r in robot_sets]
    group = meeting_automorphisms(configs[0])
    configs += [c.transformed(a.g, a.t) for c in configs for a in group[1:]]
    box = geometry.bounding_box([v for c in configs for b in [region_box(c, 0, group)]
                                 for v in (b[:2], b[2:])])
    enc = Encoding(box, group, True)
    memo: dict = {}
    carried = 0
    for _ in range(2):  # the second table finds every orbit in the memo
        table = FactsTable(enc, 3, get_algorithm("paper"), frozenset(meeting), "local-weak",
                           frames_for("all"), group, memo, targets=True)
        cells = np.array([sorted((x - enc.x0) * enc.height + y - enc.y0 for x, y in c.robots)
                          for c in configs], dtype=np.int32)
        srt, keys = table.config_keys(cells)
        table.rows(keys, srt)
        for row in range(table.size):
            c = table.configuration(row, form=True)
            if "canonical_form" in c.__dict__:
                carried += 1
                assert c.canonical_form == Configuration(c.robots, meeting).canonical_form
    assert carried >= table.size  # the paper computes forms: most rows carry one
