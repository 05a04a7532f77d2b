"""The wear rates of a cycloid reducer's contacts from its system model's loads: the pins on
the discs, the crank (eccentric) bearings, the crank support bearings and a K-H-V drive's
output pins in their holes, each turned into the clearance it opens (docs/wear.md). The
law and its coefficient: efficiency/wear.py.

Pins on a disc: over one meshing period (one pin pitch of crank angle, P positions) every
loaded contact c at position p slides |v_s| dphi (v_s at unit crank speed) under its force
F; the disc and the pin each lose K F |v_s| dphi / H per period (Archard, per surface; K by
the contact's film ratio). The volume spreads over the surface the contacts sweep: the
disc's loaded flank band (its arc length in the disc's frame, summed over the contacts'
travel in one period, on each of its Z_a lobes) and each pin's arc under its contact
normals (the pins held in their grooves: ASSUMPTION, a pin turning in its groove would
spread its share over its whole circumference). The disc's flank receding by h_d along
its normal, and the pin's loaded arc by h_p, open the gap at every pin position as an
equidistant modification of h_d + h_p does.

Rolling bearings: a roller's contact on a race slides a share SLIP of the distance it rolls
(micro-slip and cage drag; ASSUMPTION), under the rollers' summed load sum Q = Q_SUM_PER_FR
F_r / cos(alpha) (the load zone of a line-contact set with zero play: sum Q_j / F_r =
int cos^(10/9) / int cos^(19/9) over +-90 deg). Each race loses K sum Q SLIP v_r / H per
unit time, v_r = omega (d_m^2 - D^2) / (4 d_m) the rolling speed over a race (the cage at
its epicyclic speed). Spread over the race (pi d l: a race under a rotating load), its
depth is uniform and the diametral play grows by twice it; a race under a fixed load wears
its load zone (half the circumference) twice as deep on one side only: the same play
along the load, so one formula serves both.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import friction as fr
from .wear import run_in_factor, run_in_roughness, wear_coefficient, REGIMES, regime
from ..units import S_PER_H

#: ASSUMPTION: the share of the rolling distance a roller's race contact slides (micro-slip
#: of line contacts and cage drag in lubricated roller bearings: 1-3 %, after T.A. Harris &
#: M.N. Kotzalas, *Essential Concepts of Bearing Technology*, 5th ed., 2007, ch. 9 on
#: rolling friction and slip; the middle taken).
SLIP = 0.02


def _roller_sum_factor(samples: int = 2001) -> float:
    psi = np.linspace(-math.pi / 2, math.pi / 2, samples)
    c = np.cos(psi)
    return float(np.trapezoid(c ** (10 / 9), psi) / np.trapezoid(c ** (19 / 9), psi))


#: sum Q_j / F_r of a line-contact roller set with zero play (module docstring).
Q_SUM_PER_FR = _roller_sum_factor()
#: Stribeck's factor of a line-contact set with zero play: Q_max = 4.08 F_r / Z (Harris &
#: Kotzalas 2007, ch. 7), the contact whose film ratio sets the bearing's K.
Q_MAX_STRIBECK = 4.08


@dataclass(frozen=True)
class ContactWear:
    """One element's wear at one load state, per hour of that state.

    ``volume_m3_per_h``: each surface's worn volume; ``depth_m_per_h``: each surface's
    depth; ``clearance_m_per_h``: the clearance it opens (an equidistant modification for
    the mesh, the diametral play of a bearing); ``film_ratio``: the load-weighted mean;
    ``regime_share``: the share of F v_s in each regime of REGIMES; ``k_mean``: the
    F v_s-weighted K."""
    element: str
    volume_m3_per_h: dict
    depth_m_per_h: dict
    clearance_m_per_h: float
    film_ratio: float
    regime_share: dict
    k_mean: float


def _shares(lam, weight) -> dict:
    total = float(np.sum(weight))
    names = regime(lam)
    return {r: (float(np.sum(weight[names == r])) / total if total > 0 else 0.0)
            for r in REGIMES}


def _film_ratio(ve, eta, r_eq, w_per_length, e_star, alpha, sigma):
    with np.errstate(divide="ignore", invalid="ignore"):
        hc = fr.central_film_thickness_line(ve, eta, r_eq, w_per_length, e_prime=2 * e_star,
                                            pressure_viscosity=alpha)
    return np.where(np.isfinite(hc) & (hc > 0), hc / sigma, 0.0)


def swept_arc(points, loaded) -> float:
    """The arc the contacts sweep over one period: the sum of each contact's steps between
    loaded neighbouring positions.

    Parameters
    ----------
    points : numpy.ndarray, shape (P, C, 2)
        Each contact's point in the worn body's frame [m].
    loaded : numpy.ndarray, shape (P, C) of bool

    Returns
    -------
    float
        [m].
    """
    step = np.linalg.norm(np.diff(points, axis=0), axis=-1)
    both = loaded[1:] & loaded[:-1]
    return float(np.sum(step[both]))


def pin_disc_wear(si, drive, record, meshing, *, crank_speed_rad_s: float, k_boundary: float,
                  worn_depth_m: float, disc_turn_rad) -> ContactWear:
    """One disc's contacts with its pins: the worn volumes, depths and the equidistant
    clearance they open, per hour at this load (module docstring).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        The lubricant, hardness and roughness.
    drive : toothfem.fem.drives.cycloid.CycloidDrive
        Its geometry (lobes, pins, pin radius) and E*.
    record : toothfem.fem.load_sharing.LoadSharing
        The disc's loads over one period (the system model's).
    meshing : toothfem.geometry.kinematics.MeshingState
        Its meshing at the record's positions, unit crank speed.
    crank_speed_rad_s : float
        The crank's speed against the pins [rad/s].
    k_boundary : float
        K_b [-].
    worn_depth_m : float
        The pair's worn depth so far (the roughness's run-in) [m].
    disc_turn_rad : array_like, shape (P,)
        The disc's rotation at each position (its frame for the swept flank).

    Returns
    -------
    ContactWear
    """
    f = np.asarray(record.force, float)
    loaded = f > 0
    b = float(record.face_width)
    lub = si.lubricant
    hard = si.material.hardness_Pa
    omega = abs(float(crank_speed_rad_s))
    ve = np.abs(meshing.entrainment_velocity) * omega
    sigma0 = fr.composite_rms_roughness(lub.roughness_Ra_m)
    sigma = float(run_in_roughness(sigma0, worn_depth_m))
    k_boundary = k_boundary * float(run_in_factor(worn_depth_m, sigma0))
    lam = np.full(f.shape, np.inf)
    lam[loaded] = _film_ratio(ve[loaded], lub.dynamic_viscosity_Pa_s,
                              record.equivalent_radius[loaded], f[loaded] / b, drive.e_star_Pa,
                              lub.pressure_viscosity_1_per_Pa, sigma)
    k = np.zeros(f.shape)
    k[loaded] = wear_coefficient(k_boundary, lam[loaded], record.ph[loaded], hard)
    n_pos = f.shape[0]
    # each surface's volume per period: sum K F |v_s| dphi / H, dphi = period / P; periods
    # per hour: omega 3600 / period
    weight = f * np.abs(meshing.sliding_velocity)                  # per unit crank speed
    per_hour = omega * S_PER_H / n_pos
    volume = float(np.sum(k * weight)) / hard * per_hour
    g = drive.geometry
    # the disc's flank band, in its own frame
    rel = np.asarray(record.point, float) - np.asarray(meshing.centre, float)[:, None, :]
    turn = -np.asarray(disc_turn_rad, float)
    cos, sin = np.cos(turn)[:, None], np.sin(turn)[:, None]
    in_disc = np.stack([cos * rel[..., 0] - sin * rel[..., 1],
                        sin * rel[..., 0] + cos * rel[..., 1]], axis=-1)
    hw = float(np.mean(record.half_width[loaded])) if np.any(loaded) else 0.0
    arc_disc = max(swept_arc(in_disc, loaded), 2 * hw)
    # each pin's loaded arc: the contact normals' directions on it
    arc_pin = max(g.pin_radius_m * swept_arc(-np.asarray(meshing.normal, float), loaded),
                  2 * hw)
    depth = {"disc flank": volume / (drive.stage.lobe_count * b * arc_disc),
             "pins": volume / (g.pin_count * b * arc_pin)}
    w = weight[loaded]
    return ContactWear(element="mesh", volume_m3_per_h={"disc flank": volume, "pins": volume},
                       depth_m_per_h=depth, clearance_m_per_h=sum(depth.values()),
                       film_ratio=float(np.sum(np.where(np.isfinite(lam[loaded]),
                                                        lam[loaded], 0.0) * f[loaded])
                                        / max(np.sum(f[loaded]), 1e-300)),
                       regime_share=_shares(lam[loaded], w),
                       k_mean=float(np.sum(k[loaded] * w) / max(np.sum(w), 1e-300)))


def bearing_wear(si, drive, bearing, radial_load_N, *, speed_rad_s: float, k_boundary: float,
                 worn_depth_m: float, element: str) -> ContactWear:
    """A rolling bearing's races: the worn volumes and depths and the diametral play they
    open, per hour at this load (module docstring).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
        E* of the steel pair.
    bearing : toothfem.efficiency.bearing_set.Bearing
        Its rolling set (pitch diameter, rollers, length, contact angle).
    radial_load_N : array_like
        Its radial load at the positions [N] (the mean is taken: the races sweep them all).
    speed_rad_s : float
        The rotating ring's speed against the other [rad/s].
    k_boundary : float
    worn_depth_m : float
        The races' worn depth so far (run-in) [m].
    element : str
        Its name in the outputs.

    Returns
    -------
    ContactWear
    """
    fr_n = np.asarray(radial_load_N, float)
    d_m, dia = bearing.pitch_diameter_m, bearing.element_diameter_m
    length = bearing.element_length_m or bearing.width_m
    ca = math.cos(math.radians(bearing.contact_angle_deg))
    hard = si.material.hardness_Pa
    lub = si.lubricant
    omega = abs(float(speed_rad_s))
    v_roll = omega * (d_m ** 2 - (dia * ca) ** 2) / (4.0 * d_m)
    sigma0 = fr.composite_rms_roughness(lub.roughness_Ra_m)
    sigma = float(run_in_roughness(sigma0, worn_depth_m))
    k_boundary = k_boundary * float(run_in_factor(worn_depth_m, sigma0))
    q_max = Q_MAX_STRIBECK * fr_n / (bearing.elements * ca)
    e_star = drive.e_star_Pa
    volume, depth, lam_w, k_w, shares = {}, {}, [], [], []
    for race, d_race in (("inner race", d_m - dia * ca), ("outer race", d_m + dia * ca)):
        sign = 1.0 if race == "inner race" else -1.0
        r_eq = 1.0 / (2.0 / dia + sign * 2.0 / d_race)
        w = q_max / length
        lam = _film_ratio(np.full(fr_n.shape, v_roll), lub.dynamic_viscosity_Pa_s, r_eq, w,
                          e_star, lub.pressure_viscosity_1_per_Pa, sigma)
        ph = np.sqrt(np.maximum(w, 0.0) * e_star / (math.pi * r_eq))
        k = wear_coefficient(k_boundary, lam, ph, hard)
        q_sum = Q_SUM_PER_FR * fr_n / ca
        v = float(np.mean(k * q_sum)) * SLIP * v_roll / hard * S_PER_H
        volume[race] = v
        depth[race] = v / (math.pi * d_race * length)
        lam_w.append(float(np.mean(lam)))
        k_w.append(float(np.mean(k)))
        shares.append(_shares(lam, q_sum))
    return ContactWear(element=element, volume_m3_per_h=volume, depth_m_per_h=depth,
                       clearance_m_per_h=2.0 * sum(depth.values()),
                       film_ratio=float(np.mean(lam_w)),
                       regime_share={r: float(np.mean([s[r] for s in shares]))
                                     for r in REGIMES},
                       k_mean=float(np.mean(k_w)))


def output_pin_wear(si, drive, om, pin_force_N, *, speed_rad_s: float, k_boundary: float,
                    worn_depth_m: float) -> ContactWear:
    """The output flange's pins in the members' holes (K-H-V): each pin slides on its hole
    (or in its sleeve) at 2 e w_rel (the sine paper's Eq. 38, as the efficiency model's
    output loss: docs/derivations.md 7) under its load; both surfaces of that interface
    lose K Q v_s / H, spread over their circumference (the contact goes round each once a
    turn of the crank against the member), and the radial clearance between pin and hole
    grows by the two depths.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
        Its eccentricity, face width and E*.
    om : toothfem.si.OutputMechanismSI
        The pins, their rollers and holes.
    pin_force_N : array_like, shape (P, M, n_o)
        Each pin's load on each member's hole at the positions [N].
    speed_rad_s : float
        w_rel, the crank against the member [rad/s].
    k_boundary : float
    worn_depth_m : float
        The interface's worn depth so far (run-in) [m].

    Returns
    -------
    ContactWear
        ``clearance_m_per_h``: the radial clearance's growth (the system model's gap).
    """
    q = np.abs(np.asarray(pin_force_N, float))
    e = drive.geometry.eccentricity_m
    b = drive.face_width_m
    hard = si.material.hardness_Pa
    lub = si.lubricant
    v_s = 2.0 * e * abs(float(speed_rad_s))
    r_in = om.pin_radius_m                       # the sliding interface's inner surface:
    r_out = (om.roller_radius_m if om.roller_radius_m is not None    # the sleeve's bore or
             else (om.hole_radius_m or om.pin_radius_m + e))          # the hole
    if om.roller_radius_m is not None:
        r_out = r_in                               # a sleeve on its pin: conformal
    sigma0 = fr.composite_rms_roughness(lub.roughness_Ra_m)
    sigma = float(run_in_roughness(sigma0, worn_depth_m))
    k_b = k_boundary * float(run_in_factor(worn_depth_m, sigma0))
    loaded = q > 0
    r_eq = r_in if r_out <= r_in else r_in * r_out / (r_out - r_in)
    lam = np.full(q.shape, np.inf)
    lam[loaded] = _film_ratio(np.full(int(loaded.sum()), 0.5 * v_s), lub.dynamic_viscosity_Pa_s,
                              r_eq, q[loaded] / b, drive.e_star_Pa,
                              lub.pressure_viscosity_1_per_Pa, sigma)
    ph = np.zeros(q.shape)
    ph[loaded] = np.sqrt(q[loaded] / b * drive.e_star_Pa / (math.pi * r_eq))
    k = np.zeros(q.shape)
    k[loaded] = wear_coefficient(k_b, lam[loaded], ph[loaded], hard)
    # per pin and member, the mean over the positions: K Q v_s / H per second
    n_pins = q.shape[1] * q.shape[2]
    volume = float(np.sum(np.mean(k * q, axis=0))) * v_s / hard * S_PER_H / n_pins
    depth = {"pin": volume / (2 * math.pi * r_in * b),
             "hole": volume / (2 * math.pi * max(r_out, r_in) * b)}
    w = q[loaded]
    return ContactWear(element="output pins", volume_m3_per_h={"pin": volume, "hole": volume},
                       depth_m_per_h=depth, clearance_m_per_h=sum(depth.values()),
                       film_ratio=float(np.mean(np.where(np.isfinite(lam[loaded]),
                                                         lam[loaded], 0.0)))
                       if np.any(loaded) else math.inf,
                       regime_share=_shares(lam[loaded], w),
                       k_mean=float(np.sum(k[loaded] * w) / max(np.sum(w), 1e-300)))
