"""Test oracle: the sine paper's mesh efficiency read literally, beside the same contacts
integrated position by position.

Source: Y. Lu, L. Xu, "Transmission efficiency of one tooth difference sine tooth profile
planetary reducer", Heliyon 10 (2024) e26300, Eqs. 3-5, 8-25, Tables 1-3, Sec. 6.2.
Derivations, numbers and the verdict are in ``docs/sine_mesh_efficiency.md``. The
production path is ``toothfem.efficiency`` (evaluation, drive_losses, contact_friction)
(``mesh_table``, ``contact_mu``,
``evaluate``); this module reproduces the paper to check it against (tests/test_sine_mesh.py)
and feeds ``benchmarks/sine_mesh_reading.py``.

Two models, side by side:

* :func:`mesh_efficiency` -- ours. Crank positions over one mesh period (2 pi/z2), every
  candidate tooth pair of :func:`toothfem.geometry.sine.meshing`, the analytic load split
  (``F_i = F0 cos(alpha_i)`` on the pairs within ``in_mesh_gap_m`` whose moment arm can
  carry the torque, paper Eqs. 16-19; the gap is the model's ``SINE_IN_MESH_GAP_M``),
  Hertz pressure per contact, and the loss ``sum mu_i F_i |v_s,i|`` (Eq. 21 in SI) with the
  EHL regression of Xu et al. (2007) at the model's composite roughness, or a Coulomb
  coefficient (:func:`tests.oracles.mesh_loss.mesh_loss`). The same contacts, loads and
  friction as the model's analytic path, summed per position.
* :func:`paper_mesh_efficiency` -- the paper's structure: one tooth pair followed along a
  planet flank (profile angle phi from tip to root, the "period pi/z1"), force
  ``F0 cos(alpha_k1)`` with F0 from Eq. 18, velocities from Eqs. 4-5 at the conjugate
  contact, Eq. 23 with a choice of coefficients and units and the flank's Ra as the
  paper's S_Ra. A :class:`PaperReading` names each choice; :data:`PAPER_READINGS` holds
  the ones tabulated in the docs.

Power (Eq. 25, Eq. 33): ``P = T1 omega_H``, the input power; the load torque of Eqs. 16-19
is ``T2 = |i12| T1`` (lossless). SI throughout unless a reading says otherwise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from toothfem.efficiency.friction import (ALPHA_MINERAL_OIL, XU2007_COEFFICIENTS,
                                          composite_rms_roughness)
from toothfem.fem.drives.sine import SINE_IN_MESH_GAP_M
from toothfem.errors import ToothfemError, check_range
from toothfem.fem.hertz import reduced_modulus
from toothfem.fem.load_sharing import LoadSharing, analytic_split
from toothfem.geometry import sine
from toothfem.geometry.kinematics import MeshingState

from .mesh_loss import MeshLoss, mesh_loss, stage_power

__all__ = [
    "DEFAULT_POSITIONS",
    "DEFAULT_FLANK_SAMPLES",
    "TABLE1_COEFFICIENTS",
    "PAPER_TABLE3",
    "PAPER_PUBLISHED",
    "SineMeshConditions",
    "conditions_from_case",
    "SineMeshEfficiency",
    "mesh_efficiency",
    "FlankKinematics",
    "flank_kinematics",
    "xu2007_raw",
    "PaperReading",
    "PAPER_READINGS",
    "PaperMeshEfficiency",
    "paper_mesh_efficiency",
]

#: Crank positions per mesh period (2 pi/z2) in :func:`mesh_efficiency`, at mid-intervals.
DEFAULT_POSITIONS = 80
#: Profile samples along one flank (tip to root, both included) in :func:`flank_kinematics`.
DEFAULT_FLANK_SAMPLES = 401

#: Sine paper Table 1 as printed: b1 has no minus sign, three decimals. In Xu's places
#: (exponents b2, b3, b6, b7, b8) it differs from :data:`XU2007_COEFFICIENTS` by the sign
#: of b1, which multiplies mu by e^(2 x 8.916) = 5.6e7.
TABLE1_COEFFICIENTS = (8.916, 1.033, 1.036, -0.354, 2.812, -0.101, 0.752, -0.391, 0.620)

#: The paper's published meshing-efficiency range at Table 3 conditions (Sec. 6.2 (1)).
PAPER_PUBLISHED = {"max": 0.9937, "min": 0.9658, "mean": 0.9796,
                   "period": "pi/z1 of the meshing position angle"}


# --------------------------------------------------------------------------- conditions

@dataclass(frozen=True)
class SineMeshConditions:
    """Operating point of the mesh study (SI).

    ``input_torque_Nm`` is T1 on the crank; the planet (moving member) carries
    ``|i12| T1`` (lossless). ``roughness_Ra_m`` is the Ra of each flank (Table 3, the
    case's ``lubricant.roughness_Ra_um``): :func:`mesh_efficiency` feeds the friction law
    their composite RMS roughness as the model does, the paper's readings feed Ra itself
    (Eq. 23's S_Ra).
    """
    input_speed_rpm: float
    input_torque_Nm: float
    dynamic_viscosity_Pa_s: float
    roughness_Ra_m: float
    youngs_modulus_Pa: float
    poisson_ratio: float
    pressure_viscosity_1_per_Pa: float = ALPHA_MINERAL_OIL

    def __post_init__(self):
        check_range("input_speed_rpm", self.input_speed_rpm, 0, None, lo_open=True)
        check_range("input_torque_Nm", self.input_torque_Nm, 0, None, lo_open=True)
        check_range("dynamic_viscosity_Pa_s", self.dynamic_viscosity_Pa_s, 0, None,
                    lo_open=True)
        check_range("roughness_Ra_m", self.roughness_Ra_m, 0, 1e-4)
        check_range("youngs_modulus_Pa", self.youngs_modulus_Pa, 0, None, lo_open=True)
        check_range("poisson_ratio", self.poisson_ratio, 0, 0.5, hi_open=True)
        check_range("pressure_viscosity_1_per_Pa", self.pressure_viscosity_1_per_Pa, 0, None,
                    lo_open=True)

    @property
    def crank_speed_rad_s(self) -> float:
        return self.input_speed_rpm * 2 * math.pi / 60

    @property
    def input_power_W(self) -> float:
        """Eq. 33: P = 2 pi n1 T1 (n1 in rev/s)."""
        return self.input_torque_Nm * self.crank_speed_rad_s

    @property
    def e_star_Pa(self) -> float:
        """Contact modulus E* of two bodies of this material."""
        e, nu = self.youngs_modulus_Pa, self.poisson_ratio
        return float(reduced_modulus(e, nu, e, nu))


#: Sine paper Table 3 (n1 = 300 rpm, T1 = 400 N mm, eta0 = 2e-8 MPa s = 0.02 Pa s,
#: Ra = 0.4 um) with Table 2's material (E = 212 GPa, nu = 0.28).
PAPER_TABLE3 = SineMeshConditions(input_speed_rpm=300.0, input_torque_Nm=0.4,
                                  dynamic_viscosity_Pa_s=0.02, roughness_Ra_m=0.4e-6,
                                  youngs_modulus_Pa=212e9, poisson_ratio=0.28)


def conditions_from_case(case) -> SineMeshConditions:
    """The mesh conditions of a sine case (operating point, lubricant, material)."""
    if case.drive != "sine":
        raise ToothfemError(f"case.drive = {case.drive!r}: the sine mesh model needs 'sine'")
    op, lub = case.operating, case.lubricant
    if op.input_torque_Nm is None:
        raise ToothfemError("operating.input_torque_Nm is required for the mesh efficiency")
    return SineMeshConditions(
        input_speed_rpm=op.input_speed_rpm, input_torque_Nm=op.input_torque_Nm,
        dynamic_viscosity_Pa_s=lub.dynamic_viscosity_Pa_s,
        roughness_Ra_m=lub.roughness_Ra_um * 1e-6,
        youngs_modulus_Pa=case.material.youngs_modulus_GPa * 1e9,
        poisson_ratio=case.material.poisson_ratio,
        pressure_viscosity_1_per_Pa=lub.pressure_viscosity_1_per_GPa * 1e-9)


def _ratio(pair) -> float:
    """K-H-V ratio crank/planet, -z1/(z2 - z1) (the paper's i12)."""
    return -pair.planet_teeth / (pair.ring_teeth - pair.planet_teeth)


class _EfficiencyRange:
    """``max`` and ``min`` of an ``efficiency`` array (both results below)."""

    @property
    def max(self) -> float:
        return float(np.max(self.efficiency))

    @property
    def min(self) -> float:
        return float(np.min(self.efficiency))


# --------------------------------------------------------------------------- our model

@dataclass(frozen=True)
class SineMeshEfficiency(_EfficiencyRange):
    """Per-position mesh efficiency of the physical model (P positions, C candidates).

    ``planet_angle_rad`` = crank angle x z2/z1: the planet's turn relative to the crank,
    the paper's phi1 (Eq. 2), in which one planet flank spans pi/z1.
    """
    crank_angle_rad: np.ndarray        # (P,)
    planet_angle_rad: np.ndarray       # (P,)
    state: MeshingState
    load: LoadSharing
    loss: MeshLoss
    power_W: float

    @property
    def efficiency(self) -> np.ndarray:
        return self.loss.efficiency

    @property
    def mean(self) -> float:
        """Time mean (positions are uniform in crank angle)."""
        return float(np.mean(self.efficiency))

    @property
    def conjugate(self) -> np.ndarray:
        """(P, C) bool: the conjugate (gap 0) contact of each position."""
        return self.state.gap == 0


def mesh_efficiency(pair, conditions: SineMeshConditions, crank_angle_rad=None, *,
                    mu=None, in_mesh_gap_m: float = SINE_IN_MESH_GAP_M,
                    positions: int = DEFAULT_POSITIONS,
                    candidates: int = sine.DEFAULT_CANDIDATES) -> SineMeshEfficiency:
    """Mesh efficiency of a sine pair at crank angles (default: ``positions`` mid-points of
    one mesh period 2 pi/z2) from the analytic load split.

    ``mu`` None: EHL friction of Xu et al. (2007) per contact with S the composite RMS
    roughness of the two flanks (:func:`toothfem.efficiency.friction.composite_rms_roughness`,
    as the model); it warns with ``MixedLubricationWarning`` where the film ratio is below
    its full-film range, which is everywhere for the prototype. A number: Coulomb
    friction. Loss = sum mu F |v_s|, efficiency = 1 - loss / (T1 omega_H).
    """
    check_range("positions", positions, 1, None)
    if crank_angle_rad is None:
        crank_angle_rad = (np.arange(int(positions)) + 0.5) / int(positions) \
            * (2 * math.pi / pair.ring_teeth)
    chi = np.atleast_1d(np.asarray(crank_angle_rad, float))
    w = conditions.crank_speed_rad_s
    state = sine.meshing(pair, chi, w, candidates)
    torque = abs(_ratio(pair)) * conditions.input_torque_Nm
    load = analytic_split(state, torque, pair.face_width_m, conditions.e_star_Pa,
                          in_mesh_gap_m, weight="cos_pressure_angle")
    power = stage_power(torque, w, _ratio(pair))
    loss = mesh_loss(state, load, power, mu, eta0_Pa_s=conditions.dynamic_viscosity_Pa_s,
                     roughness_m=composite_rms_roughness(conditions.roughness_Ra_m),
                     e_prime_Pa=2 * conditions.e_star_Pa,
                     pressure_viscosity=conditions.pressure_viscosity_1_per_Pa)
    return SineMeshEfficiency(chi, chi * pair.ring_teeth / pair.planet_teeth, state, load,
                              loss, power)


# --------------------------------------------------------------------------- one flank

@dataclass(frozen=True)
class FlankKinematics:
    """The conjugate contact followed along one planet flank, tip (phi = 0) to root
    (phi = pi/z1), N samples. Lengths m, speeds m/s, angles rad.

    ``profile_angle``: phi of Eq. 1 (the paper's "meshing position angle").
    ``planet_angle``: psi = the planet's turn relative to the crank at contact (phi1 of
    Eq. 2); ``crank_angle`` = psi z1/z2.
    ``pressure_angle``: alpha_k1 of Eqs. 8-10; ``contact_radius``: r_k1 of Eq. 11.
    ``sliding``: |v12| of Eq. 4 at the contact in the crank frame (omega1 = omega_H z2/z1,
    omega2 = omega_H), equal to the physical sliding (d/z1) omega_H |KP|.
    ``entrainment_eq5``: |U12| of Eq. 5 (mean material velocity in the crank frame);
    ``entrainment_rolling``: the rolling speed relative to the moving contact point
    (MeshingState convention).
    ``radius_planet``, ``radius_ring``: signed curvature radii, convex positive.
    ``moment_arm``: of the contact normal about the planet centre (negative: the contact
    carries the output torque for a counter-clockwise crank).
    """
    profile_angle: np.ndarray
    planet_angle: np.ndarray
    crank_angle: np.ndarray
    pressure_angle: np.ndarray
    contact_radius: np.ndarray
    sliding: np.ndarray
    entrainment_eq5: np.ndarray
    entrainment_rolling: np.ndarray
    radius_planet: np.ndarray
    radius_ring: np.ndarray
    moment_arm: np.ndarray
    crank_speed_rad_s: float
    planet_teeth: int
    ring_teeth: int

    def equivalent_radius(self, kind: str = "conformal") -> np.ndarray:
        """'conformal': 1/(1/rho1 + 1/rho2), the comprehensive curvature of a concave-convex
        pair (signed radii); 'planet': 1/|K1| (Eq. 7 is K1 alone); 'external':
        1/(|K1| + |K2|), both taken convex."""
        k1, k2 = 1.0 / self.radius_planet, 1.0 / self.radius_ring
        with np.errstate(divide="ignore"):
            if kind == "conformal":
                return 1.0 / (k1 + k2)
            if kind == "planet":
                return 1.0 / np.abs(k1)
            if kind == "external":
                return 1.0 / (np.abs(k1) + np.abs(k2))
        raise ToothfemError(f"radius = {kind!r} is not one of {list(_RADII)}")


def flank_kinematics(pair, crank_speed_rad_s: float,
                     samples: int = DEFAULT_FLANK_SAMPLES) -> FlankKinematics:
    """Kinematics of the conjugate contact along one flank (see :class:`FlankKinematics`)."""
    n = int(check_range("samples", samples, 3, None))
    z1, z2 = pair.planet_teeth, pair.ring_teeth
    w = float(crank_speed_rad_s)
    phi = np.linspace(0.0, math.pi / z1, n)
    chi = sine.contact_crank_angle(pair, phi)
    st = sine.meshing(pair, chi, w)
    col = np.argmax(st.gap == 0, axis=1)          # meshing guarantees one conjugate column
    rows = np.arange(n)
    pick = lambda a: a[rows, col]                  # noqa: E731
    K = st.point[rows, col]                        # (N, 2), ring frame
    O1 = st.centre
    w1 = -w * z2 / z1                              # planet relative to the crank
    w2 = -w                                        # ring relative to the crank
    v1 = w1 * np.stack([-(K - O1)[:, 1], (K - O1)[:, 0]], axis=1)
    v2 = w2 * np.stack([-K[:, 1], K[:, 0]], axis=1)
    seed = sine.seed_pressure_angles(pair, phi)
    return FlankKinematics(
        profile_angle=phi, planet_angle=chi * z2 / z1, crank_angle=chi,
        pressure_angle=seed.alpha_k1, contact_radius=seed.r_k1,
        sliding=np.hypot(*(v1 - v2).T), entrainment_eq5=np.hypot(*(0.5 * (v1 + v2)).T),
        entrainment_rolling=np.abs(pick(st.entrainment_velocity)),
        radius_planet=pick(st.radius_moving), radius_ring=pick(st.radius_fixed),
        moment_arm=pick(st.moment_arm), crank_speed_rad_s=w, planet_teeth=z1,
        ring_teeth=z2)


# --------------------------------------------------------------------------- Eq. 23

def xu2007_raw(ph, sr, ve, nu0, r, s, coefficients=XU2007_COEFFICIENTS, *,
               exponents: str = "xu2007"):
    """The EHL regression of Eqs. 23-24 on numbers as given (no unit conversion).

    ``exponents="xu2007"``: Xu et al. (2007), mu = e^f Ph^b2 |SR|^b3 Ve^b6 nu0^b7 R^b8
    (docs/derivations.md, sec. 4.2); with :data:`XU2007_COEFFICIENTS` and Ph [GPa],
    Ve [m/s], nu0 [cP], R [m], S [um] it equals
    :func:`toothfem.efficiency.friction.ehl_xu2007`. ``exponents="eq23"``: the labels as
    printed in the paper's Eq. 23, Ph^b1 |SR|^b2 U^b3 eta0^b4 R^b5.
    f = b1 + b4 |SR| Ph log10(nu0) + b5 exp(-|SR| Ph log10(nu0)) + b9 exp(S) in both.
    Overflow gives inf (absurd readings are reported, not refused).
    """
    b = tuple(float(c) for c in coefficients)
    with np.errstate(all="ignore"):
        ph, sr, ve = np.asarray(ph, float), np.abs(np.asarray(sr, float)), np.asarray(ve, float)
        nu0, r, s = np.asarray(nu0, float), np.asarray(r, float), np.asarray(s, float)
        x = sr * ph * np.log10(nu0)
        f = b[0] + b[3] * x + b[4] * np.exp(-x) + b[8] * np.exp(s)
        if exponents == "xu2007":
            return np.exp(f) * ph**b[1] * sr**b[2] * ve**b[5] * nu0**b[6] * r**b[7]
        if exponents == "eq23":
            return np.exp(f) * ph**b[0] * sr**b[1] * ve**b[2] * nu0**b[3] * r**b[4]
    raise ToothfemError(f"exponents = {exponents!r} is not one of ['xu2007', 'eq23']")


#: Numbers fed to Eq. 23, as factors from SI (Pa, m/s, Pa s, m, m) for
#: (Ph, U, eta0, R, Ra). 'regression': Xu's units (GPa, m/s, cP, m, um); 'thesis': Ph in
#: MPa as Xu's thesis table labels it; 'paper_mm': the N-mm-MPa-s system of the paper's
#: Tables 2-3 (MPa, mm/s, MPa s -- Table 3's 2e-8 --, mm, um); 'si': plain SI.
UNIT_SYSTEMS = {
    "regression": (1e-9, 1.0, 1e3, 1.0, 1e6),
    "thesis": (1e-6, 1.0, 1e3, 1.0, 1e6),
    "paper_mm": (1e-6, 1e3, 1e-6, 1e3, 1e6),
    "si": (1.0, 1.0, 1.0, 1.0, 1.0),
}
_COEFFICIENT_SETS = {
    "xu2007": (XU2007_COEFFICIENTS, "xu2007"),
    "table1": (TABLE1_COEFFICIENTS, "xu2007"),
    "eq23_printed": (TABLE1_COEFFICIENTS, "eq23"),
}
_VELOCITIES = ("eq5", "rolling", "absolute")
_RADII = ("conformal", "planet", "external")
_TORQUES = ("output", "input")
_LOAD_RULES = ("spread", "single")


@dataclass(frozen=True)
class PaperReading:
    """One reading of the paper's Eqs. 15-25 (every choice the text leaves open or prints
    wrongly). Defaults: the paper's structure evaluated consistently in SI.

    ``pairs_in_mesh``: z_s of Eq. 18 (not given in the paper). ``load_rule``: 'spread' --
    the z_s pairs' phases are spread over the flank, so sum cos^2(alpha_i) r_i =
    z_s <cos^2(alpha) r>_flank and F = F0 cos(alpha_k1) (Eq. 17), zero at tip and root;
    'single' -- Eq. 19 for the one pair (z_s = 1): F = T/(r cos(alpha)), infinite at tip
    and root (alpha = 90 deg there).
    ``torque``: 'output' T2 = |i12| T1 in Eq. 19, or 'input' T1 (Table 3 gives only T1).
    ``velocities``: 'eq5' (v12 of Eq. 4, U12 of Eq. 5, crank frame), 'rolling' (v12 of
    Eq. 4, rolling speed relative to the contact point), 'absolute' (planet spinning at its
    absolute speed about a fixed centre, ring fixed, carrier ignored: v = |omega_out| r,
    U = v/2, SR = 2).
    ``radius``: see :meth:`FlankKinematics.equivalent_radius`.
    ``coefficients``: 'xu2007' (corrected), 'table1' (Table 1 as printed, in Xu's places),
    'eq23_printed' (Table 1 and Eq. 23's exponent labels as printed).
    ``units``: key of :data:`UNIT_SYSTEMS`. ``loss_factor``: multiplies Eq. 21's loss
    (1e3: loss in N mm/s compared with a power in W).
    P_h = sqrt(W E'/(2 pi R)) with W = F/L and E' = 2E* (the paper's right-hand form).
    """
    label: str = "consistent"
    pairs_in_mesh: int = 2
    load_rule: str = "spread"
    torque: str = "output"
    velocities: str = "eq5"
    radius: str = "conformal"
    coefficients: str = "xu2007"
    units: str = "regression"
    loss_factor: float = 1.0

    def __post_init__(self):
        check_range("pairs_in_mesh", self.pairs_in_mesh, 1, None)
        if int(self.pairs_in_mesh) != self.pairs_in_mesh:
            raise ToothfemError(f"pairs_in_mesh = {self.pairs_in_mesh!r} must be an integer")
        for name, allowed in (("load_rule", _LOAD_RULES), ("torque", _TORQUES),
                              ("velocities", _VELOCITIES), ("radius", _RADII),
                              ("coefficients", tuple(_COEFFICIENT_SETS)),
                              ("units", tuple(UNIT_SYSTEMS))):
            if getattr(self, name) not in allowed:
                raise ToothfemError(f"{name} = {getattr(self, name)!r} is not one of "
                                    f"{list(allowed)}")
        if self.load_rule == "single" and self.pairs_in_mesh != 1:
            raise ToothfemError(f"pairs_in_mesh = {self.pairs_in_mesh} with load_rule "
                                "'single': Eq. 19 for one pair means z_s = 1")
        check_range("loss_factor", self.loss_factor, 0, None, lo_open=True)


#: The readings tabulated in docs/sine_mesh_efficiency.md (sec. 3). 'table1_sign' is the
#: one that reproduces the published range with the fewest departures from the text.
PAPER_READINGS = {
    "consistent": PaperReading(),
    "consistent_zs40": PaperReading("consistent, z_s = 40 (half the teeth)", 40),
    "single_pair": PaperReading("Eq. 19 for one pair (z_s = 1)", 1, load_rule="single"),
    "input_torque": PaperReading("T1 instead of T2 in Eq. 19", torque="input"),
    "rolling": PaperReading("rolling speed instead of Eq. 5", velocities="rolling"),
    "radius_planet": PaperReading("R = 1/K1 (Eq. 7 alone)", radius="planet"),
    "radius_external": PaperReading("R = 1/(|K1| + |K2|)", radius="external"),
    "paper_units": PaperReading("N-mm-MPa-s numbers in Xu's formula", units="paper_mm"),
    "as_printed": PaperReading("Eq. 23 + Table 1 as printed, N-mm-MPa-s, R = 1/K1",
                               coefficients="eq23_printed", units="paper_mm",
                               radius="planet"),
    "absolute": PaperReading("absolute speeds, carrier ignored (SR = 2)",
                             velocities="absolute"),
    "table1_sign": PaperReading("Table 1 as printed (b1 = +8.916)", coefficients="table1"),
    "mpa_x1000": PaperReading("Ph in MPa, R = 1/K1, Eq. 21 x 1e3, z_s = 20", 20,
                              radius="planet", units="thesis", loss_factor=1e3),
}


@dataclass(frozen=True)
class PaperMeshEfficiency(_EfficiencyRange):
    """Efficiency along one flank under a :class:`PaperReading` (arrays (N,), SI)."""
    reading: PaperReading
    kinematics: FlankKinematics
    force_N: np.ndarray
    ph_Pa: np.ndarray
    sliding: np.ndarray
    entrainment: np.ndarray
    slide_to_roll: np.ndarray
    equivalent_radius: np.ndarray
    mu: np.ndarray
    loss_W: np.ndarray
    power_W: float
    efficiency: np.ndarray = field(repr=False)

    @property
    def mean(self) -> float:
        """Mean over the profile angle phi (the paper's axis)."""
        return _trapezoid_mean(self.efficiency, self.kinematics.profile_angle)

    @property
    def time_mean(self) -> float:
        """Mean over time (crank angle): the energy average."""
        return _trapezoid_mean(self.efficiency, self.kinematics.crank_angle)


def _trapezoid_mean(y, x) -> float:
    y = np.asarray(y, float)
    if not np.all(np.isfinite(y)):
        return float(np.nan) if np.any(np.isnan(y)) else float(np.min(y))
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)) / (x[-1] - x[0]))


