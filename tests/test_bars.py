"""Progress bars show on a terminal only (issue 25: they flooded logs)."""
from __future__ import annotations

import io

from toothfem.bars import bar


def test_a_bar_is_silent_off_a_terminal_and_when_disabled():
    out = io.StringIO()                       # not a TTY, as a log file or a pipe
    assert list(bar(range(3), file=out, desc="x")) == [0, 1, 2]
    assert out.getvalue() == ""
    assert bar(range(2), enabled=False).disable


def test_a_bar_shows_on_a_terminal():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    out = Terminal()
    assert list(bar(range(3), file=out, desc="x")) == [0, 1, 2]
    assert "x" in out.getvalue() and "3/3" in out.getvalue()
