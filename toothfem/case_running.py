"""The case file's sections of how the reducer runs: the operating point, the lubricant and
friction, the seals, bearings and housing's heat (the sizes the drive's geometry leaves
out), the duty cycle and the measured points. The same frozen dataclasses with their
schema in the fields' metadata as :mod:`toothfem.case_sections` (its ``_f`` and
``_Section``)."""
from __future__ import annotations

from dataclasses import dataclass

from .case_checks import (BEARING_RATING_KN, DRAG_NMM, EXTERNAL_LOAD_N, EXTERNAL_MOMENT_NM,
                          HEAT_CAPACITY_J_K, HOUSING_AREA_M2, INPUT_TORQUE_NM, LOAD_ARM_MM,
                          PITCH_DIAMETER_MM, POWER_KW, PRELOAD_N, RADIUS_MM, SPEED_RPM,
                          SUPPORT_MM, TORQUE_NM)
from .case_sections import _f, _Section
from .errors import CaseError, check_range

#: What an unset load key of [operating] stands for, and why.
_LOAD_UNSET = "from the load key given"


_LOAD_SOURCE = ("one of output_torque_Nm, input_torque_Nm and input_power_kW is required; "
                "the others follow from it")


@dataclass(frozen=True)
class Operating(_Section):
    _section = "operating"
    input_speed_rpm: float = _f(*SPEED_RPM, default=1000.0,
                                source="ASSUMPTION: a round input speed (no source)")
    output_torque_Nm: float | None = _f(*TORQUE_NM, default=None, unset=_LOAD_UNSET,
                                        source=_LOAD_SOURCE)
    input_torque_Nm: float | None = _f(*INPUT_TORQUE_NM, default=None, unset=_LOAD_UNSET,
                                       source=_LOAD_SOURCE)
    input_power_kW: float | None = _f(*POWER_KW, default=None, unset=_LOAD_UNSET,
                                      source=_LOAD_SOURCE)
    rated_torque_Nm: float | None = _f(
        *TORQUE_NM, default=None,
        doc="rated output torque of the reducer (catalogue, datasheet): check warns above "
            "it; the stiffness curve spans +-it",
        unset="the operating torque stands in",
        source="none: the catalogue's rated torque where the case states it")
    start_stop_torque_Nm: float | None = _f(
        *TORQUE_NM, default=None,
        doc="allowable output torque when starting and stopping (catalogue): above it a "
            "warning",
        unset="no check",
        source="none: the catalogue's figure where the case states it (RV-40E: 1029 N m)")
    momentary_torque_Nm: float | None = _f(
        *TORQUE_NM, default=None,
        doc="momentary maximum output torque (catalogue, e.g. an emergency stop): above it a "
            "warning that the reducer is damaged; rated <= start/stop <= momentary, else refused",
        unset="no check",
        source="none: the catalogue's figure where the case states it (RV-40E: 2058 N m)")

    # the dynamics (toothfem modes, docs/dynamics.md)
    motor_inertia_kgm2: float = _f(0.0, 1e4, default=0.0,
                                   doc="the motor's rotor inertia on the input (modes)",
                                   source="0: the reducer's own input parts alone")
    load_inertia_kgm2: float = _f(0.0, 1e6, default=0.0,
                                  doc="the driven load's inertia on the output (modes)",
                                  source="0: the reducer's own output flange alone")
    max_input_speed_rpm: float | None = _f(*SPEED_RPM, default=None,
                                           doc="top of the speed range of the Campbell "
                                               "diagram's crossings",
                                           unset="the highest input speed the case names",
                                           source="none: the case's operating and duty "
                                                  "speeds")

    def _check(self):
        limits = [("rated_torque_Nm", self.rated_torque_Nm),
                  ("start_stop_torque_Nm", self.start_stop_torque_Nm),
                  ("momentary_torque_Nm", self.momentary_torque_Nm)]
        given = [(k, v) for k, v in limits if v]
        for (k1, v1), (k2, v2) in zip(given, given[1:]):
            if v2 < v1:
                raise CaseError(f"operating.{k2} = {v2:g} is below operating.{k1} = {v1:g}: "
                                "rated <= start/stop <= momentary")