def paper_mesh_efficiency(kinematics: FlankKinematics, conditions: SineMeshConditions,
                          reading: PaperReading = PaperReading(),
                          face_width_m: float = 8e-3) -> PaperMeshEfficiency:
    """Eqs. 15-25 along one flank under ``reading``.

    F (Eqs. 17-19), W = F/L (Eq. 15), P_h = sqrt(W E'/(2 pi R)), SR = v12/U12,
    mu from Eq. 23 (``reading.coefficients``, ``reading.units``),
    P_s = mu F v12 x ``loss_factor`` (Eq. 21 in SI), eta = 1 - P_s / (T1 omega_H) (Eq. 25).
    """
    check_range("face_width_m", face_width_m, 0, None, lo_open=True)
    k = kinematics
    z1, z2 = k.planet_teeth, k.ring_teeth
    t1 = conditions.input_torque_Nm
    torque = t1 * z1 / (z2 - z1) if reading.torque == "output" else t1
    ca = np.cos(k.pressure_angle)
    with np.errstate(divide="ignore", invalid="ignore"):
        if reading.load_rule == "single":
            force = torque / (k.contact_radius * ca)
        else:
            c2r = _trapezoid_mean(ca**2 * k.contact_radius, k.profile_angle)
            force = torque / (reading.pairs_in_mesh * c2r) * ca
    force = np.where(np.isfinite(force), np.maximum(force, 0.0), np.inf)
    if reading.velocities == "absolute":
        sliding = abs(k.crank_speed_rad_s) * (z2 - z1) / z1 * k.contact_radius
        entrain = 0.5 * sliding
    else:
        sliding = k.sliding
        entrain = k.entrainment_eq5 if reading.velocities == "eq5" else k.entrainment_rolling
    radius = k.equivalent_radius(reading.radius)
    e_prime = 2 * conditions.e_star_Pa
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ph = np.sqrt(force / face_width_m * e_prime / (2 * math.pi * radius))
        sr = sliding / entrain
        fp, fu, fe, fr, fs = UNIT_SYSTEMS[reading.units]
        coef, expo = _COEFFICIENT_SETS[reading.coefficients]
        mu = xu2007_raw(ph * fp, sr, entrain * fu, conditions.dynamic_viscosity_Pa_s * fe,
                        radius * fr, conditions.roughness_Ra_m * fs, coef, exponents=expo)
        # no load or no sliding: no loss (mu may be 0 * inf = nan there)
        idle = (force == 0) | (sliding == 0)
        mu = np.where(idle, 0.0, mu)
        loss = np.where(idle, 0.0, mu * force * sliding * reading.loss_factor)
    loss = np.where(np.isnan(loss), np.inf, loss)
    power = conditions.input_power_W
    return PaperMeshEfficiency(reading, k, force, ph, sliding, entrain, sr, radius, mu, loss,
                               power, 1.0 - loss / power)
