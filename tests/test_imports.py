"""The import graph: every module imports alone, nothing is imported eagerly, no cycle.

The layers contract itself (the pipeline order) is checked by ``lint-imports``
(import-linter, configured in ``pyproject.toml``), which ``.ci/run`` runs.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import networkx as nx
import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("gather_verify", "schedulers")


def all_modules() -> list[str]:
    """Every module of the two packages, from the files on disk (importing nothing)."""
    names = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


ALONE = """
import importlib, json, sys, traceback
failed = {}
for name in json.loads(sys.argv[1]):
    for loaded in [m for m in sys.modules if m.split(".")[0] in ("gather_verify", "schedulers")]:
        del sys.modules[loaded]
    try:
        importlib.import_module(name)
    except Exception:
        failed[name] = traceback.format_exc(limit=-3)
print(json.dumps(failed))
"""


def test_every_module_imports_alone_in_a_fresh_interpreter() -> None:
    """One subprocess; before each module, every module of ours is forgotten, so each import
    starts as in a fresh interpreter (a cycle through a package ``__init__`` fails here)."""
    modules = all_modules()
    assert "schedulers" in modules and "gather_verify.engine.explore" in modules
    out = subprocess.run([sys.executable, "-c", ALONE, json.dumps(modules)], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout
    failed = json.loads(out)
    assert not failed, "\n".join(f"{name}:\n{tb}" for name, tb in failed.items())


def test_import_gather_verify_is_cheap_and_lazy() -> None:
    code = ("import sys, gather_verify\n"
            "ours = sorted(m for m in sys.modules if m.startswith(('gather_verify', 'schedulers')))\n"
            "print(ours, 'numpy' in sys.modules)\n"
            "from gather_verify import Configuration, run_check\n"
            "print(run_check.__module__, Configuration.__module__)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                         check=True).stdout.splitlines()
    assert out[0] == "['gather_verify'] False"
    assert out[1] == "gather_verify.plane_check gather_verify.model.configuration"


def test_public_names_resolve_and_unknown_names_raise() -> None:
    import gather_verify

    for name in gather_verify.__all__:
        assert getattr(gather_verify, name) is not None, name
    assert set(gather_verify.__all__) <= set(dir(gather_verify))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        gather_verify.nope  # noqa: B018


def import_graph() -> nx.DiGraph:
    """Module -> imported module, for every import statement of ours, also those inside
    functions (grimp, the graph builder of import-linter); ``if TYPE_CHECKING:`` imports,
    which never run, are left out."""
    grimp = pytest.importorskip("grimp")
    g = grimp.build_graph(*PACKAGES, exclude_type_checking_imports=True)
    graph = nx.DiGraph()
    for module in g.modules:
        graph.add_node(module)
        graph.add_edges_from((module, imported) for imported in g.find_modules_directly_imported_by(module))
    return graph


def cycles(graph: nx.DiGraph) -> list[list[str]]:
    return sorted(sorted(c) for c in nx.strongly_connected_components(graph) if len(c) > 1)


def test_no_import_cycle_module_level_or_inside_functions() -> None:
    graph = import_graph()
    assert graph.has_edge("gather_verify.engine.search", "gather_verify.engine.fast_explore")
    assert cycles(graph) == []


def test_the_cycle_finder_finds_a_cycle() -> None:
    """The check above can fail: one edge back from the model to the explorer makes a cycle."""
    graph = import_graph()
    graph.add_edge("gather_verify.model.configuration", "gather_verify.engine.explore")
    assert any("gather_verify.engine.explore" in c for c in cycles(graph))


def test_schedulers_import_only_the_model_layer() -> None:
    """(and the error types, and the compiled kernels, which import nothing of the project)"""
    graph = import_graph()
    ours = {m for s in graph if s.startswith("schedulers") for m in graph.successors(s)
            if m.startswith("gather_verify")}
    assert ours and all(m.startswith(("gather_verify.model", "gather_verify.errors",
                                      "gather_verify.kernels")) for m in ours), ours


NOT_NEEDED = """
import json, sys
heavy = ("networkx", "scipy", "matplotlib", "hypothesis", "gather_verify.synthesis",
         "gather_verify.sweeps.sweep")
# a finite world's check: none of the paper's world (Z²) engine, properties or tables
finite = ("gather_verify.paper", "sqlite3", "gather_verify.plane_check", "gather_verify.engine.explore",
          "gather_verify.engine.checks", "gather_verify.properties", "gather_verify.render",
          "gather_verify.scenario_tests", "statistics", "gather_verify.world_replay")
if sys.argv[1] == "ring":
    from gather_verify.world_check import run_world_check
    r = run_world_check("ring:9", [0, 3, 5], [7], "go-to-target", "async", reduction=False)
    heavy += finite
elif sys.argv[1] == "grid":
    from gather_verify.plane_check import run_check
    from gather_verify.model.configuration import Configuration
    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    r = run_check(c, algorithm="go-to-target", scheduler="async", reduction=False)
else:  # the command line, on the ring
    from gather_verify.cli import main
    assert main(["check", "--world", "ring:9", "--robots", "0 3 5", "--meeting", "7",
                 "--algorithm", "go-to-target", "--scheduler", "async", "--json"]) == 0
    r = {"verdict": "VERIFIED"}
    # and the command line imports the module of the command it runs, no other
    heavy += finite + ("gather_verify.scenario",) + tuple(f"gather_verify.cli.{name}" for name in
                            ("classify", "census", "simulate", "replay", "sweep", "report",
                             "impossibility", "bench", "test", "synthesize"))
print(json.dumps([r["verdict"], sorted(m for m in heavy if m in sys.modules)]))
"""


@pytest.mark.parametrize("run", ["ring", "grid", "cli-ring"])
def test_a_check_imports_nothing_it_does_not_use(run: str) -> None:
    """Checking go-to-target on a ring or on Z² (the bench's runs, and a user's first check)
    imports no networkx (a world's view builds its graph only when asked for it), no plotting
    or test library, no synthesis or sweep; the ring's check no paper package, no sqlite and
    nothing of Z²'s engine (its properties, its checks, its pictures); the command line
    only the module of the command it runs. Each import is a fixed cost of every process
    (networkx alone: 0.2 s), and where bytecode is not cached, each module is compiled
    again by every process."""
    out = subprocess.run([sys.executable, "-c", NOT_NEEDED, run], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout.splitlines()[-1]
    assert json.loads(out) == ["VERIFIED", []]


@pytest.mark.parametrize("argv", [
    ["check", "--world", "ring:9", "--robots", "0 3 5", "--meeting", "7", "--json"],
    ["check", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--scheduler", "ssync"],
    ["sweep", "--world", "ring:5-7", "--robots", "2-3", "--meeting", "1"],
    ["report", "--help"],
])
def test_the_parser_of_one_command_reads_as_the_whole_parser(argv: list[str], capsys) -> None:
    """The command line builds the parser of the command it runs alone (importing no other
    command's module): it reads every command line as the parser of every command does."""
    from gather_verify.cli import build_parser
    from gather_verify.cli.common import UsageError

    def read(parser):  # the namespace, or the help printed and the exit code
        try:
            return vars(parser.parse_args(argv))
        except SystemExit as stop:
            return capsys.readouterr().out, stop.code

    assert read(build_parser(argv[0])) == read(build_parser())
    with pytest.raises(UsageError, match="invalid choice"):  # no other command in it
        build_parser(argv[0]).parse_args(["classify" if argv[0] != "classify" else "check"])