#: Where the Vogel constants' defaults come from (docs/efficiency.md, "Oil temperature").
_VOGEL_SOURCE = ("ASSUMPTION: a mineral oil; B = 1000, C = 95 °C take 100 mm²/s at 40 °C to "
                 "10.2 at 100 °C (B = 900 reproduces ISO VG 68's 68 -> 8.7 within 5 %)")


@dataclass(frozen=True)
class Lubricant(_Section):
    _section = "lubricant"
    dynamic_viscosity_Pa_s: float = _f(1e-4, 10.0, default=0.02,
                                       doc="eta0 at the reference temperature (EHL friction)",
                                       source="the sine paper's Table 3: eta0 = 2e-8 MPa s")
    kinematic_viscosity_mm2_s: float = _f(0.1, 10000.0, default=100.0,
                                          doc="nu at the reference temperature (churning, "
                                              "Palmgren's drag, film thickness)",
                                          source="ASSUMPTION: ISO VG 100 (ISO 3448: 100 mm²/s "
                                                 "at 40 °C)")
    density_kg_m3: float = _f(500.0, 1500.0, default=870.0,
                              source="ASSUMPTION: a mineral gear oil (no source)")
    pressure_viscosity_1_per_GPa: float = _f(1.0, 50.0, default=20.0,
                                             doc="alpha of Barus' law (EHL film)",
                                             source="ASSUMPTION: typical of mineral gear oils "
                                                    "at moderate temperature, about 10-30 "
                                                    "1/GPa (efficiency/friction.py)")
    reference_temperature_C: float = _f(-40.0, 200.0, default=40.0,
                                        doc="where the viscosities above hold",
                                        source="ISO 3448: viscosity grades are stated at "
                                               "40 °C")
    roughness_Ra_um: float = _f(0.0, 10.0, default=0.4,
                                doc="arithmetic mean roughness of the flanks",
                                source="the sine paper's Table 3: R_a = 0.4 µm")
    vogel_B_C: float = _f(100.0, 5000.0, default=1000.0,
                          doc="Vogel B: eta = A exp(B/(T + C)), T in deg C",
                          source=_VOGEL_SOURCE)
    vogel_C_C: float = _f(0.0, 300.0, default=95.0, doc="Vogel C [deg C]",
                          source=_VOGEL_SOURCE)
    churning: str = _f(choices=("none", "lu_xu_2024"), default="lu_xu_2024",
                       doc="churning (oil agitation and splash) law of an oil bath; "
                           "lu_xu_2024: the sine paper's Eq. 42",
                       source="Y. Lu & L. Xu, Heliyon 10 (2024) e26300, Eq. 42, on every gear "
                              "stage in an oil bath (was none before issue 13)")
    churning_scale: float = _f(0.0, 100.0, default=1.0,
                               doc="factor on the churning law",
                               source="1: the law as published (the loop's churning effect "
                                      "fits a correction)")
    lubrication: str = _f(choices=("oil_bath", "oil_mist", "oil_jet", "grease"),
                          default="oil_bath",
                          doc="how the reducer is lubricated: the churning law acts in an oil "
                              "bath; the bearings' viscous drag takes Palmgren's f0 of it",
                          source="ASSUMPTION: a horizontal reducer with its lower half in oil "
                                 "(the sine paper's rig)")
    pour_point_C: float = _f(-80.0, 50.0, default=-15.0,
                             doc="lowest temperature of the viscosity law",
                             source="ASSUMPTION: mineral ISO VG 68-680 gear oils pour at about "
                                    "-9 to -30 °C (makers' data sheets)")
    max_temperature_C: float = _f(0.0, 300.0, default=150.0,
                                  doc="highest temperature of the viscosity law",
                                  source="the upper limit of mineral oil named in issue 13 "
                                         "(oxidation); ISO/TR 14179-1 rates gear drives at a "
                                         "95 °C sump")

    def _check(self):
        t_ref = self.reference_temperature_C
        if not self.pour_point_C < t_ref < self.max_temperature_C:
            raise CaseError(f"lubricant.reference_temperature_C = {t_ref!r} is outside the "
                            f"valid range ({self.pour_point_C:g}, {self.max_temperature_C:g})"
                            ": between pour_point_C and max_temperature_C")


