"""Tables that fit 100 columns with the full names in a legend (issue 41): the terminal's
table cuts a longer name at a word with a reference to its full name below, and the
tolerance table shows short names, each interval on its own row, and only the
percentiles the ensemble answers."""
from __future__ import annotations

import contextlib

from toothfem.report import summary as report_summary
from toothfem.report.tolerance_table import INTERVAL_ROW, screen_table
from toothfem.tolerance_result import rings_needed

from tests.test_tolerance_report import synthetic


def _widest(text: str) -> int:
    return max(len(line) for line in text.splitlines())


def test_a_wide_table_is_cut_with_its_names_in_a_legend():
    """Names too long for 100 columns beside the numbers are cut at a word (no bracket
    left open) with [n]; each full name below, every line within the width; the numbers
    untouched. A table that fits is left as it is."""
    long = ("largest pin force in the reducer (system model: every disc free on its "
            "supports, the split between them solved over the pairing period)")
    rows = [(long, "N", {"ours": 87.13, "published": 90.0}),
            ("  its peak to peak over one pitch at the run's positions (the full period: "
             "toothfem stiffness, which takes every pitch)", "arcsec", {"ours": 0.4586}),
            ("short", "N m", {"ours": 40.0})]
    out = report_summary.text(rows, "a title " * 30)
    assert _widest(out) <= report_summary.WIDTH
    lines = out.splitlines()
    assert any(line.startswith("largest pin force in the reducer [1] ") for line in lines)
    assert any(line.startswith("  its peak to peak over one pitch at the run's positions [2]")
               for line in lines)
    legend = "\n".join(lines[lines.index(next(x for x in lines if x.startswith("[1]: "))):])
    assert " ".join(legend.split()).startswith("[1]: " + long)
    assert "[2]: its peak to peak" in legend
    assert "87.13" in out and "0.4586" in out
    narrow = [("short", "N m", {"ours": 40.0})]
    assert report_summary.text(narrow) == "\n".join(
        ["quantity  unit  ours", "--------  ----  ----", "short     N m     40"])


def test_tolerance_screen_table_gives_only_what_it_answers():
    """40 reducers answer P50 and P90/P10, not P99/P1 (368): no such column, a note with
    the count; each percentile's interval on the row below it; the full labels in the
    legend; the table within 100 columns. 400 reducers answer every tail: the backlash a
    row per side (low: interference, high: play)."""
    r = synthetic(40)
    rows, legend, note = screen_table(r.summary(), r.outputs())
    columns = {c for _, _, cells in rows for c in cells}
    assert "1 in 10 worse" in columns and "1 in 100 worse" not in columns
    assert note.endswith(f"(--samples {rings_needed(0.99)})") and "P99 and P1 need 368" in note
    force = next(i for i, row in enumerate(rows) if row[0] == "max force")
    assert rows[force][2]["1 in 10 worse"].startswith("P90 ")
    assert rows[force + 1][0] == INTERVAL_ROW
    assert rows[force + 1][2]["median"].startswith("[")
    assert legend["max force"] == r.outputs()["max_force_N"][0]
    out = report_summary.text(rows, "title", legend=legend)
    assert _widest(out) <= report_summary.WIDTH
    big = synthetic(400)
    rows, legend, note = screen_table(big.summary(), big.outputs())
    assert note == ""
    names = [name for name, _, _ in rows]
    assert "backlash, low" in names and "backlash, high" in names
    high = rows[names.index("backlash, high")][2]
    assert high["1 in 10 worse"].startswith("P90 ") and high["1 in 100 worse"].startswith("P99 ")
    assert _widest(report_summary.text(rows, "title", legend=legend)) <= report_summary.WIDTH


def test_default_ensemble_answers_what_it_prints(cases_dir, tmp_path, monkeypatch):
    """The command's default ensemble (issue 41): enough reducers for the median and the
    P90/P10 with their intervals; no one-tolerance runs below 80 reducers (a quarter of
    them is fewer than 20 a tolerance), a quarter from there on; the command passes the
    default to the analysis."""
    from toothfem import cli, tolerance

    assert tolerance.DEFAULT_SAMPLES >= rings_needed(0.9) == rings_needed(0.1)
    assert rings_needed(0.99) > tolerance.DEFAULT_SAMPLES
    assert [tolerance.default_share_samples(n) for n in (40, 79, 80, 200)] == [0, 0, 20, 50]
    seen = {}

    class Stop(Exception):
        pass

    def fake(case, **kw):
        seen.update(kw)
        raise Stop
    monkeypatch.setattr(tolerance, "tolerance_analysis", fake)
    with contextlib.suppress(Stop):     # the CLI may report the stop as its own failure
        cli.main(["tolerance", str(cases_dir / "rv40e.toml"), "--out", str(tmp_path / "t")])
    assert seen["samples"] == tolerance.DEFAULT_SAMPLES and seen["share_samples"] is None


def test_tolerance_command_prints_within_100_columns(cases_dir, tmp_path, capsys):
    """The command's table, legend and notes on a real ensemble: every line but the
    warnings within 100 columns; the tails it cannot answer said with their counts; no
    one-tolerance runs said."""
    from toothfem import cli

    assert cli.main(["tolerance", str(cases_dir / "cycloid_pinhousing.toml"), "--samples",
                     "6", "--positions", "6", "--out", str(tmp_path / "t")]) == 0
    out = capsys.readouterr().out
    lines = [x for x in out.splitlines() if not x.startswith(("warning:", "wrote "))]
    assert max(len(x) for x in lines) <= report_summary.WIDTH
    assert "P90 and P10 need 36; P99 and P1 need 368 (--samples 368)" in " ".join(out.split())
    assert "variance shares: not run" in out
    assert any(x.startswith("max force: largest pin force on any disc") for x in lines)


def test_check_and_efficiency_print_within_100_columns(cases_dir, capsys):
    """check's convention and long values, efficiency's sources and notes: wrapped within
    100 columns (the warnings are prose and stay one line each)."""
    from toothfem import cli

    for argv in (["check", str(cases_dir / "rv40e.toml")],
                 ["efficiency", str(cases_dir / "cycloid_khv.toml")]):
        assert cli.main(argv) == 0
        out = capsys.readouterr().out
        lines = [x for x in out.splitlines() if not x.startswith("warning:")]
        assert max(len(x) for x in lines) <= report_summary.WIDTH, argv[0]
    assert "source: pin_contacts: pin-disc contacts: EHL (Xu 2007)" in out
