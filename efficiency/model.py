"""Reducer efficiency from the contact: the loss of every component and the prediction API.

``evaluate(case, speed_rpm, torque_Nm, oil_temp_C)`` returns the losses in watts of each
component at arrays of operating points (input speed, output torque, oil temperature);
``predict`` returns the efficiency alone. Each loss is computed from the loads and speeds
the component sees in the lossless train at that output torque (first order in the losses,
the usual practice of ISO/TR 14179 and of the sine paper, Eqs. 26-45); the efficiency is
``P_out / (P_out + sum of losses)``. docs/efficiency.md has the equations and checks.

Components by drive:

* sine (Lu & Xu 2024): ``mesh`` (contact friction summed over the contacts of one meshing
  period from a load-sharing record), ``eccentric_bearing`` (Eq. 32 with the bearing
  force from the planet's equilibrium, Eqs. 26-31), ``plain_bearings`` (Eq. 34),
  ``output_mechanism`` (pins in holes, Eqs. 37-39), ``churning`` (Eq. 42), ``drag``.
* cycloid: ``pin_contacts`` (pins sliding on the disc for the integral housing; for
  conventional pins the pin turns in its groove when the groove slides more easily, see
  :func:`_pin_contact_mu`; ``friction.pin_groove_coefficient`` 0 = ideal rolling), ``crank_bearings`` (the disc's crank-hole bearings: the output
  mechanism of an RV-type drive), ``first_stage`` (involute spur stage), ``churning``
  (Eq. 42 with a0 = the eccentricity and the crank speed, when ``lubricant.churning`` is
  set), ``drag``.
* rv: the cycloid components on the case's ``[cycloid]`` geometry plus the spur stage, or
  the RV paper's split-power method (``method="rv_split_power"``).

Friction at the tooth/pin contacts: ``case.friction.mesh_law`` (EHL regression of Xu et al.
2007 by default; Coulomb; Benedict-Kelley), each contact at its own load, Hertz pressure,
sliding and entraining speed; in mixed lubrication (film ratio lambda < 3) the asperity
friction ``friction.boundary_coefficient`` takes over in proportion xi(lambda) =
(1 - lambda/3)^2 (a solid-fraction blending in the manner of Castro & Seabra 2008; the
shape of xi is a modelling choice, stated in the docs).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..errors import CaseError, ToothfemError, check_range
from ..fem.hertz import reduced_modulus
from . import friction as fr

LOADS = ("analytic", "fem")
METHODS = ("power_flow", "rv_split_power")

#: Teeth of the sine pair within this unloaded gap share the load in the analytic split:
#: the order of the pair's elastic approach at the rig torque (Hertz approach of a few
#: micrometres plus tooth bending); the FE model finds the set itself.
SINE_IN_MESH_GAP_M = 5e-6
#: Full-film bound of the EHL regression (same as friction.LAMBDA_FULL_FILM).
LAMBDA_FULL = fr.LAMBDA_FULL_FILM


# ---------------------------------------------------------------------------------------
# Results

@dataclass(frozen=True)
class Efficiency:
    """Losses of every component at M operating points (arrays of shape (M,))."""
    speed_rpm: np.ndarray
    torque_Nm: np.ndarray
    oil_temp_C: np.ndarray | None
    output_power_W: np.ndarray
    losses_W: dict
    loads: str
    method: str
    notes: tuple = ()
    mesh_efficiency: dict = field(default_factory=dict)   # per stage, (M,)

    @property
    def input_power_W(self) -> np.ndarray:
        return self.output_power_W + sum(self.losses_W.values())

    @property
    def efficiency(self) -> np.ndarray:
        return self.output_power_W / self.input_power_W

    def shares(self) -> dict:
        """Each loss as a fraction of the input power (the sine paper's 'loss shares')."""
        p = self.input_power_W
        return {k: v / p for k, v in self.losses_W.items()}


# ---------------------------------------------------------------------------------------
# Lubricant

def viscosity_factor(lubricant, oil_temp_C):
    """eta(T)/eta(T_ref) by Vogel's law eta = A exp(B/(T + C)) (Vogel 1921; T in deg C).
    ``oil_temp_C`` None means the reference temperature (factor 1)."""
    if oil_temp_C is None:
        return 1.0
    t = np.asarray(oil_temp_C, float)
    lo = -lubricant.vogel_C_C
    if np.any(~np.isfinite(t)) or np.any(t <= lo + 1.0) or np.any(t > 250.0):
        bad = float(t[~np.isfinite(t) | (t <= lo + 1.0) | (t > 250.0)].flat[0])
        raise CaseError(f"oil_temp_C = {bad!r} is outside the valid range ({lo + 1:g}, 250] "
                        f"of the Vogel law with C = {lubricant.vogel_C_C:g} deg C")
    b, c = lubricant.vogel_B_C, lubricant.vogel_C_C
    return np.exp(b / (t + c) - b / (lubricant.reference_temperature_C + c))


def _mixed(mu_ehl, lam, boundary):
    """Blend the EHL friction with asperity friction as the film ratio falls below 3."""
    if boundary <= 0:
        return mu_ehl
    xi = np.clip(1.0 - lam / LAMBDA_FULL, 0.0, 1.0) ** 2
    return (1.0 - xi) * mu_ehl + xi * boundary


# ---------------------------------------------------------------------------------------
# Meshing cycle of one design: kinematics at unit crank speed, loads at a few torques

@dataclass(frozen=True)
class MeshTable:
    """Loaded contacts of one meshing period, flattened over (position, contact).

    Velocities are for a crank speed of 1 rad/s (they scale with it); loads are known at
    ``torques`` (N m on the moving member) and interpolated as F/T and P_h/sqrt(T), which
    is exact for the analytic split (one torque) and for a fixed contact set.
    """
    loads: str
    n_positions: int
    torques: np.ndarray            # (K,)
    force: np.ndarray              # (K, N) N
    ph: np.ndarray                 # (K, N) Pa
    position: np.ndarray           # (N,) position index
    vs: np.ndarray                 # (N,) |sliding speed| at unit crank speed, m/s
    ve: np.ndarray                 # (N,) |entraining speed| at unit crank speed, m/s
    r_eq: np.ndarray               # (N,) m
    normal: np.ndarray             # (N, 2) fixed -> moving member
    centre: np.ndarray             # (P, 2) centre of the moving member, m
    face_width: float
    pressure_from_fe: np.ndarray   # (N,) bool
    hertz_invalid: np.ndarray      # (N,) bool

    def at(self, torque):
        """(force, ph) at moving-member torques ``torque`` (M,): arrays (M, N)."""
        t = np.asarray(torque, float)[:, None]
        if self.torques.size == 1:
            f1 = self.force[0] / self.torques[0]
            p1 = self.ph[0] / math.sqrt(self.torques[0])
            return t * f1, np.sqrt(t) * p1
        f_t = self.force / self.torques[:, None]
        p_t = self.ph / np.sqrt(self.torques)[:, None]
        tt = np.clip(t[:, 0], self.torques[0], self.torques[-1])
        f = np.stack([np.interp(tt, self.torques, f_t[:, j]) for j in range(f_t.shape[1])], 1)
        p = np.stack([np.interp(tt, self.torques, p_t[:, j]) for j in range(p_t.shape[1])], 1)
        return t * f, np.sqrt(t) * p


def table_from_records(state, records, loads):
    """A MeshTable from a meshing state (unit crank speed) and load-sharing records."""
    loaded = np.zeros(state.shape, bool)
    for r in records:
        loaded |= r.force > 0
    pos, con = np.nonzero(loaded)
    return MeshTable(
        loads=loads, n_positions=state.shape[0],
        torques=np.array([r.torque for r in records]),
        force=np.stack([r.force[pos, con] for r in records]),
        ph=np.stack([r.ph[pos, con] for r in records]),
        position=pos, vs=np.abs(state.sliding_velocity[pos, con]),
        ve=np.abs(state.entrainment_velocity[pos, con]),
        r_eq=np.abs(state.equivalent_radius[pos, con]),
        normal=state.normal[pos, con], centre=np.asarray(state.centre),
        face_width=records[0].face_width,
        pressure_from_fe=np.any([r.pressure_from_fe[pos, con] for r in records], axis=0),
        hertz_invalid=np.any([r.hertz_invalid[pos, con] for r in records], axis=0))


def _e_star(material):
    e = material.youngs_modulus_GPa * 1e9
    return float(reduced_modulus(e, material.poisson_ratio, e, material.poisson_ratio))


#: Torques, as fractions of the case's declared torque on the member, at which the FE load
#: sharing is tabulated (fixed by the case, not by the points asked for, so a point's result
#: does not depend on the other points of the call); outside the range F/T is held at the end
#: value and the notes say so.
FE_TORQUE_FRACTIONS = (0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0)


def _declared_torque(case) -> float | None:
    """Output torque declared by [operating] (or input torque/power times the ratio,
    lossless): the reference of the FE torque table."""
    op = case.operating
    ratio = abs(case.ratio())
    if op.output_torque_Nm:
        return float(op.output_torque_Nm)
    if op.input_torque_Nm:
        return float(op.input_torque_Nm) * ratio
    if op.input_power_kW:
        return op.input_power_kW * 1e3 / (op.input_speed_rpm * 2 * math.pi / 60) * ratio
    return None


def _fe_reference(case, member_torque, per_member: float, notes) -> float:
    """Reference torque of the FE table on the member; a note where points fall outside."""
    declared = _declared_torque(case)
    ref = declared / per_member if declared else float(np.max(member_torque))
    lo, hi = FE_TORQUE_FRACTIONS[0] * ref, FE_TORQUE_FRACTIONS[-1] * ref
    out = (member_torque < lo) | (member_torque > hi)
    if np.any(out):
        notes.append(f"{int(out.sum())} point(s) outside the FE load table's torque range "
                     f"{lo * per_member:.3g}-{hi * per_member:.3g} N m: the load split of the "
                     "nearest end is scaled to them")
    return ref


@lru_cache(maxsize=4)
def _sine_solver(sine, material, output_mechanism, positions):
    """The FE cycle-mode solver of a sine pair (one factorisation per body; hat tables in
    the disk cache)."""
    from types import SimpleNamespace

    from ..fem import sine_fe
    from ..fem.cache import DiskCache, default_dir

    model = sine_fe.model_from_case(SimpleNamespace(drive="sine", sine=sine, material=material,
                                                    output_mechanism=output_mechanism))
    phis = np.linspace(0.0, model.pair.crank_pitch_rad, positions, endpoint=False)
    return sine_fe.CycleSolver(model, phis, cache=DiskCache(default_dir()))


@lru_cache(maxsize=16)
def sine_table(sine, material, loads="analytic", positions=36, torque_ref=None,
               output_mechanism=None) -> MeshTable:
    """Meshing table of a sine pair (one tooth pitch of the crank). FE loads: the planet
    held at the inner edge of its output-pin holes (``output_mechanism``), see
    fem/sine_fe.py; P_h is the FE pressure where Hertz fails (every loaded contact of the
    prototype)."""
    from ..fem.load_sharing import analytic_split
    from ..geometry import sine as sg

    pair = sine.geometry()
    phis = np.linspace(0.0, pair.crank_pitch_rad, positions, endpoint=False)
    state = sg.meshing(pair, phis, 1.0)
    width = sine.face_width_mm * 1e-3
    if loads == "analytic":
        recs = [analytic_split(state, 1.0, width, _e_star(material), SINE_IN_MESH_GAP_M)]
    else:
        solver = _sine_solver(sine, material, output_mechanism, positions)
        recs = [solver.solve(f * torque_ref) for f in FE_TORQUE_FRACTIONS]
    return table_from_records(state, recs, loads)


@lru_cache(maxsize=4)
def _cycle_solver(cycloid, material, positions):
    """The FE cycle-mode solver of a disc (one factorisation, influence coefficients kept in
    memory and in the disk cache, fem/cache.py: a new torque costs no new solve)."""
    from types import SimpleNamespace

    from ..fem import cycloid_fe as cf
    from ..fem.cache import DiskCache, default_dir

    model = cf.model_from_case(SimpleNamespace(cycloid=cycloid, material=material))
    return cf.CycleSolver(model, np.linspace(0.0, 2 * math.pi / model.geometry.pin_count,
                                             positions, endpoint=False),
                          cache=DiskCache(default_dir()))


@lru_cache(maxsize=16)
def cycloid_table(cycloid, material, loads="analytic", positions=36, torque_ref=None
                  ) -> MeshTable:
    """Meshing table of a cycloid disc (one pin pitch of the crank), pins fixed (the
    sliding speed at the disc; conventional pins are handled by the friction rule)."""
    from ..fem.load_sharing import analytic_split
    from ..geometry import cycloid as cy

    g = cycloid.geometry()
    phis = np.linspace(0.0, 2 * math.pi / g.pin_count, positions, endpoint=False)
    state = cy.meshing(g, phis, 1.0, pin_motion="fixed")
    width = cycloid.face_width_mm * 1e-3
    if loads == "analytic":     # the seed's rigid split ignores modifications (all gaps 0)
        recs = [analytic_split(state, 1.0, width, _e_star(material), in_mesh_gap_m=math.inf)]
    else:
        solver = _cycle_solver(cycloid, material, positions)
        recs = [solver.solve(f * torque_ref) for f in FE_TORQUE_FRACTIONS]
    return table_from_records(state, recs, loads)


# ---------------------------------------------------------------------------------------
# Contact friction over a table

def _contact_mu(case, table, force, ph, crank_speed, eta0, notes):
    """(M, N) friction coefficient at each loaded contact, and the film ratio."""
    f = case.friction
    lub = case.lubricant
    ve = table.ve[None, :] * crank_speed[:, None]
    vs = table.vs[None, :] * crank_speed[:, None]
    lam = np.full(force.shape, np.inf)
    if f.mesh_law == "coulomb":
        return np.where(force > 0, f.coefficient, 0.0), lam
    mu = np.zeros(force.shape)
    ok = (force > 0) & (ve > 0) & (ph > 0)
    eta = np.broadcast_to(np.asarray(eta0, float)[:, None] if np.ndim(eta0) else eta0,
                          force.shape)
    roughness = math.sqrt(2.0) * lub.roughness_Ra_um * 1e-6 * 1.25   # composite RMS of two
    if f.mesh_law == "benedict_kelley":
        w = force / table.face_width
        with np.errstate(divide="ignore", invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mu[ok] = fr.benedict_kelley(w[ok], vs[ok], 2 * ve[ok], eta[ok],
                                        lub.roughness_Ra_um * 1e-6)
        neg = ok & ~(mu > 0)
        if np.any(neg):      # the log term of B-K turns negative at low load and speed
            notes.append(f"Benedict-Kelley gives mu <= 0 at {int(neg.sum())} contact(s) "
                         "(outside its range): taken as 0")
            mu[neg] = 0.0
        return mu, lam
    e_prime = 2 * _e_star(case.material)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fr.MixedLubricationWarning)
        sr = np.where(ve > 0, vs / np.where(ve > 0, ve, 1.0), 0.0)
        res = fr.ehl_xu2007(ph[ok], sr[ok], ve[ok], eta[ok],
                            np.broadcast_to(table.r_eq, force.shape)[ok], roughness,
                            e_prime=e_prime,
                            pressure_viscosity=lub.pressure_viscosity_1_per_GPa * 1e-9)
    mu[ok] = res.mu
    lam[ok] = res.film_ratio
    low = np.isfinite(lam) & (lam < LAMBDA_FULL)
    if np.any(low):
        notes.append(f"film ratio lambda < {LAMBDA_FULL:g} at {100 * low.mean():.0f} % of the "
                     f"loaded contacts (min {lam[ok].min():.2g}): mixed lubrication, the Xu "
                     "regression is extrapolated"
                     + ("" if f.boundary_coefficient > 0 else
                        "; friction.boundary_coefficient = 0, so no asperity friction added"))
    mu = _mixed(mu, lam, f.boundary_coefficient)
    return mu, lam


def _mesh_loss(table, force, mu, crank_speed):
    """(M,) cycle-mean loss sum mu F |v_s| over the period."""
    vs = table.vs[None, :] * crank_speed[:, None]
    return np.sum(mu * force * vs, axis=1) / table.n_positions


def _resultant(table, force):
    """(M, P, 2) resultant contact force on the moving member at each position."""
    m = force.shape[0]
    out = np.zeros((m, table.n_positions, 2))
    for k in range(2):
        np.add.at(out[:, :, k], (slice(None), table.position), force * table.normal[:, k])
    return out


# ---------------------------------------------------------------------------------------
# Operating points

def _points(case, speed_rpm, torque_Nm, oil_temp_C):
    n = np.atleast_1d(np.asarray(speed_rpm, float))
    t = np.atleast_1d(np.asarray(torque_Nm, float))
    temp = None if oil_temp_C is None else np.atleast_1d(np.asarray(oil_temp_C, float))
    try:
        n, t, *rest = np.broadcast_arrays(n, t, *([] if temp is None else [temp]))
    except ValueError:
        raise ToothfemError(f"speed_rpm {n.shape}, torque_Nm {t.shape} and oil_temp_C "
                            f"{None if temp is None else temp.shape} do not broadcast") from None
    for name, arr, lo in (("speed_rpm", n, 0.0), ("torque_Nm", t, 0.0)):
        bad = ~np.isfinite(arr) | (arr <= lo)
        if np.any(bad):
            raise CaseError(f"{name} = {float(arr[bad].flat[0])!r} is outside the valid range "
                            f"({lo:g}, inf)")
    temp = rest[0] if rest else None
    return n.astype(float).ravel(), t.astype(float).ravel(), \
        None if temp is None else temp.ravel()


def evaluate(case, speed_rpm, torque_Nm, oil_temp_C=None, *, loads="analytic",
             method="power_flow", positions=36) -> Efficiency:
    """Losses of every component of ``case`` at the operating points (input speed [rpm],
    output torque [N m], oil temperature [deg C] or None for the lubricant's reference)."""
    if loads not in LOADS:
        raise CaseError(f"loads = {loads!r} is not one of {list(LOADS)}")
    if method not in METHODS:
        raise CaseError(f"method = {method!r} is not one of {list(METHODS)}")
    if isinstance(positions, bool) or int(positions) != positions:
        raise CaseError(f"positions = {positions!r} must be an integer")
    check_range("positions", positions, 4, 720, error=CaseError)
    n, t, temp = _points(case, speed_rpm, torque_Nm, oil_temp_C)
    visc = viscosity_factor(case.lubricant, temp) * np.ones_like(n)
    if method == "rv_split_power":
        if temp is not None or loads != "analytic":
            raise CaseError("method = 'rv_split_power' takes the declared mesh efficiency: "
                            "oil_temp_C and loads = 'fem' do not apply to it")
        return _rv_split(case, n, t, temp)
    if case.drive == "sine":
        return _sine(case, n, t, temp, visc, loads, positions)
    return _cycloid(case, n, t, temp, visc, loads, positions)


def predict(case, speed_rpm, torque_Nm, oil_temp_C=None, **kw) -> np.ndarray:
    """Efficiency (0..1) of ``case`` at arrays of operating points; shape of the
    broadcast inputs. Keywords as :func:`evaluate`."""
    eta = evaluate(case, speed_rpm, torque_Nm, oil_temp_C, **kw).efficiency
    return eta.reshape(np.broadcast_shapes(np.shape(speed_rpm), np.shape(torque_Nm),
                                           np.shape(oil_temp_C) if oil_temp_C is not None
                                           else ()))


# ---------------------------------------------------------------------------------------
# Sine reducer (Lu & Xu 2024, Eqs. 21-45)

def churning_lu_xu_2024(centre_distance_mm, speed_rpm, kinematic_viscosity_mm2_s):
    """No-load loss of the sine paper, Eq. 42 [W]:
    P0 = 1e-7 a0 (n1/60)^(4/3) (nu/n1)^0.1 (nu + 90) kW, a0 in mm, n1 in rpm, nu in mm^2/s.
    The printed 'z50' is read as the viscosity nu50 (OCR of the same symbol as gamma50);
    the kW unit is the one that gives the paper's 1.85 % share (docs/efficiency.md)."""
    n = np.asarray(speed_rpm, float)
    nu = np.asarray(kinematic_viscosity_mm2_s, float)
    return 1e-7 * centre_distance_mm * (n / 60.0) ** (4.0 / 3.0) * (nu / n) ** 0.1 \
        * (nu + 90.0) * 1e3


def _sine(case, n, t2, temp, visc, loads, positions):
    from ..geometry.train import khv_speeds

    st, om = case.sine, case.output_mechanism
    if om is None:
        raise CaseError("[output_mechanism] section is required for the sine reducer's losses")
    w = khv_speeds(st.planet_teeth, st.ring_teeth)
    crank = n * 2 * math.pi / 60                            # rad/s
    w_planet = crank * w["moving"]
    rel = np.abs(crank - w_planet)                          # crank relative to the planet
    p_out = t2 * np.abs(w_planet)
    notes = []
    torque_ref = _fe_reference(case, t2, 1.0, notes) if loads == "fem" else None
    table = sine_table(st, case.material, loads, positions, torque_ref, om)
    force, ph = table.at(t2)
    eta0 = case.lubricant.dynamic_viscosity_Pa_s * visc
    mu, _ = _contact_mu(case, table, force, ph, crank, eta0, notes)
    mesh = _mesh_loss(table, force, mu, crank)
    if np.any(table.hertz_invalid):
        notes.append(f"Hertz's assumptions fail at {int(table.hertz_invalid.sum())} of "
                     f"{table.hertz_invalid.size} loaded contacts (half-width not small against "
                     "the radii); "
                     + ("P_h there is the FE pressure" if np.any(table.pressure_from_fe) else
                        "P_h there is still Hertz's (analytic loads): use loads='fem'"))
    a0 = st.module_mm * (st.ring_teeth - st.planet_teeth) / 2
    ecc, out_mech = _w_mechanism(case, om, table, force, t2, a0, rel)
    plain = om.plain_bearing_friction_torque_Nmm * 1e-3 * crank * np.ones_like(n)  # Eq. 34
    losses = {"mesh": mesh, "eccentric_bearing": ecc, "plain_bearings": plain,
              "output_mechanism": out_mech}
    lub = case.lubricant
    if lub.churning != "none":
        losses["churning"] = lub.churning_scale * churning_lu_xu_2024(
            a0, n, lub.kinematic_viscosity_mm2_s * visc)
    losses["drag"] = case.friction.drag_torque_Nmm * 1e-3 * crank
    # the mesh efficiency in the crank frame (virtual power T2 |w_planet - w_crank|), for
    # display: in a K-H-V stage the energy balance with the contact loss itself is exact
    return Efficiency(n, t2, temp, p_out, losses, loads, "power_flow", tuple(notes),
                      {"sine": 1 - mesh / (t2 * rel)})


def _w_mechanism(case, om, table, force, torque, a0_mm, rel):
    """(eccentric bearing, pins-in-holes output mechanism) losses [W] of a K-H-V member
    carrying ``torque`` (M,) out through pins in holes (sine paper Eqs. 26-39, derivations
    7): the pins' load sum Q = 4T/(pi R_w) acts along -e on the member, the eccentric
    bearing carries |mesh resultant - sum Q e| (the member's equilibrium), the pins slide
    in their sleeves at 2 a0 w_rel (Eq. 38)."""
    r_w = om.pin_hole_circle_radius_mm * 1e-3
    sum_q = 4 * torque / (math.pi * r_w)                                   # Eq. 26
    e_dir = table.centre / np.linalg.norm(table.centre, axis=1)[:, None]   # (P, 2)
    bearing = _resultant(table, force) - sum_q[:, None, None] * e_dir[None]
    f_r1 = np.mean(np.linalg.norm(bearing, axis=2), axis=1)                # Eq. 27, exact
    ecc = case.friction.bearing_coefficient * om.eccentric_bearing_inner_radius_mm * 1e-3 \
        * f_r1 * rel                                                       # Eq. 32
    out_mech = case.friction.output_pin_coefficient * sum_q * 2 * a0_mm * 1e-3 * rel  # 38-39
    return ecc, out_mech


# ---------------------------------------------------------------------------------------
# Cycloid and RV drives

def _pin_contact_mu(case, mu_disc):
    """Friction that resists sliding at a pin: the disc contact's (integral housing), or
    for a pin free to turn in its groove the smaller of that and the groove's Coulomb
    coefficient ``friction.pin_groove_coefficient``: the pin turns until the two friction torques balance, so the interface
    that slides more easily takes the sliding (loss mu F v_s either way, v_s the sliding
    speed of a fixed pin, since the groove radius is the pin radius)."""
    if case.cycloid.pin_structure == "integral":
        return mu_disc
    return np.minimum(mu_disc, case.friction.pin_groove_coefficient)


def cycloid_speeds(case):
    """(cycloid section, speeds for unit input speed, first stage or None)."""
    from ..geometry.train import khv_speeds, rv_speeds

    cyc = case.cycloid
    if cyc is None:
        raise CaseError("a [cycloid] section (disc and pins) is required for the contact "
                        "losses of this drive")
    if case.drive == "rv":
        z = case.rv
        w = rv_speeds(z.sun_teeth, z.planet_teeth, z.disc_teeth, z.pin_count)
        return cyc, {"input": 1.0, "crank": w["planet"], "disc": w["disc"],
                     "carrier": w["carrier"]}, ("rv", z.sun_teeth, z.planet_teeth)
    if case.first_stage is not None:
        fs = case.first_stage
        w = rv_speeds(fs.sun_teeth, fs.planet_teeth, cyc.lobe_count, cyc.pin_count)
        return cyc, {"input": 1.0, "crank": w["planet"], "disc": w["disc"],
                     "carrier": w["carrier"]}, ("first_stage", fs.sun_teeth, fs.planet_teeth)
    w = khv_speeds(cyc.lobe_count, cyc.pin_count)
    return cyc, {"input": 1.0, "crank": 1.0, "disc": w["moving"], "carrier": w["moving"]}, None


def disc_contact_losses(case, table, torque_disc, crank_speed, eta0, notes=None):
    """Pin-contact loss of one cycloid disc [W] and the mean resultant of its pin forces
    [N] (what its crank bearings carry), at disc torques ``torque_disc`` (M,), crank
    speeds relative to the pin ring [rad/s] and inlet viscosities [Pa s], from a meshing
    ``table`` (any load source: analytic, FE or another contact model's records through
    :func:`table_from_records`)."""
    notes = [] if notes is None else notes
    force, ph = table.at(torque_disc)
    mu_disc, _ = _contact_mu(case, table, force, ph, crank_speed, eta0, notes)
    mu = _pin_contact_mu(case, mu_disc)
    if case.cycloid.pin_structure == "conventional":
        share = np.mean(mu_disc > case.friction.pin_groove_coefficient)
        notes.append(f"conventional pins turn in their grooves at {100 * share:.0f} % of the "
                     "loaded contacts (groove friction below the disc contact's)")
    loss = _mesh_loss(table, force, mu, crank_speed)
    f_bearing = np.mean(np.linalg.norm(_resultant(table, force), axis=2), axis=1)
    return loss, f_bearing


#: Samples of the angle between the pin resultant and a crank hole's tangent (its mean over
#: a crank turn: the holes turn with the disc, the resultant with the crank).
_CRANK_ANGLE_SAMPLES = 64


def _crank_bearing_loss(case, cyc, f_resultant, t_disc, rel):
    """Friction loss of one disc's crank-hole bearings (2K-V) [W]. The k holes at radius
    R_c take the pin resultant F and the disc torque T between them, evenly: hole i carries
    -F/k + T/(k R_c) t_i (t_i its tangent), so sum |F_i| = k <|a e - b t|> with a = F/k,
    b = T/(k R_c), averaged over the angle between e and t (uniform over a crank turn).
    Loss = f r_b sum |F_i| w_rel (Palmgren's load-dependent friction torque f F r_b)."""
    h = cyc.disc_holes
    k = h.crank_hole_count
    r_b = h.crank_hole_radius_mm * 1e-3
    r_c = h.crank_hole_circle_radius_mm * 1e-3
    if k < 1 or r_b <= 0 or r_c <= 0:
        raise CaseError("cycloid.disc_holes: crank_hole_count, crank_hole_radius_mm and "
                        "crank_hole_circle_radius_mm are required for the crank-bearing loss "
                        "of a 2K-V (RV-type) drive")
    a = f_resultant / k
    b = t_disc / (k * r_c)
    psi = (np.arange(_CRANK_ANGLE_SAMPLES) + 0.5) * 2 * math.pi / _CRANK_ANGLE_SAMPLES
    load = k * np.mean(np.sqrt(a[:, None] ** 2 + b[:, None] ** 2
                               - 2 * a[:, None] * b[:, None] * np.cos(psi)), axis=1)
    return case.friction.bearing_coefficient * load * r_b * rel


def _cycloid(case, n, t2, temp, visc, loads, positions):
    if case.material is None:
        raise CaseError("a [material] section is required for the contact losses")
    cyc, w, spur = cycloid_speeds(case)
    w_in = n * 2 * math.pi / 60
    crank = np.abs(w_in * w["crank"])
    disc_rel = np.abs(w_in * (w["crank"] - w["disc"]))       # crank relative to the disc
    p_out = t2 * np.abs(w_in * w["carrier"])
    notes = []
    t_disc = t2 / cyc.disc_count          # even split for losses (load factor is for strength)
    torque_ref = _fe_reference(case, t_disc, cyc.disc_count, notes) if loads == "fem" \
        else None
    table = cycloid_table(cyc, case.material, loads, positions, torque_ref)
    eta0 = case.lubricant.dynamic_viscosity_Pa_s * visc
    pins_disc, f_bearing = disc_contact_losses(case, table, t_disc, crank, eta0, notes)
    pins = cyc.disc_count * pins_disc
    eta2 = 1 - pins / (t2 * disc_rel)                 # disc-pin mesh, crank frame
    mesh_eff = {"cycloid": eta2}
    if spur is None:
        # K-H-V: the disc's torque leaves through pins in holes; its central eccentric
        # bearing carries the pin resultant and the pins' load (as the sine planet)
        om = case.output_mechanism
        if om is None:
            raise CaseError("a K-H-V cycloid drive (no [first_stage]) needs [output_mechanism] "
                            "(pins in holes) for its output losses")
        force, _ = table.at(t_disc)
        ecc, out_mech = _w_mechanism(case, om, table, force, t_disc, cyc.eccentricity_mm,
                                     disc_rel)
        # the energy balance with the contact loss itself (Chen & Angeles' closed form
        # agrees to first order)
        losses = {"pin_contacts": pins, "eccentric_bearing": cyc.disc_count * ecc,
                  "output_mechanism": cyc.disc_count * out_mech}
    else:                                             # 2K-V: power_flow.rv_power_flow form
        from . import spur as sp

        losses = {"crank_bearings": cyc.disc_count * _crank_bearing_loss(
            case, cyc, f_bearing, t_disc, disc_rel)}
        stage = case.first_stage
        zs, zp = spur[1], spur[2]
        ratio = abs(1 / w["carrier"])
        t_sun = t2 / ratio
        if stage is not None and stage.mesh_efficiency is not None:
            eta1 = np.full_like(n, stage.mesh_efficiency)
        elif stage is not None:
            eta1 = sp.mesh_efficiency(stage, t_sun, w_in * (1 - w["carrier"]), eta0,
                                      case.lubricant.roughness_Ra_um)
        else:
            raise CaseError("a [first_stage] section is required for the sun-planet mesh")
        r, z4, z5 = zp / zs, cyc.lobe_count, cyc.pin_count
        if np.any(z5 - z4 * eta2 <= 0):
            raise CaseError(f"the disc-pin mesh efficiency {float(np.min(eta2)):.4g} in the "
                            f"crank frame is at or below z4/z5 = {z4 / z5:.4g}: the train "
                            "self-locks (friction too high for these operating points)")
        eta_train = (1 + r * eta1 * z5 / (z5 - z4 * eta2)) / ratio
        eta_lossless_1 = (1 + r * eta1 * z5 / (z5 - z4)) / ratio   # only the spur losses
        p_in = p_out / eta_train
        losses["first_stage"] = p_out / eta_lossless_1 - p_out
        losses["pin_contacts"] = p_in - p_out - losses["first_stage"]
        mesh_eff["first_stage"] = eta1
    lub = case.lubricant
    if lub.churning != "none":        # Eq. 42 with a0 = the eccentricity, n = crank speed
        losses["churning"] = lub.churning_scale * churning_lu_xu_2024(
            cyc.eccentricity_mm, crank * 60 / (2 * math.pi), lub.kinematic_viscosity_mm2_s * visc)
    losses["drag"] = case.friction.drag_torque_Nmm * 1e-3 * w_in
    return Efficiency(n, t2, temp, p_out, losses, loads, "power_flow", tuple(notes), mesh_eff)


def _rv_split(case, n, t2, temp):
    """The RV paper's split/virtual power method at each operating point (mesh
    efficiencies as declared)."""
    from .power_flow import rv_split_power

    if case.drive != "rv":
        raise CaseError(f"method = 'rv_split_power' needs drive = 'rv', not {case.drive!r}")
    z = case.rv
    eta1 = z.mesh_efficiency
    # the method is linear in the input power: the losses per watt of input, scaled
    r = rv_split_power(z.sun_teeth, z.planet_teeth, z.disc_teeth, z.pin_count, 1.0, eta1, eta1)
    p_out = t2 * np.abs(n * 2 * math.pi / 60 / r.ratio)
    p_in = p_out / r.efficiency
    losses = {"sun_planet_mesh": p_in * r.loss_L1_W, "cycloid_mesh": p_in * r.loss_L2_W}
    return Efficiency(n, t2, temp, p_out, losses, "analytic", "rv_split_power",
                      ("RV paper Eqs. 8-15 with the declared mesh efficiency",),
                      {"sun_planet": np.full_like(n, eta1), "cycloid": np.full_like(n, eta1)})


def operating_point(case, **kw):
    """(input speed [rpm], output torque [N m]) of the case's [operating] table: the declared
    output torque, or the output torque that the declared input torque or power gives
    through the model's own efficiency (fixed point T2 = i T1 eta(T2); ``kw`` as
    :func:`evaluate`)."""
    op = case.operating
    ratio = abs(case.ratio())
    if op.output_torque_Nm:
        return op.input_speed_rpm, op.output_torque_Nm
    if op.input_torque_Nm:
        t_in = op.input_torque_Nm
    elif op.input_power_kW:
        t_in = op.input_power_kW * 1e3 / (op.input_speed_rpm * 2 * math.pi / 60)
    else:
        raise CaseError("[operating] needs output_torque_Nm, input_torque_Nm or input_power_kW")
    t2 = t_in * ratio
    for _ in range(50):       # contraction: eta varies slowly with torque
        new = t_in * ratio * float(evaluate(case, op.input_speed_rpm, t2, **kw).efficiency[0])
        if abs(new - t2) < 1e-10 * t2:
            return op.input_speed_rpm, new
        t2 = new
    # the contraction rate is 1 - eta: slow where the load-independent losses take much of
    # the input; a bracketed root of T2 - i T1 eta(T2) on (0, i T1] instead (issue 14)
    return op.input_speed_rpm, _output_torque_root(case, t_in * ratio, kw)


#: The bracket's lower end, a fraction of the lossless output torque i T1.
_ROOT_LO = 1e-9


def _output_torque_root(case, t_lossless, kw) -> float:
    """Output torque T2 in (0, i T1) with T2 = i T1 eta(T2) (brentq); CaseError naming the
    declared input when even a vanishing output needs more than it (the no-load losses
    exceed the input power: the reducer does not turn)."""
    from scipy.optimize import brentq

    op = case.operating
    speed = op.input_speed_rpm

    def residual(t2):
        return t2 - t_lossless * float(evaluate(case, speed, t2, **kw).efficiency[0])

    lo = _ROOT_LO * t_lossless
    if residual(lo) >= 0:
        key, value = (("input_torque_Nm", op.input_torque_Nm) if op.input_torque_Nm
                      else ("input_power_kW", op.input_power_kW))
        raise CaseError(f"operating.{key} = {value!r} does not overcome the load-independent "
                        f"losses at {speed:g} rpm: no output torque")
    return float(brentq(residual, lo, t_lossless, rtol=1e-10))