@dataclass(frozen=True)
class Friction(_Section):
    _section = "friction"
    coefficient: float = _f(0.0, 1.0, default=0.05,
                            doc="Coulomb friction at the tooth/pin contacts (mesh_law = "
                                "coulomb only)",
                            source="ASSUMPTION: lubricated steel on steel (no source); read "
                                   "by the Coulomb law only")
    bearing_coefficient: float = _f(0.0, 0.1, default=0.0015,
                                    doc="rolling bearings' load term M1 = mu P d_m/2 "
                                        "(Palmgren's mu = 2 f1)",
                                    source="SKF's constant coefficient of friction of deep "
                                           "groove ball bearings, 0.0015 (SKF General "
                                           "Catalogue, Friction, Table 1)")
    output_pin_coefficient: float = _f(0.0, 1.0, default=0.05,
                                       doc="output pins sliding in their holes or sleeves "
                                           "(the sine paper's f_k)",
                                       source="ASSUMPTION: lubricated steel sliding (no "
                                              "source; the sine paper's rig: f_k = 0.03)")
    pin_groove_coefficient: float = _f(0.0, 1.0, default=0.0,
                                       doc="conventional pins sliding in their housing "
                                           "grooves (0: pins roll freely)",
                                       source="0: the pins roll freely in their grooves")
    mesh_law: str = _f(choices=("ehl_xu2007", "coulomb", "benedict_kelley"),
                       default="ehl_xu2007", doc="friction law at the tooth/pin contacts",
                       source="the sine paper's choice: Xu, Kahraman et al., J. Mech. Des. "
                              "129 (2007) 58-68")
    boundary_coefficient: float = _f(0.0, 1.0, default=0.1,
                                     doc="asperity (boundary) friction of lubricated steel "
                                         "in mixed lubrication; 0: the EHL law alone",
                                     source="boundary-lubricated steel, about 0.1 (Bowden & "
                                            "Tabor 1950; Hutchings & Shipway 2017: "
                                            "0.05-0.15); was 0 before issue 13")
    drag_torque_Nmm: float = _f(*DRAG_NMM, default=0.0,
                                doc="load-independent drag on the input shaft (seals, preload)",
                                source="0: no drag beyond the seals and bearings modelled")
    windage_torque_Nmm: float = _f(*DRAG_NMM, default=0.0,
                                   doc="drag on the input shaft at 1000 rpm that grows with "
                                       "the square of the speed (windage: P = T_w (n/1000 "
                                       "rpm)^2 omega_in; Dawson 1984)",
                                   source="0: these reducers turn slowly in an oil bath, "
                                          "whose churning law covers the bath")
    viscous_drag_Nmm: float = _f(*DRAG_NMM, default=0.0,
                                 doc="drag on the input shaft at 1000 rpm and the case's "
                                     "reference viscosity that grows in proportion to the "
                                     "speed and the oil's viscosity (a sleeve, bushing or "
                                     "close clearance shearing oil: Petroff's law, "
                                     "T = T_v (n/1000 rpm) eta/eta_ref)",
                                 source="0: no sheared oil film beyond the bearings and "
                                        "churning modelled")


BEARING_TYPES = ("ball", "angular_ball", "cylindrical", "tapered", "needle")


#: The source of the external loads' defaults.
_NO_LOAD = "0: no external load on the output"


