"""The ``gather-verify`` command line: one module per subcommand.

Every subcommand module defines ``HELP``, ``add_arguments(parser)`` and
``run(args) -> int``. Exit codes are shared by all commands: 0 success or
VERIFIED, 1 VIOLATED, 2 bad input or usage (:class:`~gather_verify.errors.InvalidInput`
or an unreadable/unwritable file: one line on stderr, never a traceback), 3 INCOMPLETE
(also when the watchdog stopped the user's code where no check could report it),
4 NOT-APPLICABLE, 5 a replayed trace no longer reproduces, 70 a bug of gather-verify (any other exception: it says so and prints
the traceback), 130 interrupted by Ctrl-C (one line on stderr says what was kept and how
to resume), 141 the output pipe was closed (``| head``). See docs/reliability.md.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import sys
import traceback
from collections.abc import Sequence

from gather_verify.algorithms.base import AlgorithmCrash
from gather_verify.cli.common import (
    EXIT_BUG,
    EXIT_INCOMPLETE,
    EXIT_INTERRUPTED,
    EXIT_USAGE,
    EXIT_VIOLATED,
    UsageError,
)
from gather_verify.errors import InvalidInput
from gather_verify.inputs import kept
from gather_verify.watchdog import Overtime, count_interrupts

EXIT_BROKEN_PIPE = 141
"""The output pipe was closed by its reader (128 + SIGPIPE, as shells report it)."""
COMMANDS = ("classify", "census", "simulate", "check", "replay", "sweep", "report",
            "impossibility", "bench", "test", "synthesize")


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(f"{self.prog}: {message}")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command, or, given ``command``, of that one alone: the command
    line imports only the module of the command it runs (a check does not pay for the
    synthesis, the sweeps or the paper's tables). Every other command's module must still be
    there, found without importing it."""
    parser = _Parser(prog="gather-verify", description=__doc__.splitlines()[0], allow_abbrev=False)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        if command is not None and name != command:
            if importlib.util.find_spec(f"gather_verify.cli.{name}") is None:
                raise _missing(name)
            continue
        try:
            module = importlib.import_module(f"gather_verify.cli.{name}")
        except ModuleNotFoundError as error:
            if error.name != f"gather_verify.cli.{name}":
                raise  # a module the command imports: its own message says which
            raise _missing(name) from error
        p = sub.add_parser(name, help=module.HELP, description=module.HELP, allow_abbrev=False)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def _missing(name: str) -> ImportError:
    """A listed command with no module: never skipped, since a command that vanishes from
    --help would hide a broken install."""
    return ImportError(f"the command module gather_verify.cli.{name} is missing: a bug of "
                       "gather-verify (a broken install, or a command listed with no module)",
                       name=f"gather_verify.cli.{name}")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        for text in argv:  # (a shell cannot pass one; a program can, and the OS refuses it)
            if "\x00" in text:
                raise UsageError(f"the argument {text!r} holds a NUL byte: no value or file "
                                 "name has one")
        args = build_parser(argv[0] if argv and argv[0] in COMMANDS else None).parse_args(argv)
        if not getattr(args, "_run", None):
            build_parser().print_help(sys.stderr)
            return EXIT_USAGE
        count_interrupts()  # a KeyboardInterrupt no Ctrl-C sent is the user's code's
        with kept():  # every input file is read once (gather_verify.inputs)
            return int(args._run(args))
    except InvalidInput as error:  # the user's mistake: the message names the bad value
        print(f"error: {one_line(str(error))}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # the reader went away (| head): stop quietly, as cat does
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except OSError as error:  # unreadable input or unwritable output file
        print(f"error: {one_line(str(error))}", file=sys.stderr)
        return EXIT_USAGE
    except AlgorithmCrash as crash:  # outside a search (simulate, impossibility ...)
        print("crash: " + "\n  at ".join([str(crash), *crash.frames]), file=sys.stderr)
        return EXIT_VIOLATED
    except KeyboardInterrupt:
        print("interrupted; run the same command again (a sweep keeps every row it stored and "
              "resumes)", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Overtime as stopped:  # the watchdog, where no check turned it into INCOMPLETE
        print(f"stopped: your code was still running after {stopped.seconds:g} s (the time "
              "limit's watchdog); nothing was decided", file=sys.stderr)
        return EXIT_INCOMPLETE
    except Exception as error:  # anything else is ours
        sqlite3 = sys.modules.get("sqlite3")  # imported by the commands that keep results
        if sqlite3 is not None and isinstance(error, sqlite3.DatabaseError):
            # read-only, damaged, or a full disk
            print(f"error: the results database failed: {one_line(str(error))} (every row "
                  "stored before is kept, and the same command resumes once the database is "
                  "writable and whole)",
                  file=sys.stderr)
            return EXIT_USAGE
        if _interrupted(error):  # Ctrl-C inside C code (numba loading its kernels) comes wrapped
            print("interrupted; run the same command again (a sweep keeps every row it stored and "
              "resumes)", file=sys.stderr)
            return EXIT_INTERRUPTED
        traceback.print_exc(file=sys.stderr)
        print("internal error: this is a bug of gather-verify, not a mistake in your input; "
              "please report it with the command line and the traceback above", file=sys.stderr)
        return EXIT_BUG


def one_line(text: str) -> str:
    """``text`` with every character a terminal or ``str.splitlines`` would not keep on one
    line (controls, separators) written as its escape: a name taken from the user's input
    cannot break the one-line error in two.

    >>> one_line("unknown field 'a\\x1eb'")
    "unknown field 'a\\\\x1eb'"
    """
    return "".join(ch if ch.isprintable() or ch == " " else ch.encode("unicode_escape").decode()
                   for ch in text)


def _interrupted(error: BaseException) -> bool:
    """Whether a KeyboardInterrupt caused ``error`` (a SystemError raised by C code that was
    interrupted, for one)."""
    seen: set[int] = set()
    cause: BaseException | None = error
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, KeyboardInterrupt):
            return True
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return False


if __name__ == "__main__":
    sys.exit(main())
