"""The TE loop's long runs (issue 39): the model's TE in two processes and from warm starts
gives the numbers of one process from cold starts, a loop stopped after a step resumes from
its journal, and a model that cannot reach the measured widths is said so with its best
effect and what the widths need."""
import numpy as np
import pytest

from toothfem.efficiency.loop.te.model import RecordingModel
from toothfem.efficiency.loop.te.model_records import Effects

#: Torques of the model checks [N m]: zero (the running losses alone), the knee, the rating.
TORQUES = (0.0, 90.6, 407.9)


def _widths(runs) -> np.ndarray:
    return np.array([r.width_arcsec for r in runs])


def test_two_processes_and_warm_starts_give_the_cold_single_process_numbers(cases_dir):
    """Without warm starts a call's numbers are a fresh model's bit for bit whatever came
    before; with them (from a near call's states and from the torque before) and in two
    processes, the widths of a fresh model's cold solve within 1e-3 arcsec (the Newton
    solve's own tolerance: RTOL 1e-8 of the coordinates, a twist of some 1000 arcsec;
    measured 5e-4 at most), and the two processes' bit for bit the one process's from the
    same history."""
    from toothfem import load_case

    case = load_case(cases_dir / "rv40e.toml")
    history = [Effects(crank_bearing_play_m=5e-6), Effects(crank_bearing_play_m=5.05e-6),
               Effects(friction_scale=1.3), Effects(crank_bearing_play_m=5.1e-6)]
    cold = [_widths(RecordingModel(case).te(e, TORQUES)) for e in history]
    again = RecordingModel(case)              # without warm starts: no call moves another
    for e, c in zip(history, cold):
        np.testing.assert_array_equal(_widths(again.te(e, TORQUES)), c)
    one = RecordingModel(case, warm_starts=True)
    with RecordingModel(case, workers=2, warm_starts=True) as two:
        for e, c in zip(history, cold):
            a, b = one.te(e, TORQUES), two.te(e, TORQUES)
            np.testing.assert_array_equal(_widths(a), _widths(b))
            for x, y in zip(a, b):
                np.testing.assert_array_equal(x.te_forward_rad, y.te_forward_rad)
                np.testing.assert_array_equal(x.te_backward_rad, y.te_backward_rad)
            np.testing.assert_allclose(_widths(a), c, rtol=0, atol=1e-3)
    with pytest.raises(ValueError, match="workers = 3 is outside the valid range"):
        RecordingModel(case, workers=3)


def test_a_loop_stopped_after_its_first_step_resumes_from_the_journal(cases_dir, tmp_path,
                                                                      capsys):
    """te-loop stopped as its first step is kept (the step's hook raising, as a kill
    there): the same command reads the step's evaluations back from the journal, goes
    through that step again without the model and ends with the fit the step made."""
    import json

    from toothfem import cli
    from toothfem.efficiency.loop.te import problem

    folder = cases_dir.parent / "data" / "demo" / "te" / "rv40e_running"
    out = tmp_path / "loop"
    args = ["te-loop", str(cases_dir / "rv40e.toml"), "--te", str(folder), "--effects",
            "crank_bearing_play,friction", "--workers", "1", "--out", str(out)]
    real = problem.TeProblem.run
    kept = []

    def stopped(self, candidates=None, progress=False, on_step=None, replay=()):
        def hand_on(i, record):
            on_step(i, record)                  # the command's: kept on disk
            kept.append(record)
            raise KeyboardInterrupt             # stopped right after the step is kept
        return real(self, candidates, progress, hand_on, replay)

    problem.TeProblem.run = stopped
    try:
        assert cli.main(args) != 0
    finally:
        problem.TeProblem.run = real
    assert not out.exists() and len(kept) == 1
    first = kept[0]
    assert first["added"] == "crank_bearing_play" and first["evaluations"]
    capsys.readouterr()
    assert cli.main(args) == 0
    said = capsys.readouterr().out
    assert f"resuming: 1 finished selection steps kept beside {out} " \
           f"({len(first['evaluations'])} model evaluations read back)" in said
    report = json.loads((out / "report.json").read_text())
    assert report["replayed_evaluations"] == len(first["evaluations"])
    # the step gone through again from the journal: the same fit, bit for bit
    assert report["steps"][0]["added"] == "crank_bearing_play"
    assert report["final"]["values"]["crank_bearing_play"] == \
        first["values"]["crank_bearing_play"]
    # only the second step's evaluations were made again (its candidate, friction)
    assert 0 < report["model_evaluations"] < len(first["evaluations"])
    assert not [p for p in tmp_path.iterdir() if ".journal-" in p.name]