@dataclass(frozen=True)
class Seals(_Section):
    """Radial lip seals on the input and the output shaft (ISO/TR 14179-1 seal loss).
    None: the drive's own diameter (efficiency/envelope.py, ASSUMPTION); 0: no seal."""
    _section = "seals"
    # a shaft no larger than the largest reducer the case model takes (RADIUS_MM)
    input_diameter_mm: float | None = _f(
        0.0, 2 * RADIUS_MM[1], default=None,
        doc="shaft diameter under the input seal; seal loss P = 7.69e-6 D² n W (D in mm, n in "
            "rpm), ISO/TR 14179-1:2001; 0: no seal",
        unset="the drive's (efficiency/envelope.py)",
        source="ASSUMPTION: cycloid, RV: the input shaft in the discs' centre bore; sine: "
               "through the eccentric bearing (2 r_p)")
    output_diameter_mm: float | None = _f(
        0.0, 2 * RADIUS_MM[1], default=None,
        doc="shaft diameter under the output seal; the same law at the output speed",
        unset="the drive's (efficiency/envelope.py)",
        source="ASSUMPTION: the pin-circle diameter (cycloid, RV); 2 (R_w + r_x) (sine)")


@dataclass(frozen=True)
class Bearings(_Section):
    """The bearings on the eccentrics (crank bearings in the discs' holes of a 2K-V drive,
    the eccentric bearing of a K-H-V drive) and the main (output) bearing pair, with the
    external loads on the output. None: the drive's own value (efficiency/envelope.py)."""
    _section = "bearings"
    eccentric_type: str | None = _f(choices=BEARING_TYPES, default=None,
                                    doc="rolling-element type of the eccentric bearings "
                                        "(ISO 281's exponent, Palmgren's f0)",
                                    unset="needle",
                                    source="RV reducers' crank bearings are needle roller "
                                           "bearings (Nabtesco's RV construction): the "
                                           "system model's rollers; another type is refused")
    eccentric_pitch_diameter_mm: float | None = _f(
        *PITCH_DIAMETER_MM, lo_open=True, default=None,
        doc="checked to lie between the journal and the hole (refused naming the hole's key)",
        unset="the rollers' pitch circle",
        source="the system model's rollers: the hole less one roller diameter (2K-V crank "
               "hole, K-H-V centre bore); 2 r_p plus one roller (sine)")
    eccentric_dynamic_rating_kN: float | None = _f(
        *BEARING_RATING_KN, lo_open=True, default=None,
        doc="basic dynamic load rating C of one eccentric bearing (ISO 281); refused above "
            "1.3x the rating of the rolling set that fits the hole",
        unset="ISO 281 of the rollers that fit (sine: no life)",
        source="ISO 281 of the needle rollers that fit the hole (efficiency/bearing_set.py); "
               "a sine reducer's has none")
    main_type: str = _f(choices=BEARING_TYPES, default="angular_ball",
                        doc="main bearing pair: angular contact ball bearings (RV-E)",
                        source="the RV-E's built-in main bearings; ISO 281:2007 Table 3 of a "
                               "40 deg contact: X = 0.35, Y = 0.57, e = 1.14")
    main_pitch_diameter_mm: float | None = _f(
        *PITCH_DIAMETER_MM, lo_open=True, default=None,
        unset="the pin-circle diameter (sine: 2 (R_w + r_x))",
        source="ASSUMPTION: the rows at the pin circle (Palmgren drag without an oil bath)")
    main_dynamic_rating_kN: float | None = _f(
        *BEARING_RATING_KN, lo_open=True, default=None,
        doc="basic dynamic load rating C of one main bearing row (ISO 281)",
        unset="ISO 281 of an assumed ball set (sine: none)",
        source="ASSUMPTION: ISO 281 of a ball set with balls 6 % of the pitch diameter "
               "(cycloid, RV); a sine reducer's has none")
    contamination: str | None = _f(
        choices=("extreme_cleanliness", "high_cleanliness", "normal_cleanliness",
                 "slight_contamination", "typical_contamination", "severe_contamination",
                 "very_severe_contamination"), default=None,
        doc="lubricant cleanliness (ISO 281:2007 Table 13): with it, the modified life "
            "L10m = a_ISO L10 of every bearing",
        unset="no modified life",
        source="none: ISO 281's basic rating life L10 alone")
    main_span_mm: float | None = _f(*SUPPORT_MM, lo_open=True, default=None,
                                    doc="distance between the load centres of the two rows",
                                    unset="needed with an external moment",
                                    source="none: needed only with an external moment")
    main_preload_N: float | None = _f(*PRELOAD_N, default=None,
                                      doc="axial preload of each main bearing row",
                                      unset="ASSUMPTION 2 % of the row's C0",
                                      source="ASSUMPTION: a light preload of makers' matched "
                                             "angular contact pairs is about 1-2 % of C0")
    external_radial_load_N: float = _f(*EXTERNAL_LOAD_N, default=0.0, source=_NO_LOAD)
    external_axial_load_N: float = _f(*EXTERNAL_LOAD_N, default=0.0, source=_NO_LOAD)
    external_moment_Nm: float = _f(*EXTERNAL_MOMENT_NM, default=0.0,
                                   doc="tilting moment on the output besides the one the "
                                       "offsets below give",
                                   source=_NO_LOAD)
    external_radial_offset_mm: float = _f(*LOAD_ARM_MM, default=0.0,
                                          doc="axial distance from the main pair's centre to "
                                              "the radial load's line (its moment arm)",
                                          source=_NO_LOAD)
    external_axial_radius_mm: float = _f(*LOAD_ARM_MM, default=0.0,
                                         doc="distance from the axis to the axial load's line "
                                             "(its moment arm)",
                                         source=_NO_LOAD)


