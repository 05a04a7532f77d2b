"""Derived quantities of a case: what `toothfem check` prints (units in the key names)."""
from __future__ import annotations



from .case import Case
from .case_consistency import consistency
from .efficiency import evaluate, operating_point
from .errors import ToothfemError
from .units import rpm_to_rad_s


#: The sign convention of every ratio `check` prints (toothfem.geometry.train), said once.
RATIO_CONVENTION = ("ratios are i = n_input / n_output, signed: i > 0 when the output turns "
                    "with the input, i < 0 against it (case files state |i|)")


def derived(case: Case) -> dict:
    """A flat mapping of the quantities an engineer checks first, per drive.

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    dict
        Units in the key names: the signed ratio (:data:`RATIO_CONVENTION`), output speed,
        the operating point's torques, powers and efficiency (analytic loads), each drive's
        geometry and train figures, and ``warnings`` (an operating point above a declared
        rating; a quantity that could not be derived).
    """
    out: dict = {"name": case.name, "drive": case.drive,
                 "ratio_sign_convention": RATIO_CONVENTION, "ratio": _r(case.ratio())}
    op = case.operating
    out["output_speed_rpm"] = _r(op.input_speed_rpm / case.ratio())
    warnings: list[str] = []
    out.update(_operating(case, warnings))
    out.update(case.layout.derived_rows(case))
    if out.get("interference_before_load_um", 0) > 0:
        warnings.append(f"the disc interferes with its pins by {out['interference_before_load_um']:.4g}"
                        f" um before load (pins {out['interference_pins']}, '+': the flank "
                        "of a positive disc torque) wherever it is turned: both flanks are "
                        "preloaded on assembly")
    warnings += consistency(case, out)
    out["warnings"] = warnings
    return out


def _operating(case: Case, warnings: list) -> dict:
    """Torques [N m], powers [W] and efficiency at the operating point (analytic loads,
    the case's efficiency model), and the rating check."""
    op = case.operating
    try:
        e = evaluate(case, *operating_point(case))
    except ToothfemError as exc:
        warnings.append(f"operating point not derived: {exc}")
        return {}
    speed, torque = float(e.speed_rpm[0]), float(e.torque_Nm[0])
    p_in, p_out = float(e.input_power_W[0]), float(e.output_power_W[0])
    d = {"operating_input_speed_rpm": _r(speed),
         "operating_output_torque_Nm": _r(torque),
         "operating_input_torque_Nm": _r(p_in / rpm_to_rad_s(speed)),
         "operating_input_power_W": _r(p_in),
         "operating_output_power_W": _r(p_out),
         "operating_efficiency_analytic": _r(float(e.efficiency[0]), 6)}
    rated = op.rated_torque_Nm
    if rated is not None:
        d["rated_torque_Nm"] = rated
        if torque > rated:
            warnings.append(f"the operating point's output torque {torque:.4g} N m is "
                            f"{torque / rated:.2f} x the rated {rated:g} N m "
                            "(operating.rated_torque_Nm)")
    return d


def _r(x, digits=10):
    return float(f"{x:.{digits}g}")


