"""The accuracy life of a cycloid or RV reducer, as a Python call: ``wear_analysis`` steps
the hours of the case's duty cycle, wears every pin contact, crank and support bearing and
output pin by Archard's law (efficiency/wear.py, efficiency/wear_contacts.py) at the loads the system
model solves with the clearances worn so far, and reports the lost motion, backlash, TE and
efficiency against the hours (what ``toothfem wear`` calls; docs/wear.md).

The clearances enter the system model as they are built into it: the disc flanks' and pins'
wear as an equidistant modification of the disc on the same FE tables (the design search's
``geometry``), the bearings' as their diametral play (the crank bearings' ``variant``
option; the support bearings' roller law with the play), the output pins' as their holes'
radius. A wear coefficient of zero leaves
every figure as at 0 h.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .case import Case, as_case
from .errors import CaseError, GeometryError, check_range
from .efficiency import rated_output_torque
from .efficiency.evaluation import evaluate, operating_point
from .efficiency.no_load import path_friction
from .efficiency.wear import DEFAULT_K, check_coefficient
from .efficiency.wear_contacts import bearing_wear, output_pin_wear, pin_disc_wear
from .efficiency.drive_losses import disc_contact_losses
from .efficiency.mesh_table import table_from_records
from .fem.datasheet.sheet import backlash_arcmin, lost_motion_arcmin, LOST_MOTION_FRACTION
from .fem.contact import ContactError
from .fem.drives import MAX_POSITIONS, drive_for
from .fem.drives.assembly import SUPPORT_ANGLE_DEG, SUPPORT_LENGTH_REL, SUPPORT_ROLLERS
from .fem.system.datasheet import SystemTwist
from .fem.system.elements import RollerBearing
from .geometry.cycloid import CycloidGeometry
from .units import ARCMIN, ARCSEC, RAD_S_PER_RPM

#: Steps over the hours by default, on a grid t_k = H (k/n)^2 (dense where the run-in is
#: fast), and the positions per pin pitch of the system model (the RV-40E's lost motion at
#: 0 h is ``stiffness``'s at its 36 to 1e-4 arcmin: tests/test_wear.py).
DEFAULT_STEPS, DEFAULT_POSITIONS = 12, 12
#: The longest run asked for [h] (a reducer's life is 6000-20000 h; 1e6 h is a century).
MAX_HOURS = 1e6
#: The torques of the backlash's twists where the datasheet's does not settle [N m].
BACKLASH_TORQUES_NM = (1e-2, 1e-1)
#: The clearances the wear opens, by the system model's part.
CLEARANCES = ("mesh", "crank bearings", "support bearings", "output pins")


@dataclass(frozen=True)
class WearState:
    """The worn clearances at one time [m]: the equidistant modification the pins' and
    flanks' wear adds, and the crank and support bearings' diametral play; the depth each
    pair has lost (the roughness's run-in)."""
    clearance_m: dict = field(default_factory=lambda: {c: 0.0 for c in CLEARANCES})
    depth_m: dict = field(default_factory=lambda: {c: 0.0 for c in CLEARANCES})

    def advanced(self, rates: dict, hours: float) -> WearState:
        """This state after ``hours`` at the rates.

        Parameters
        ----------
        rates : dict
            Part of CLEARANCES -> (clearance, depth) growth [m/h].
        hours : float
            [h].

        Returns
        -------
        WearState
        """
        return WearState({c: self.clearance_m[c] + hours * rates[c][0] for c in CLEARANCES},
                         {c: self.depth_m[c] + hours * rates[c][1] for c in CLEARANCES})


@dataclass(frozen=True, kw_only=True)
class WearResult:
    """The accuracy life of a case: one ``history`` row per time (hours, lost motion with
    its parts, backlash, TE, efficiency, the clearances and the contacts' regimes)."""
    case_name: str
    hours: float
    wear_coefficient: float
    coefficient_source: str
    lost_motion_limit_arcmin: float | None
    history: list
    notes: tuple = ()

    @property
    def hours_to_limit(self) -> float | None:
        """The hours at which the lost motion reaches the limit (linear between the rows),
        None without a limit or where the run does not reach it."""
        lim = self.lost_motion_limit_arcmin
        if lim is None:
            return None
        rows = self.history
        if rows[0]["lost_motion_arcmin"] >= lim:
            return 0.0
        for a, b in zip(rows, rows[1:]):
            if b["lost_motion_arcmin"] >= lim:
                da = b["lost_motion_arcmin"] - a["lost_motion_arcmin"]
                return a["hours"] + (lim - a["lost_motion_arcmin"]) / da \
                    * (b["hours"] - a["hours"])
        return None

    def summary(self) -> dict:
        """The key figures and the history (JSON-ready).

        Returns
        -------
        dict
        """
        first, last = self.history[0], self.history[-1]
        return {"case": self.case_name, "hours": self.hours,
                "wear_coefficient": self.wear_coefficient,
                "wear_coefficient_source": self.coefficient_source,
                "lost_motion_limit_arcmin": self.lost_motion_limit_arcmin,
                "hours_to_lost_motion_limit": self.hours_to_limit,
                "lost_motion_growth": (last["lost_motion_arcmin"]
                                       / first["lost_motion_arcmin"] - 1.0),
                "history": self.history, "notes": list(self.notes)}

    def table(self) -> list:
        """The rows every table shows.

        Returns
        -------
        list of (str, str)
            Quantity with its unit, and the value (:func:`toothfem.report.wear.wear_rows`).
        """
        from .report.wear import wear_rows
        return wear_rows(self)

    def plot(self) -> dict:
        """The pictures.

        Returns
        -------
        dict
            File name -> matplotlib Figure (:func:`toothfem.report.wear.wear_figures`).
        """
        from .report.wear import wear_figures
        return wear_figures(self)

    def write(self, folder) -> dict:
        """The files into an existing folder.

        Parameters
        ----------
        folder : path

        Returns
        -------
        dict
            The summary with the names of the files written
            (:func:`toothfem.report.wear.write_wear`).
        """
        from .report.wear import write_wear
        return write_wear(self, folder)


def hour_grid(hours: float, steps: int) -> np.ndarray:
    """The times of the run: t_k = H (k/n)^2, k = 0..n.

    Parameters
    ----------
    hours : float
    steps : int

    Returns
    -------
    numpy.ndarray, shape (steps + 1,)
    """
    return hours * (np.arange(steps + 1) / steps) ** 2


class WornReducer:
    """The case's system model with worn clearances: its loads, figures and wear rates at
    a :class:`WearState` (one FE table set for all: the clearances shift gaps and plays).

    Parameters
    ----------
    case : toothfem.case.Case
    positions : int
        Positions per pin pitch.
    k_boundary : float
        K_b [-].
    """

    def __init__(self, case: Case, positions: int, k_boundary: float):
        self.case, self.si = case, case.to_si()
        self.drive = drive_for(case)
        geometry = getattr(self.drive, "geometry", None)
        if not isinstance(geometry, CycloidGeometry):
            raise CaseError(f"case.drive = {case.drive!r}: the wear model turns worn flanks "
                            "into a cycloid disc's equidistant modification; valid: a "
                            "cycloid or RV case")
        self.geometry0 = geometry
        supports = self.drive.supports(self.si.supports)
        # a cycloid disc's system (CycloidSystem: its plays, bearings and mesh)
        self.base: Any = self.drive.system_model(supports, positions)
        self.friction = path_friction(self.si, self.drive)
        self.rated, _ = rated_output_torque(self.si)
        self.k_boundary = k_boundary
        speed = self.drive.speeds()
        duty = self.si.duty_cycle
        if duty:
            self.duty = [(abs(d.output_torque_Nm), abs(d.input_speed_rad_s), d.time_share)
                         for d in duty]
        else:
            rpm, torque = operating_point(self.si)
            self.duty = [(abs(torque), rpm * RAD_S_PER_RPM, 1.0)]
        self.crank_per_input = abs(speed["crank"])
        sets = {b.name: b for b in self.drive.layout.bearing_set(self.si, self.drive)}
        self.bearings = {"crank bearings": next((b for n, b in sets.items()
                                                 if "crank_bearing" in n or "eccentric" in n),
                                                None),
                         "support bearings": sets.get("crank_support_bearings")}
        self.d_shaft = supports.crankshaft_diameter_m
        self._base_losses: tuple[float, float, float] | None = None

    def system(self, state: WearState):
        """The system model and the disc's geometry with the worn clearances.

        Parameters
        ----------
        state : WearState

        Returns
        -------
        system : toothfem.fem.drives.assembly.CycloidSystem
            A variant of the case's, on its tables.
        geometry : toothfem.geometry.cycloid.CycloidGeometry
            The disc with the mesh's clearance added to its equidistant modification.
        """
        c = state.clearance_m
        sys_ = self.base.variant(crank_bearing_play_m=self.base.crank_bearing_play_m
                                 + c["crank bearings"])
        if c["support bearings"] and self.bearings["support bearings"] is not None:
            # the support bearings' law with the play (the variant built it with none; the
            # system asks its parts' laws when it first solves)
            sys_.support_bearing = RollerBearing(
                SUPPORT_ROLLERS, SUPPORT_LENGTH_REL * self.d_shaft,
                play_m=c["support bearings"], contact_angle_rad=math.radians(SUPPORT_ANGLE_DEG))
        om = getattr(sys_.path, "output_mechanism", None)
        if c["output pins"] and om is not None:
            # the holes' radius grown by the pins' and holes' wear (the path's gap)
            hole = om.hole_radius_m if om.hole_radius_m is not None \
                else om.contact_radius_m + self.geometry0.eccentricity_m
            sys_.path = dataclasses.replace(sys_.path, output_mechanism=dataclasses.replace(
                om, hole_radius_m=hole + c["output pins"]))
        geom = dataclasses.replace(self.geometry0,
                                   equidistant_m=self.geometry0.equidistant_m + c["mesh"])
        return sys_, geom

    def twist(self, state: WearState) -> SystemTwist:
        """The worn reducer's twist model (friction in the path, as the datasheet's).

        Parameters
        ----------
        state : WearState

        Returns
        -------
        SystemTwist
        """
        sys_, geom = self.system(state)
        return SystemTwist(sys_, friction=self.friction, geometry=geom)

    def rates(self, state: WearState, twist: SystemTwist | None = None) -> tuple:
        """Each clearance's growth and each pair's depth per hour of the duty cycle, and the
        contacts' wear records at its first row.

        Parameters
        ----------
        state : WearState
        twist : SystemTwist, optional
            The worn reducer's (:meth:`twist` of ``state``), if built already.

        Returns
        -------
        rates : dict
            Part -> (clearance, depth) [m/h].
        records : list of ContactWear
        """
        twist = self.twist(state) if twist is None else twist
        sys_: Any = twist.system
        rates = {c: np.zeros(2) for c in CLEARANCES}
        records = []
        for row, (torque, speed, share) in enumerate(self.duty):
            states = twist.states(torque)
            crank = speed * self.crank_per_input
            # the first disc's contacts (its record's pins are its meshing's); the balanced
            # layout's discs carry alike (the datasheet's split), so each wears as it does
            slot = sys_.slots[0]
            rec = sys_.member_record(0, states)
            ms = self.drive.meshing(slot.solver.positions_rad)
            turn = sys_.mesh.turn_ratio * np.asarray(slot.solver.positions_rad)
            w = pin_disc_wear(self.si, self.drive, rec, ms, crank_speed_rad_s=crank,
                              k_boundary=self.k_boundary, worn_depth_m=state.depth_m["mesh"],
                              disc_turn_rad=turn)
            rates["mesh"] += share * np.array([w.clearance_m_per_h,
                                               sum(w.depth_m_per_h.values())])
            if row == 0:
                records.append(w)
            for part, names in (("crank bearings", [n for k in sys_.bearing_names for n in k]),
                                ("support bearings", [n for k in sys_.support_names
                                                     for n in k.values()])):
                bearing = self.bearings[part]
                if bearing is None:
                    continue
                for name in names:
                    load = [float(np.linalg.norm(s.bearing_force_N[name])) for s in states]
                    w = bearing_wear(self.si, self.drive, bearing, load,
                                     speed_rad_s=speed * bearing.speed_per_input,
                                     k_boundary=self.k_boundary,
                                     worn_depth_m=state.depth_m[part], element=name)
                    rates[part] += share / len(names) * np.array(
                        [w.clearance_m_per_h, sum(w.depth_m_per_h.values())])
                    if row == 0:
                        records.append(w)
            om = getattr(sys_.path, "output_mechanism", None)
            if om is not None:
                forces = np.array([s.output_pin_force_N for s in states])   # (P, M, n_o)
                speeds = self.drive.speeds()
                w = output_pin_wear(self.si, self.drive, om, forces,
                                    speed_rad_s=speed * abs(speeds["crank"] - speeds["member"]),
                                    k_boundary=self.k_boundary,
                                    worn_depth_m=state.depth_m["output pins"])
                rates["output pins"] += share * np.array([w.clearance_m_per_h,
                                                          sum(w.depth_m_per_h.values())])
                if row == 0:
                    records.append(w)
        return {c: tuple(v) for c, v in rates.items()}, records

    def pin_loss_W(self, twist: SystemTwist, state: WearState) -> float:
        """The pins' contact loss of every disc at the duty cycle's first row, from the worn
        system's loads and the run-in roughness (the efficiency model's friction laws).

        Parameters
        ----------
        twist : SystemTwist
            The worn reducer's.
        state : WearState
            Its worn depths (the roughness).

        Returns
        -------
        float
            [W].
        """
        from .efficiency.wear import run_in_roughness
        from .efficiency.friction import composite_rms_roughness
        torque, speed, _ = self.duty[0]
        lub = self.si.lubricant
        sigma0 = composite_rms_roughness(lub.roughness_Ra_m)
        ra = lub.roughness_Ra_m * float(run_in_roughness(sigma0, state.depth_m["mesh"])) \
            / sigma0
        si = dataclasses.replace(self.si, lubricant=dataclasses.replace(lub, roughness_Ra_m=ra))
        sys_: Any = twist.system
        states = twist.states(torque)
        crank = np.array([speed * self.crank_per_input])
        # the first disc's (as the wear's), for every disc
        rec = sys_.member_record(0, states)
        table = table_from_records(self.drive.meshing(sys_.slots[0].solver.positions_rad),
                                   [rec], "system")
        loss, _ = disc_contact_losses(si, table, np.array([abs(rec.torque)]), crank,
                                      lub.dynamic_viscosity_Pa_s)
        return float(loss[0]) * len(sys_.slots)

    def figures(self, state: WearState, hours: float, twist: SystemTwist,
                records: list) -> dict:
        """One history row: the datasheet's figures of the worn reducer.

        Parameters
        ----------
        state : WearState
        hours : float
            Its time [h].
        twist : SystemTwist
            The worn reducer's.
        records : list of ContactWear
            The contacts' wear at the state (:meth:`rates`).

        Returns
        -------
        dict
            ``hours``, ``lost_motion_arcmin`` and its parts, ``backlash_arcmin``, the TE,
            ``efficiency``, ``clearance_um``, the mesh's film ratio, regimes and K.
        """
        lm = lost_motion_arcmin(twist, self.rated)
        t_lm = LOST_MOTION_FRACTION * self.rated

        def mid(t, side):
            pts = [twist.at(t, side, branch=b) for b in (1, -1)]
            return {k: 0.5 * sum(float(np.mean(p.paths[k])) for p in pts)
                    for k in pts[0].paths}
        up, down = mid(t_lm, 1), mid(-t_lm, -1)
        parts = {k: (up[k] - down.get(k, 0.0)) / ARCMIN for k in up}
        te = np.array([s.twist_rad for s in twist.states(self.rated)]) / ARCSEC
        torque, speed, _ = self.duty[0]
        if self._base_losses is None:
            ev = evaluate(self.si, speed / RAD_S_PER_RPM, torque)
            self._base_losses = (float(ev.output_power_W[0]),
                                 float(sum(v[0] for v in ev.losses_W.values())),
                                 self.pin_loss_W(twist, state))
        p_out, losses, pin0 = self._base_losses
        pin = self.pin_loss_W(twist, state)
        mesh = [r for r in records if r.element == "mesh"]
        um = 1e6
        return {"hours": float(hours), "lost_motion_arcmin": float(lm),
                "lost_motion_parts_arcmin": parts,
                "backlash_arcmin": worn_backlash_arcmin(twist),
                "te_mean_arcsec": float(np.mean(te)),
                "te_peak_to_peak_arcsec": float(np.ptp(te)),
                "efficiency": p_out / (p_out + losses - pin0 + pin),
                "clearance_um": {c: state.clearance_m[c] * um for c in CLEARANCES},
                "mesh_film_ratio": float(np.mean([r.film_ratio for r in mesh])),
                "mesh_regime_share": {k: float(np.mean([r.regime_share[k] for r in mesh]))
                                      for k in mesh[0].regime_share},
                "mesh_wear_coefficient": float(np.mean([r.k_mean for r in mesh]))}


def worn_backlash_arcmin(twist: SystemTwist) -> float:
    """The datasheet's backlash (:func:`toothfem.fem.datasheet.sheet.backlash_arcmin`: the
    twists at zero torque from either flank) of a worn reducer. A body floating in a worn
    bearing's play may not settle under the datasheet's 1e-4 N m: the twists are then taken
    at the first of BACKLASH_TORQUES_NM that settles, whose elastic part
    (2e-4 arcmin at 1e-2 N m and 2e-3 at 1e-1 on a reducer of 100 N m/arcmin, both flanks)
    is below the figure's digits.

    Parameters
    ----------
    twist : SystemTwist

    Returns
    -------
    float
        [arcmin].
    """
    try:                               # the datasheet's own
        return backlash_arcmin(twist)
    except ContactError as exc:
        err = exc
    for t in BACKLASH_TORQUES_NM:
        try:
            return float((twist.at(t, 1).total.mean() - twist.at(-t, -1).total.mean())
                         / ARCMIN)
        except ContactError as exc:
            err = exc
    raise err


def wear_analysis(case: Case, hours: float, *, wear_coefficient: float | None = None,
                  steps: int = DEFAULT_STEPS, positions: int = DEFAULT_POSITIONS,
                  progress=None, times=None) -> WearResult:
    """Lost motion, backlash, TE and efficiency of a worn reducer over the hours of its
    duty cycle (module docstring; docs/wear.md).

    Each step t_k -> t_k+1 of :func:`hour_grid` takes the clearances' growth rates at both
    ends (Heun's predictor-corrector: the loads re-solved at the worn clearances of each)
    and reports the figures at every t_k.

    Parameters
    ----------
    case : toothfem.case.Case
    hours : float
        (0, MAX_HOURS] [h].
    wear_coefficient : float, optional
        K_b [-]; default ``[wear] wear_coefficient``, else Flodin & Andersson's.
    steps : int
        Steps over the hours (>= 1).
    positions : int
        Positions per pin pitch of the system model.
    progress : callable, optional
        Wraps the iterator over the steps.
    times : array_like, optional
        The times of the rows instead of :func:`hour_grid` [h]: increasing from 0 to
        ``hours`` (``steps`` is then their count less one).

    Returns
    -------
    WearResult

    Raises
    ------
    CaseError
        For hours, steps, positions or a coefficient out of range, or a drive without a
        cycloid disc.
    """
    case = as_case(case)
    check_range("hours", hours, 0.0, MAX_HOURS, lo_open=True, error=CaseError,
                why="the duty cycle's running time [h]")
    check_range("steps", steps, 1, 1000, error=CaseError, why="steps over the hours")
    check_range("positions", positions, 2, MAX_POSITIONS, error=CaseError)
    if wear_coefficient is not None:
        k, source = check_coefficient(wear_coefficient, "--wear-coefficient"), "given"
    elif case.wear.wear_coefficient is not None:
        k, source = float(case.wear.wear_coefficient), "[wear] wear_coefficient"
    else:
        k, source = DEFAULT_K, ("ASSUMPTION: mild wear of lubricated hardened steel "
                                "(docs/wear.md)")
    model = WornReducer(case, int(positions), k)
    grid = hour_grid(float(hours), int(steps)) if times is None else np.asarray(times, float)
    if times is not None and not (grid.ndim == 1 and grid.size >= 2 and grid[0] == 0
                                  and np.all(np.diff(grid) > 0) and grid[-1] == hours):
        raise CaseError(f"times = {grid!r}: increasing from 0 to hours = {hours:g}")
    steps = grid.size - 1
    state = WearState()
    twist = model.twist(state)
    rates, records = model.rates(state, twist)
    history = [model.figures(state, 0.0, twist, records)]
    it = range(int(steps))
    for i in progress(it) if progress is not None else it:
        dt = float(grid[i + 1] - grid[i])
        guess = state.advanced(rates, dt)
        try:
            ahead, _ = model.rates(guess)
            state = state.advanced({c: tuple(0.5 * (a + b) for a, b in zip(rates[c],
                                                                           ahead[c]))
                                    for c in CLEARANCES}, dt)
            twist = model.twist(state)
            rates, records = model.rates(state, twist)
            history.append(model.figures(state, grid[i + 1], twist, records))
        except (ContactError, GeometryError) as exc:
            worn = ", ".join(f"{c} {1e6 * v:.3g} um" for c, v in guess.clearance_m.items())
            raise CaseError(f"hours = {hours:g}: the worn reducer's system model does not "
                            f"solve at {grid[i + 1]:.4g} h (clearances worn: {worn}; {exc}); "
                            f"valid: up to {grid[i]:.4g} h at this wear coefficient") from None
    notes = ["the pins are taken as held in their grooves (their loaded arc wears)",
             f"rolling bearings: races slide {100 * 0.02:g} % of their rolling distance",
             "the TE is over one pin pitch of the system model at the rated torque"]
    return WearResult(case_name=case.name, hours=float(hours), wear_coefficient=k,
                      coefficient_source=source,
                      lost_motion_limit_arcmin=case.wear.lost_motion_limit_arcmin,
                      history=history, notes=tuple(notes))