@dataclass(frozen=True)
class Thermal(_Section):
    """Heat balance of the housing: losses = h A (T_oil - T_ambient). None: a cited
    estimate (efficiency/thermal.py)."""
    _section = "thermal"
    ambient_C: float = _f(-40.0, 100.0, default=20.0,
                          doc="ambient air; within [pour point, max_temperature_C) of the oil",
                          source="ASSUMPTION: a laboratory")
    housing_area_m2: float | None = _f(*HOUSING_AREA_M2, lo_open=True, default=None,
                                       doc="surface that sheds heat",
                                       unset="6 pi r² of the housing radius r",
                                       source="ASSUMPTION: a cylinder of the housing radius as "
                                              "long as its diameter (RV-40E: 0.118 m² against "
                                              "about 0.12 m² of the real reducer)")
    heat_transfer_W_m2K: float | None = _f(0.0, 1000.0, lo_open=True, default=None,
                                           doc="heat transfer coefficient of the housing's "
                                               "surface",
                                           unset="natural convection + radiation at each "
                                                 "temperature",
                                           source="J.P. Holman, Heat Transfer (10th ed.), "
                                                  "Table 7-2: a horizontal cylinder in air, "
                                                  "h = 1.32 (dT/d)^(1/4), plus radiation")
    emissivity: float = _f(0.0, 1.0, default=0.9,
                           doc="of the housing's surface (radiation)",
                           source="painted housing: Incropera & DeWitt, Fundamentals of Heat "
                                  "and Mass Transfer, Table A.11 (paints 0.90-0.98)")
    heat_capacity_J_K: float | None = _f(*HEAT_CAPACITY_J_K, lo_open=True, default=None,
                                         doc="lumped heat capacity",
                                         unset="half the housing envelope in steel at "
                                               "450 J/(kg K)",
                                         source="ASSUMPTION on the share (an RV-40E weighs "
                                                "about 9 kg, 0.4 of its envelope); steel: 434-477 "
                                                "J/(kg K) at 300 K (Incropera & DeWitt, Table "
                                                "A.1)")
    sensor_resistance_K_W: float = _f(0.0, 20.0, default=0.0,
                                      doc="oil at the contacts above a sump sensor per W "
                                          "of loss (the loop's thermal effect; 0: none)",
                                      source="0: none; fitted by the loop's thermal effect "
                                             "(docs/loop.md)")
    case_temperature_limit_C: float | None = _f(0.0, 300.0, lo_open=True, default=None,
                                                doc="the maker's limit of the case surface "
                                                    "(a warning above it)",
                                                unset="60 °C for a 2K-V drive, 100 °C for "
                                                      "K-H-V and sine drives",
                                                source="Nabtesco RV-E catalogue: the surface "
                                                       "at most 60 °C (ASSUMPTION for another "
                                                       "maker's RV); K-H-V, sine: nitrile lip "
                                                       "seals to +100 °C (Neale, The Tribology "
                                                       "Handbook, 'Lip seals'; ASSUMPTION: nitrile "
                                                       "seals, no maker's figure found)")
    mounting: str = _f(choices=("free", "flange"), default="free",
                       doc="free: the housing sheds heat to the air only (convection and "
                           "radiation); flange: one end face is bolted to a machine that "
                           "conducts heat away",
                       source="ASSUMPTION: no conduction into a machine (the hotter case)")
    contact_conductance_W_m2K: float = _f(1.0, 1e6, default=1000.0,
                                          doc="thermal contact conductance of the bolted "
                                              "flange joint",
                                          source="ASSUMPTION: bolted steel joints 400-1700 "
                                                 "W/(m² K) (Incropera & DeWitt, Table 3.1)")
    mount_conductivity_W_mK: float = _f(0.1, 1000.0, default=50.0,
                                        doc="thermal conductivity of the machine the flange "
                                            "is bolted to",
                                        source="steel (Incropera & DeWitt, Table A.1: carbon "
                                               "steel 60.5, AISI 4140 42.6)")


