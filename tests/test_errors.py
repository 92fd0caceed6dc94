"""The user's mistakes (exit 2, one line) are kept apart from our bugs (exit 70, traceback)."""

from __future__ import annotations

import pytest

from gather_verify import check as check_module
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

    monkeypatch.setattr(check_module, "classify_configuration", broken)
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

    monkeypatch.setattr(cli, "build_parser", lambda: _parser_running(interrupted_inside_c))
    assert cli.main(["anything"]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("interrupted")


def _parser_running(run):
    import argparse

    p = argparse.ArgumentParser()
    p.add_argument("x")
    p.set_defaults(_run=run)
    return p
