"""The demonstration rig data of data/demo/ (issue 23 item 5): what data/demo/generate.py
writes, declared synthetic in its header, and the README's command on it."""
import importlib.util
import json
import re

import numpy as np
import pytest

from toothfem import load_case
from toothfem.efficiency.loop.measured import load_measured, parse_measured

ROOT = __import__("pathlib").Path(__file__).resolve().parent.parent
DEMO = ROOT / "data" / "demo"


def _generator():
    spec = importlib.util.spec_from_file_location("demo_generate", DEMO / "generate.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


GEN = _generator()


@pytest.mark.parametrize("name", GEN.SETS)
def test_shipped_demo_data_is_what_the_script_writes(name, cases_dir):
    """Each shipped file holds what generate.py computes now (to the CSV's 10 digits), says
    in its header that it is synthetic, which effect it holds and the noise, and loads with
    its case."""
    text, prov = GEN.demo_data(name)
    case = load_case(cases_dir / f"{name}.toml")
    shipped = load_measured(DEMO / f"{name}_synthetic.csv", ratio=case.ratio())
    now = parse_measured(text, ratio=case.ratio())
    for col in ("speed_rpm", "torque_Nm", "efficiency", "input_torque_Nm", "time_h"):
        np.testing.assert_allclose(getattr(shipped, col), getattr(now, col), rtol=1e-9)
    header = (DEMO / f"{name}_synthetic.csv").read_text().split("input_speed_rpm")[0]
    effect = GEN.SETS[name][0]
    assert "synthetic" in header and f"effect: {effect}" in header and "noise:" in header
    assert json.loads((DEMO / f"{name}_synthetic.json").read_text())["truth"] == json.loads(
        json.dumps(prov["truth"]))
    assert len(shipped) == GEN.ROWS and shipped.sigma is not None    # the sensors' sigma


def test_readme_demo_command(tmp_path, capsys):
    """The README's `toothfem loop` on the sine demo, the efficiency loop end to end (the
    engine's rules are tests/test_engine.py's): the windage named with its value, the
    held-out error cut as the README says (its figures rounded as printed there); with
    --json the command prints report.json's content, alias groups included, and nothing
    else; report.md, the residual plots and the final case's fields are written; each step
    names the covariate the residual follows most (the last as the final trends say), and
    the candidates that would help only at their parameter's bound are said so."""
    from toothfem import cli

    readme = (ROOT / "README.md").read_text()
    line = re.search(r"toothfem loop (cases/sine_prototype.toml \S+) --out", readme)
    case, csv = line.group(1).split()
    out = tmp_path / "loop_sine"
    assert cli.main(["loop", str(ROOT / case), str(ROOT / csv), "--out", str(out),
                     "--json"]) == 0
    rep = json.loads((out / "report.json").read_text())
    assert json.loads(capsys.readouterr().out) == rep and "alias_groups" in rep
    assert [e["name"] for e in rep["effects"]] == ["windage"]
    windage = rep["effects"][0]["parameters"]["windage_torque_Nmm"]["value"]
    assert windage == pytest.approx(GEN.SETS["sine_prototype"][1][0], rel=0.05)
    assert rep["final_case_fields"]["friction.windage_torque_Nmm"] == pytest.approx(windage)
    before, after = (float(x) for x in re.search(
        r"held-out\s+error from ([\d.]+) to ([\d.]+) points", readme).groups())
    assert 100 * rep["baseline"]["rmse"] == pytest.approx(before, abs=0.05)
    assert 100 * rep["final"]["rmse"] == pytest.approx(after, abs=0.005)
    assert rep["baseline"]["rmse"] >= 3 * rep["final"]["rmse"]
    assert rep["n_rows"] == rep["n_points"] and rep["notes"] == [] and rep["binning"] is None
    steps = rep["steps"]
    assert len(steps) >= 2 and all(s["residual_follows_most"]["covariate"] for s in steps)
    last = max((t for t in rep["trends_after"] if t["r2"] is not None),
               key=lambda t: (t["follows"], t["r2"]))
    assert steps[-1]["residual_follows_most"] == last
    assert last["follows"] == bool(rep["unexplained"])
    assert steps[0]["bounded"] and all(c["bounded"] for c in steps[0]["candidates"]
                                      if c["name"] in steps[0]["bounded"])
    text = (out / "report.md").read_text()
    assert "held-out RMSE" in text and "windage" in text
    assert "After this step the residual" in text and "no, at its bound" in text
    for png in ("residuals_before.png", "residuals_after.png"):
        assert (out / png).stat().st_size > 10_000
