"""Sphinx directives that write the command-line reference from the code itself.

``.. gather-verify-cli::`` renders every command of ``gather_verify.cli.build_parser()``:
its description, its usage and every argument with its help, default and choices, and the
exit codes its module can return. ``.. gather-verify-exit-codes::`` renders the table of
exit codes from the ``EXIT_*`` constants of ``gather_verify.cli``; a constant without a
meaning below (or a meaning without a constant) fails the build, so the page cannot go
stale: a new option, command or exit code shows up at the next build.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import inspect

from docutils import nodes
from sphinx.util.docutils import SphinxDirective

#: Meaning of each exit code, keyed by the name of its constant.
MEANINGS = {
    "EXIT_OK": "success; VERIFIED; ROBUST-VERIFIED under ``--readings``; ``test``: every "
               "expectation met; ``check`` on a scenario whose expectation for its algorithm "
               "and scheduler is met (whatever the verdict)",
    "EXIT_VIOLATED": "VIOLATED (a property fails, with a replayable trace; an exception in "
                     "the algorithm is the property ``crash``); ``replay``: the violation is "
                     "confirmed; ``test``: an expectation failed; ``impossibility``: a run "
                     "gathered or lost the symmetry",
    "EXIT_USAGE": "bad input or usage (``InvalidInput``, or a file that cannot be read or "
                  "written): one line on stderr starting with ``error:``, never a traceback",
    "EXIT_INCOMPLETE": "INCOMPLETE: a state, time, memory or region limit stopped the search, "
                       "or a step before it (building a world, its automorphisms); "
                       "``sweep``: some configuration was stopped, or the world's census; "
                       "``synthesize``: ``unknown``; ``synthesize --verify``: the "
                       "certificate was not re-checked within the limits",
    "EXIT_NOT_APPLICABLE": "NOT-APPLICABLE: the initial configuration is in U or "
                           "UNCLASSIFIED (``impossibility``: it is not in U)",
    "EXIT_NO_LONGER_REPRODUCES": "``replay``: the trace no longer reproduces (the algorithm "
                                 "was changed since the trace was written), and the output "
                                 "says which of two kinds: ``step-not-taken`` (the algorithm "
                                 "no longer takes one of its steps) or ``property-holds`` "
                                 "(every step is taken, but the property no longer fails at "
                                 "the end)",
    "EXIT_BUG": "a bug of gather-verify (any other exception): the traceback, then one line "
                "saying so",
    "EXIT_INTERRUPTED": "interrupted by Ctrl-C; one line says what was kept (a sweep resumes "
                        "from its database)",
    "EXIT_BROKEN_PIPE": "the output pipe was closed by its reader (``| head``): the command "
                        "stops quietly",
}

#: Codes every command can return, whatever its module says (``gather_verify.cli.main``
#: returns them).
SHARED = ("EXIT_USAGE", "EXIT_BUG", "EXIT_INTERRUPTED", "EXIT_BROKEN_PIPE")

#: The other codes ``gather_verify.cli.main`` returns, for what happened outside a check.
#: Only those ``main`` does return are printed; the build fails when it returns another.
FROM_MAIN = {
    "EXIT_VIOLATED": "when the algorithm it runs crashes outside a search (simulate, "
                     "impossibility)",
    "EXIT_INCOMPLETE": "when a time limit's watchdog stops the algorithm's code outside a "
                       "check (nothing was decided)",
}


def exit_codes() -> dict[str, int]:
    """Every ``EXIT_*`` constant of the command line, by name."""
    codes = {}
    for module in ("gather_verify.cli.common", "gather_verify.cli"):
        for name, value in vars(importlib.import_module(module)).items():
            if name.startswith("EXIT_") and isinstance(value, int):
                codes[name] = value
    return codes


def command_codes(module_name: str, codes: dict[str, int], function: str | None = None
                  ) -> set[int]:
    """The exit codes a command's module (or one of its functions) can return: the
    ``EXIT_*`` names it reads, the values of the ``*_EXIT`` tables it reads, and the
    integers it returns literally."""
    module = importlib.import_module(module_name)
    found: set[int] = set()
    source = inspect.getsource(getattr(module, function) if function else module)
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Name):
            value = getattr(module, node.id, None)
            if node.id.startswith("EXIT_") and isinstance(value, int):
                found.add(value)
            elif node.id.endswith("_EXIT") and isinstance(value, dict):
                found.update(v for v in value.values() if isinstance(v, int))
        elif isinstance(node, ast.Return) and node.value is not None:
            for leaf in ast.walk(node.value):
                if isinstance(leaf, ast.Constant) and type(leaf.value) is int:
                    found.add(leaf.value)
    return found & set(codes.values())


def _paragraph(*parts: nodes.Node | str) -> nodes.paragraph:
    para = nodes.paragraph()
    for part in parts:
        para += nodes.Text(part) if isinstance(part, str) else part
    return para


def _literal(text: str) -> nodes.literal:
    return nodes.literal(text, text)


def _rst_inline(directive: SphinxDirective, text: str) -> list[nodes.Node]:
    """Inline reStructuredText (the meanings above use ``literals``)."""
    parsed, messages = directive.state.inline_text(text, directive.lineno)
    return [*parsed, *messages]


def _argument(action: argparse.Action, formatter: argparse.HelpFormatter) -> nodes.Node:
    if action.option_strings:
        metavar = formatter._format_args(action, action.dest.upper()) if action.nargs != 0 else ""
        names = ", ".join(f"{o} {metavar}".strip() for o in action.option_strings)
    else:
        names = formatter._metavar_formatter(action, action.dest)(1)[0]
    item = nodes.definition_list_item()
    item += nodes.term("", "", _literal(names))
    body = nodes.definition()
    help_text = formatter._expand_help(action) if action.help else ""
    extras = []
    if action.choices is not None and not isinstance(action.choices, dict):
        extras.append("choices: " + ", ".join(str(c) for c in action.choices))
    if (action.option_strings and action.nargs != 0 and action.default not in
            (None, argparse.SUPPRESS, False, [], "") and "default" not in help_text):
        extras.append(f"default: {action.default}")
    text = help_text or "(no help text)"
    body += _paragraph(text + (f" ({'; '.join(extras)})" if extras else ""))
    item += body
    return item


class CommandLine(SphinxDirective):
    """Every command of ``gather-verify``, from its argparse parser."""

    has_content = False

    def run(self) -> list[nodes.Node]:
        from gather_verify.cli import COMMANDS, build_parser

        codes = exit_codes()
        by_value = {v: k for k, v in codes.items()}
        shared = sorted(codes[name] for name in SHARED)
        from_main = command_codes("gather_verify.cli", codes, "main") - set(shared)
        notes = {codes[name]: text for name, text in FROM_MAIN.items() if name in codes}
        if not from_main <= set(notes):
            raise self.error(f"gather_verify.cli.main returns {sorted(from_main)}: say when, "
                             "in FROM_MAIN of docs/_ext/gv_cli.py")
        also = "; ".join(f"{code} {notes[code]}" for code in sorted(from_main))
        parser = build_parser()
        (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        if list(sub.choices) != list(COMMANDS):
            raise self.error(f"the parser's commands {list(sub.choices)} are not COMMANDS")
        result: list[nodes.Node] = [
            _paragraph("Usage: ", _literal("gather-verify COMMAND [OPTIONS]"), ". Every "
                       "command takes ", _literal("-h"), " or ", _literal("--help"), "; "
                       "options are never abbreviated. Every command can also exit with " +
                       ", ".join(map(str, shared)) + " (see the exit codes below)" +
                       (f"; and with {also}." if also else "."))]
        for name, command in sub.choices.items():
            section = nodes.section(ids=[f"command-{name}"], names=[f"gather-verify {name}"])
            section += nodes.title("", "", _literal(f"gather-verify {name}"))
            section += _paragraph(command.description or "")
            usage = command.format_usage().removeprefix("usage: ").strip()
            section += nodes.literal_block(usage, usage, language="text")
            formatter = command._get_formatter()
            for group in command._action_groups:
                actions = [a for a in group._group_actions if not isinstance(a, argparse._HelpAction)]
                if not actions:
                    continue
                section += nodes.rubric("", group.title.capitalize())
                section += nodes.definition_list("", *(_argument(a, formatter) for a in actions))
            own = sorted(command_codes(f"gather_verify.cli.{name}", codes) - set(shared))
            described = [f"{c} ({by_value[c].removeprefix('EXIT_').lower().replace('_', ' ')})"
                         for c in own]
            section += _paragraph("Exit codes: " + (", ".join(described) or "0") +
                                  "; and the shared ones, " + ", ".join(map(str, shared)) + ".")
            self.state.document.note_implicit_target(section, section)
            result.append(section)
        return result


class ExitCodes(SphinxDirective):
    """The table of exit codes, from the ``EXIT_*`` constants."""

    has_content = False

    def run(self) -> list[nodes.Node]:
        codes = exit_codes()
        if set(codes) != set(MEANINGS):
            raise self.error(
                "the exit codes of gather_verify.cli and the meanings in docs/_ext/gv_cli.py "
                f"differ: without a meaning {sorted(set(codes) - set(MEANINGS))}, without a "
                f"constant {sorted(set(MEANINGS) - set(codes))}")
        table = nodes.table()
        group = nodes.tgroup(cols=3)
        table += group
        for width in (8, 30, 62):
            group += nodes.colspec(colwidth=width)
        head = nodes.thead()
        group += head
        row = nodes.row()
        for label in ("code", "constant", "meaning"):
            row += nodes.entry("", _paragraph(label))
        head += row
        body = nodes.tbody()
        group += body
        for name, value in sorted(codes.items(), key=lambda item: item[1]):
            row = nodes.row()
            row += nodes.entry("", _paragraph(str(value)))
            row += nodes.entry("", _paragraph(_literal(name)))
            row += nodes.entry("", _paragraph(*_rst_inline(self, MEANINGS[name])))
            body += row
        return [table]


def setup(app):  # noqa: ANN001, ANN201 - Sphinx's extension entry point
    app.add_directive("gather-verify-cli", CommandLine)
    app.add_directive("gather-verify-exit-codes", ExitCodes)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
