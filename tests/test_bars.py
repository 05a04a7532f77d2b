"""Progress: a bar on a terminal, one line per finished stage elsewhere (issue 25: bars
flooded logs)."""
from __future__ import annotations

import io

import pytest

from toothfem.bars import PROGRESS_PREFIX, bar, stage


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


def test_a_long_stage_asked_for_it_writes_lines_inside_itself():
    out = io.StringIO()
    with bar(total=3, file=out, desc="TE loop step 1", unit="candidate", every_s=0.0) as b:
        b.set_postfix_str("5 model evaluations; fitting friction")
        b.update(1)
    lines = out.getvalue().splitlines()
    assert lines[0] == (PROGRESS_PREFIX + "TE loop step 1: 0 of 3 candidates so far in "
                        + lines[0].split(" in ")[1])
    assert lines[0].endswith("s (5 model evaluations; fitting friction)")
    assert "1 of 3 candidate so far in" in lines[1]
    assert "so far" not in lines[-1] and "1 of 3 candidate in" in lines[-1]
    out = io.StringIO()                       # not asked: the end's line only
    with bar(total=3, file=out, desc="x", unit="candidate") as b:
        b.set_postfix_str("y")
        b.update(1)
    assert len(out.getvalue().splitlines()) == 1


def test_a_terminal_bar_takes_every_s_without_passing_it_to_tqdm():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    out = Terminal()
    with bar(total=2, file=out, desc="x", every_s=0.0) as b:
        b.update(2)
    assert "2/2" in out.getvalue() and PROGRESS_PREFIX not in out.getvalue()


def test_a_stage_without_a_count_says_when_it_is_done():
    """bars.stage: off a terminal one line at its end with its time; on a terminal also its
    name when it starts; nothing when it is left by an error."""
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    out = io.StringIO()
    with stage("datasheet", stream=out):
        pass
    (line,) = out.getvalue().splitlines()
    assert line.startswith(PROGRESS_PREFIX + "datasheet: done in ") and line.endswith(" s")
    term = Terminal()
    with stage("datasheet", stream=term):
        assert term.getvalue() == "datasheet ...\n"
    assert term.getvalue().splitlines()[1].startswith(PROGRESS_PREFIX + "datasheet: done")
    out = io.StringIO()
    with pytest.raises(RuntimeError), stage("x", stream=out):
        raise RuntimeError("stop")
    assert out.getvalue() == ""
