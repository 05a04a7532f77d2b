"""Progress: a bar on a terminal, one line per finished stage elsewhere (issue 25: bars
flooded logs)."""
from __future__ import annotations

import io

import pytest

from toothfem.bars import PROGRESS_PREFIX, bar


def test_off_a_terminal_each_stage_is_one_line():
    out = io.StringIO()                       # not a TTY, as a log file or a pipe
    assert list(bar(range(3), file=out, desc="cycle mode", unit="position")) == [0, 1, 2]
    (line,) = out.getvalue().splitlines()
    assert line.startswith(PROGRESS_PREFIX + "cycle mode: 3 positions in ")
    out = io.StringIO()
    with bar(total=5, file=out, desc="tolerance", unit="ring") as b:
        b.update(2)
    assert "tolerance: 2 of 5 rings" in out.getvalue()


def test_a_stage_left_by_an_error_writes_no_line_and_disabled_writes_nothing():
    out = io.StringIO()
    with pytest.raises(RuntimeError), bar(total=4, file=out, desc="x") as b:
        b.update()
        raise RuntimeError("stop")
    assert out.getvalue() == ""
    out = io.StringIO()
    assert list(bar(range(2), enabled=False, file=out)) == [0, 1]
    assert out.getvalue() == ""


def test_a_bar_shows_on_a_terminal():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    out = Terminal()
    assert list(bar(range(3), file=out, desc="x")) == [0, 1, 2]
    assert "x" in out.getvalue() and "3/3" in out.getvalue()
    assert PROGRESS_PREFIX not in out.getvalue()