@dataclass(frozen=True)
class DutyPoint(_Section):
    """One row of a duty cycle: output torque, input speed and the share of time."""
    _section = "duty_cycle"
    output_torque_Nm: float = _f(*TORQUE_NM, doc="load torque of the row (the range of "
                                 "[operating] output_torque_Nm)")
    input_speed_rpm: float = _f(*SPEED_RPM, doc="input speed of the row (the range of "
                                "[operating] input_speed_rpm)")
    time_share: float = _f(0.0, 1.0, lo_open=True,
                           doc="share of the operating time; the rows' shares add up to 1")


#: Tolerance on the sum of a duty cycle's time shares (shares quoted to three digits).
DUTY_SHARE_TOL = 1e-3


def check_ambient(thermal: Thermal, lubricant: Lubricant) -> None:
    """Refuse an ambient at which the oil is outside its range (below its pour point, at or
    above its upper limit).

    Parameters
    ----------
    thermal : Thermal
        The ``[thermal]`` section (ambient [deg C]).
    lubricant : Lubricant
        The ``[lubricant]`` section (pour point and upper limit [deg C]).

    Raises
    ------
    CaseError
        One line with the valid range.
    """
    lo, hi = lubricant.pour_point_C, lubricant.max_temperature_C
    if not lo <= thermal.ambient_C < hi:
        raise CaseError(f"thermal.ambient_C = {thermal.ambient_C!r} is outside the valid "
                        f"range [{lo:g}, {hi:g}): the lubricant's pour_point_C to "
                        "max_temperature_C")


def check_duty_cycle(rows) -> None:
    """Refuse a duty cycle whose time shares do not sum to 1.

    Parameters
    ----------
    rows : sequence of DutyPoint
        The ``[[duty_cycle]]`` rows (empty: nothing to check).

    Raises
    ------
    CaseError
        One line with the sum and the valid range (1 within DUTY_SHARE_TOL).
    """
    if rows:
        total = float(sum(r.time_share for r in rows))
        check_range("duty_cycle time_share sum", total, 1 - DUTY_SHARE_TOL,
                    1 + DUTY_SHARE_TOL, error=CaseError,
                    why="the shares of time must add up to 1")


@dataclass(frozen=True)
class MeasuredPoint(_Section):
    _section = "measured"
    input_speed_rpm: float = _f(*SPEED_RPM)
    output_torque_Nm: float = _f(*TORQUE_NM)
    efficiency: float = _f(0.0, 1.0, lo_open=True, doc="output power / input power")
    source: str = _f(default="", doc="where the point comes from",
                     source="empty: none stated")
