"""The user's mistakes (exit 2, one line) are kept apart from our bugs (exit 70, traceback)."""

from __future__ import annotations

import pytest

from gather_verify import plane_check as check_module
from gather_verify.cli import main
from gather_verify.errors import InvalidInput

YARD = ["check", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--algorithm", "go-to-target"]


@pytest.mark.parametrize("argv, words", [
    (["check", "--robots", "0,x", "--meeting", "2,2"], "bad point '0,x'"),
    ([*YARD, "--property", "nope"], "unknown property 'nope'"),
    (["check", "--robots", "0,0", "--meeting", "2,2", "--algorithm", "nope"], "unknown algorithm"),
    (["check", "--robots", "0,0", "--meeting", "2,2", "--algorithm", "paper:alpha=x"],
     "bad option alpha='x'"),
])
def test_bad_input_is_one_line_and_exit_2(argv, words, capsys) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1 and words in err
    assert "Traceback" not in err


def test_an_internal_error_says_it_is_a_bug_prints_the_traceback_and_exits_70(
        monkeypatch, capsys) -> None:
    """A ValueError of ours is no longer taken for the user's mistake."""
    def broken(*args, **kwargs):
        raise ValueError("an invariant of ours does not hold")

    monkeypatch.setattr(check_module.theory, "not_applicable", broken)
    assert main(YARD) == 70
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err
    assert "ValueError: an invariant of ours does not hold" in err
    assert "bug of gather-verify" in err


def test_invalid_input_is_a_value_error_for_old_callers() -> None:
    from schedulers import get_scheduler

    with pytest.raises(InvalidInput, match="unknown scheduler 'nope'"):
        get_scheduler("nope")
    with pytest.raises(ValueError):
        get_scheduler("nope")


def test_ctrl_c_wrapped_by_c_code_is_an_interrupt(monkeypatch, capsys):
    """Ctrl-C while numba loads its kernels arrives as a SystemError caused by the
    KeyboardInterrupt: exit 130 and one line, not 'a bug of gather-verify'."""
    from gather_verify import cli

    def interrupted_inside_c(args):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as error:
            raise SystemError("<function _numba_unpickle> returned a result with an exception set") from error

    monkeypatch.setattr(cli, "build_parser", lambda *_: _parser_running(interrupted_inside_c))
    assert cli.main(["anything"]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("interrupted")


def _parser_running(run):
    import argparse

    p = argparse.ArgumentParser()
    p.add_argument("x")
    p.set_defaults(_run=run)
    return p


def _exception_classes() -> list[type[BaseException]]:
    """Every exception class defined in gather_verify and schedulers (each module imported)."""
    import importlib
    import inspect
    import pkgutil

    import gather_verify
    import schedulers

    found: dict[str, type[BaseException]] = {}
    for package in (gather_verify, schedulers):
        names = [package.__name__] + [m.name for m in pkgutil.walk_packages(
            package.__path__, package.__name__ + ".")]
        for name in names:
            module = importlib.import_module(name)
            for value in vars(module).values():
                if inspect.isclass(value) and issubclass(value, BaseException) \
                        and value.__module__ == name:
                    found[f"{name}.{value.__qualname__}"] = value
    return [found[k] for k in sorted(found)]


# deliberately BaseException, not the root: the user's `except Exception` must not swallow them
# (each says so in its docstring)
NOT_UNDER_THE_ROOT = {"gather_verify.watchdog.Overtime", "gather_verify.watchdog.ExitCalled",
                      "gather_verify.watchdog.OverMemory"}


def test_every_exception_of_the_package_derives_from_the_one_root() -> None:
    from gather_verify.errors import GatherVerifyError

    classes = _exception_classes()
    assert len(classes) >= 13  # the walk found the package's exceptions, not none of them
    names = {f"{c.__module__}.{c.__qualname__}" for c in classes}
    assert names >= NOT_UNDER_THE_ROOT
    for cls in classes:
        name = f"{cls.__module__}.{cls.__qualname__}"
        doc = (cls.__doc__ or "").lower()
        assert "cause" in doc and "fix" in doc, f"{name}: its docstring names no cause and fix"
        if name in NOT_UNDER_THE_ROOT:
            assert not issubclass(cls, Exception), f"{name} is no longer a BaseException only"
            assert "baseexception" in doc and "gatherverifyerror" in doc
        else:
            assert issubclass(cls, GatherVerifyError), f"{name} does not derive from the root"


def test_the_root_keeps_the_builtin_bases_callers_catch() -> None:
    from gather_verify.algorithms.moves import HiddenRead
    from gather_verify.errors import GatherVerifyError
    from gather_verify.model.view import MultiplicityHidden
    from gather_verify.paper.impossibility import AdversaryError
    from gather_verify.worlds.view import LightHidden

    assert issubclass(InvalidInput, ValueError)
    assert issubclass(MultiplicityHidden, LookupError) and issubclass(LightHidden, LookupError)
    assert issubclass(HiddenRead, LookupError) and issubclass(AdversaryError, AssertionError)
    assert issubclass(GatherVerifyError, Exception)


def test_a_missing_command_module_fails_loudly_as_a_bug(monkeypatch, capsys) -> None:
    """A command never vanishes from the CLI in silence: build_parser names the missing module
    and calls it a bug, and main exits 70 with the traceback."""
    from gather_verify import cli

    monkeypatch.setattr(cli, "COMMANDS", (*cli.COMMANDS, "no_such_command"))
    with pytest.raises(ImportError, match=r"gather_verify\.cli\.no_such_command is missing: a bug"):
        cli.build_parser()
    assert main(["check", "--help"]) == 70
    err = capsys.readouterr().err
    assert "a bug of gather-verify" in err and "no_such_command" in err
