"""The ``gather-verify`` command line: one module per subcommand.

Every subcommand module defines ``HELP``, ``add_arguments(parser)`` and
``run(args) -> int``. Exit codes are shared by all commands: 0 success or
VERIFIED, 1 VIOLATED, 2 bad input or usage (:class:`~gather_verify.errors.InvalidInput`
or an unreadable/unwritable file: one line on stderr, never a traceback), 3 INCOMPLETE,
4 NOT-APPLICABLE, 70 a bug of gather-verify (any other exception: it says so and prints
the traceback), 130 interrupted by Ctrl-C (one line on stderr says what was kept and how
to resume). See docs/reliability.md.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import traceback
from collections.abc import Sequence

from gather_verify.cli.common import EXIT_BUG, EXIT_INTERRUPTED, EXIT_USAGE, UsageError
from gather_verify.errors import InvalidInput

COMMANDS = ("classify", "census", "simulate", "check", "replay", "sweep", "report",
            "impossibility", "bench")


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="gather-verify", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        try:
            module = importlib.import_module(f"gather_verify.cli.{name}")
        except ModuleNotFoundError as error:
            if error.name == f"gather_verify.cli.{name}":
                continue  # not built yet
            raise
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code."""
    try:
        args = build_parser().parse_args(argv)
        if not getattr(args, "_run", None):
            build_parser().print_help(sys.stderr)
            return EXIT_USAGE
        return int(args._run(args))
    except InvalidInput as error:  # the user's mistake: the message names the bad value
        print(f"error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as error:  # unreadable input or unwritable output file
        print(f"error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("interrupted: nothing was written; run the same command again", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception:  # anything else is ours
        traceback.print_exc(file=sys.stderr)
        print("internal error: this is a bug of gather-verify, not a mistake in your input; "
              "please report it with the command line and the traceback above", file=sys.stderr)
        return EXIT_BUG


if __name__ == "__main__":
    sys.exit(main())