def test_a_plain_value_error_of_the_model_is_a_bug_not_bad_input(cases_dir, tmp_path, capsys,
                                                                  monkeypatch):
    """Issue 39: a ValueError from inside the loop's model is an internal error (exit 3,
    'a bug: please report it'), not the user's bad input (exit 2); the user's own bad input
    (a candidate name the API does not know) is still refused as such."""
    from toothfem import cli
    from toothfem.efficiency.loop.te import problem
    from toothfem.efficiency.loop.te.loop import candidate_names
    from toothfem.errors import ToothfemError

    def broken(self, *a, **k):
        raise ValueError("operands could not be broadcast together")

    monkeypatch.setattr(problem.TeProblem, "run", broken)
    folder = cases_dir.parent / "data" / "demo" / "te" / "rv40e_running"
    code = cli.main(["te-loop", str(cases_dir / "rv40e.toml"), "--te", str(folder),
                     "--effects", "friction", "--out", str(tmp_path / "loop")])
    err = capsys.readouterr().err
    assert code == 3 and "internal error: ValueError" in err and "a bug" in err
    assert not (tmp_path / "loop").exists()
    with pytest.raises(ToothfemError, match="'ring'"):
        candidate_names((), "ring")


def test_a_model_twice_too_soft_is_said_with_its_best_effect_and_what_the_widths_need(
        cases_dir, tmp_path):
    """Running recordings of the case with every part twice as stiff, fitted with the mesh's
    stiffness alone (a factor up to 3): the mesh cannot double the reducer's rigidity, so
    the loop stops naming the mesh at its bound with what it would cut, and the widths'
    reading says the rigidity they need against the model's and the factor, never "nothing
    helps"."""
    from toothfem import load_case
    from toothfem.commands.te_loop import running_lines
    from toothfem.efficiency.loop.te.loop import run_te_loop
    from toothfem.efficiency.loop.te.synthetic_model import Noise, write_synthetic_recordings
    from toothfem.fem.drives.assembly import SCALABLE

    case = load_case(cases_dir / "rv40e.toml")
    model = RecordingModel(case)
    torques = [45.0 * k for k in range(11)]      # 11 rows: the loop needs min_points + 2
    write_synthetic_recordings(tmp_path, case,
                               Effects(stiffness_scale={p: 2.0 for p in SCALABLE}), torques,
                               model=model, noise=Noise(seed=4), shapes=("W",),
                               revolutions=1, samples_per_revolution=3600)
    model.warm_starts = True                  # the fit's calls from each other's states
    result = run_te_loop(case, te=tmp_path, candidates=["stiffness_mesh"], model=model)
    loop = result.loop
    assert loop.added == ()
    # the mesh three times as stiff (its bound) lowers BIC by about 1 (the loop needs 10)
    assert "stiffness_mesh, at stiffness_factor = 3 (its bound)" in loop.stop_reason
    need = [line for line in running_lines(result) if line.startswith("the widths need a "
                                                                      "rigidity of")]
    measured = result.running.rigidity_Nm_per_arcmin
    model_k = result.model_running("after").rigidity_Nm_per_arcmin
    assert len(need) == 1 and f"{measured:.4g} N m/arcmin" in need[0]
    assert f"gives {model_k:.4g}" in need[0] and "which no fitted effect reaches" in need[0]
    assert measured > 1.5 * model_k             # about twice as stiff as the model
