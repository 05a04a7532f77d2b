"""The loss of every component of each drive, from the lossless loads and speeds.

Each loss is computed from the loads and speeds the component sees in the lossless train at
the output torque (first order in the losses, the usual practice of ISO/TR 14179 and of the
sine paper, Lu & Xu 2024, Eqs. 26-45). Components:

* sine: ``mesh`` (contact friction over one meshing period), ``eccentric_bearing`` (Eq. 32
  with the bearing force from the planet's equilibrium, Eqs. 26-31), ``plain_bearings``
  (Eq. 34), ``output_mechanism`` (pins in holes, Eqs. 37-39), ``churning`` (Eq. 42),
  ``drag``.
* cycloid: ``pin_contacts`` (pins sliding on the disc for the integral housing; a
  conventional pin turns in its groove when the groove slides more easily, see
  :func:`pin_contact_mu`), then for a K-H-V drive ``eccentric_bearing`` and
  ``output_mechanism`` (pins in holes, as the sine planet), for a 2K-V (RV-type) drive
  ``crank_bearings`` (the disc's crank-hole bearings) and ``first_stage`` (involute spur
  stage).
* every drive: the load-independent losses of :mod:`.no_load` (``churning`` in an oil
  bath, ``seals``, ``bearing_drag``, ``drag``).

Each ``*_losses`` function returns a :class:`DriveLosses`; ``toothfem.efficiency.evaluate``
turns it into the efficiency record.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from ..errors import CaseError
from ..fem.drives import drive_for
from ..limits import Exceeded
from .bearing_friction import bearing_losses
from .main_bearing import main_preload_N
from .bearings import main_bearing_load
from .envelope import envelope
from .losses import LOSSES
from .contact_friction import contact_mu, sliding_loss
from .mesh_table import LoadsMemo, fe_reference
from .no_load import no_load_losses
from ..si import si_of


@dataclass(frozen=True, kw_only=True)
class DriveLosses:
    """Output power and the losses of every component at M points, arrays (M,)."""
    output_power_W: np.ndarray
    losses_W: dict
    notes: tuple
    mesh_efficiency: dict          # per stage, (M,)
    limits: tuple = ()             # toothfem.limits.Exceeded: limits the points pass


@dataclass(frozen=True, kw_only=True)
class OperatingPoints:
    """M operating points: input speed [rad/s], output torque [N m], oil temperature
    [deg C] or None (the reference), viscosity factor eta(T)/eta_ref, the load source and
    positions of the meshing table, or the ``table`` itself (a built reducer's contacts,
    :func:`toothfem.efficiency.mesh_table.table_from_records`); ``memo``: the loads the
    calling computation has met (:class:`~toothfem.efficiency.mesh_table.LoadsMemo`)."""
    input_speed_rad_s: np.ndarray
    output_torque_Nm: np.ndarray
    viscosity_factor: np.ndarray
    loads: str
    n_positions: int
    table: object = None
    memo: LoadsMemo = field(default_factory=LoadsMemo)


def mesh_table_of(si, drive, points, member_torque, notes):
    """The meshing table of the drive for these points' load source (or theirs).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    points : toothfem.efficiency.drive_losses.OperatingPoints
    member_torque : numpy.ndarray, shape (M,)
        The member's torque at the points [N m].
    notes : list of str
        A note is appended here where the table says something about the points.

    Returns
    -------
    toothfem.efficiency.mesh_table.MeshTable
    """
    if points.table is not None:
        return points.table
    ref = None
    if points.loads == "fem":
        declared = si.declared_output_torque_Nm()
        ref = fe_reference(None if declared is None else
                           drive.member_torque(declared, peak=False), member_torque, notes)
    return points.memo.table(drive, points.loads, points.n_positions, ref)


def _members(si, drive, points, table, member_torque, notes):
    """Each member's loads as [(label, table, torque (M,) [N m], members alike)]: the even
    share for one table of them all (label ""), unless the loads are the FE's and the FE
    split between the members is not even (fem/datasheet/transmission.py, at the case's
    declared output torque, held as fractions at every point). Then member j carries its
    mean share of the output torque, its table scaled at each position by its share there
    over that mean (first order in the ripple of the share over the pitch), labelled "disc
    j of M" for its notes."""
    m = drive.members
    if points.loads != "fem" or points.table is not None or m == 1:
        return [("", table, member_torque, m)]
    ref = si.declared_output_torque_Nm() or float(np.max(points.output_torque_Nm))
    split = points.memo.split(drive, drive.supports(si.supports), ref, table.n_positions)
    if split.even_by_layout:
        notes.append(f"FE split between the {m} discs: even at every position by the layout's "
                     "symmetry (each disc at the first's configuration, the crankshafts "
                     "loading each alike)")
        return [("", table, member_torque, m)]
    ratio = split.ratio_by_position()                                   # (M, P)
    shares = split.share.mean(axis=1)
    notes.append(f"FE split between the {m} discs at {ref:.4g} N m (fractions held at every "
                 "point): mean shares " + " / ".join(f"{x:.4f}" for x in shares)
                 + f", largest {float(split.share.max()):.4f} (docs/stiffness.md)")
    # a disc the split leaves unloaded over the whole period carries (and loses) nothing
    return [(f"disc {j + 1} of {m}", table.scaled(r / r.mean()), member_torque * r.mean(), 1)
            for j, r in enumerate(ratio) if r.mean() > 0]


def w_mechanism(si, table, force, member_torque, a0_m, rel):
    """Eccentric-bearing and output-mechanism losses of a K-H-V member.

    The member's torque leaves through pins in holes (sine paper Eqs. 26-39,
    docs/derivations.md 7): the pins' load sum Q = 4T/(pi R_w) acts along -e on the
    member, the eccentric bearing carries |mesh resultant - sum Q e| (the member's
    equilibrium), the pins slide in their sleeves at 2 a0 w_rel (Eq. 38).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        Its ``output_mechanism`` and ``friction``.
    table : toothfem.efficiency.mesh_table.MeshTable
    force : numpy.ndarray, shape (M, N)
        Contact forces [N] at the points (``table.at``).
    member_torque : numpy.ndarray, shape (M,)
        T [N m].
    a0_m : float
        Eccentricity a0 [m].
    rel : numpy.ndarray, shape (M,)
        w_rel, the crank's speed relative to the member [rad/s].

    Returns
    -------
    f_r1, output : numpy.ndarray, shape (M,)
        The eccentric bearing's mean load [N] (Eq. 27) and the output mechanism's loss
        [W].

    Raises
    ------
    CaseError
        Without an [output_mechanism].
    """
    om = si.output_mechanism
    if om is None:
        raise CaseError("a K-H-V drive (no [first_stage]) needs [output_mechanism] (pins in "
                        "holes) for its output losses")
    r_w = om.pin_hole_circle_radius_m
    sum_q = 4 * member_torque / (math.pi * r_w)                            # Eq. 26
    e_dir = table.centre / np.linalg.norm(table.centre, axis=1)[:, None]   # (P, 2)
    bearing = table.resultant(force) - sum_q[:, None, None] * e_dir[None]
    f_r1 = np.mean(np.linalg.norm(bearing, axis=2), axis=1)                # Eq. 27, exact
    out_mech = si.friction.output_pin_coefficient * sum_q * 2 * a0_m * rel   # Eqs. 38-39
    return f_r1, out_mech


def pin_contact_mu(si, mu_disc):
    """Friction that resists sliding at a pin: the disc contact's (integral housing), or
    for a pin free to turn in its groove the smaller of that and the groove's Coulomb
    coefficient ``friction.pin_groove_coefficient``: the pin turns until the two friction
    torques balance, so the interface that slides more easily takes the sliding (loss
    mu F v_s either way, v_s the sliding speed of a fixed pin, since the groove radius is
    the pin radius).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        Its pin structure and groove coefficient.
    mu_disc : numpy.ndarray
        The disc contact's coefficient per contact [-].

    Returns
    -------
    numpy.ndarray
        The coefficient of the sliding interface, ``mu_disc``'s shape [-].
    """
    if si.cycloid.pin_structure == "integral":
        return mu_disc
    return np.minimum(mu_disc, si.friction.pin_groove_coefficient)


def disc_contact_losses(case, table, torque_disc, crank_speed, eta0, notes=None,
                        limits=None):
    """Pin-contact loss of one cycloid disc and the mean resultant of its pin forces.

    Parameters
    ----------
    case : toothfem.case.Case or toothfem.si.CaseSI
    table : toothfem.efficiency.mesh_table.MeshTable
        Any load source: analytic, FE, or another contact model's records through
        :func:`~toothfem.efficiency.mesh_table.table_from_records`.
    torque_disc : numpy.ndarray
        (M,) torque on the disc [N m].
    crank_speed : numpy.ndarray
        (M,) crank speed relative to the pin ring [rad/s].
    eta0 : float or numpy.ndarray
        Inlet dynamic viscosity [Pa s].
    notes : list of str, optional
        Validity notes are appended here.
    limits : list, optional
        Limits passed are appended here (:func:`contact_mu`).

    Returns
    -------
    loss, f_bearing : numpy.ndarray
        (M,) the loss [W] and the mean pin resultant [N] (what the crank bearings carry).
    """
    si = si_of(case)
    notes = [] if notes is None else notes
    force, ph = table.at(torque_disc)
    mu_disc, _ = contact_mu(si, drive_for(si).e_star_Pa, table, force, ph, crank_speed, eta0,
                            notes, limits)
    mu = pin_contact_mu(si, mu_disc)
    if si.cycloid is not None and si.cycloid.pin_structure == "conventional":
        share = np.mean(mu_disc > si.friction.pin_groove_coefficient)
        notes.append(f"conventional pins turn in their grooves at {100 * share:.0f} % of the "
                     "loaded contacts (groove friction below the disc contact's)")
    loss = sliding_loss(table, force, mu, crank_speed)
    f_bearing = np.mean(np.linalg.norm(table.resultant(force), axis=2), axis=1)
    return loss, f_bearing


#: Samples of the angle between the pin resultant and a crank hole's tangent (its mean over
#: a crank turn: the holes turn with the disc, the resultant with the crank).
CRANK_ANGLE_SAMPLES = 64


def crank_bearing_load(si, f_resultant, t_disc):
    """Sum of the loads on one disc's crank-hole bearings (2K-V), averaged over a crank
    turn [N].

    The k holes at radius R_c take the pin resultant F and the disc torque T between
    them, evenly: hole i carries -F/k + T/(k R_c) t_i (t_i its tangent), so
    sum |F_i| = k <|a e - b t|> with a = F/k, b = T/(k R_c), averaged over the angle
    between e and t (uniform over a crank turn).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        The disc's crank holes.
    f_resultant : numpy.ndarray, shape (M,)
        |F|, the mean pin resultant [N].
    t_disc : numpy.ndarray, shape (M,)
        T [N m].

    Returns
    -------
    numpy.ndarray, shape (M,)
        [N].

    Raises
    ------
    CaseError
        Without the crank holes' count, radius and circle.
    """
    h = si.cycloid.holes
    k = h.crank_hole_count
    r_c = h.crank_hole_circle_radius_m
    if k < 1 or h.crank_hole_radius_m <= 0 or r_c <= 0:
        raise CaseError("cycloid.disc_holes: crank_hole_count, crank_hole_radius_mm and "
                        "crank_hole_circle_radius_mm are required for the crank bearings "
                        "of a 2K-V (RV-type) drive")
    a = f_resultant / k
    b = t_disc / (k * r_c)
    psi = (np.arange(CRANK_ANGLE_SAMPLES) + 0.5) * 2 * math.pi / CRANK_ANGLE_SAMPLES
    return k * np.mean(np.sqrt(a[:, None] ** 2 + b[:, None] ** 2
                               - 2 * a[:, None] * b[:, None] * np.cos(psi)), axis=1)


def crank_support_load(si, t_discs):
    """Sum of the loads on the crankshafts' support bearings in the carrier (2K-V) [N].

    Each of the k crankshafts passes its discs' torque to the carrier at radius R_c: the
    discs' crank bearings on it push with sum_j T_j/(k R_c) along the carrier's tangent
    (their pin resultants, the discs a 1/M turn apart, cancel on the shaft), shared by its
    two support bearings (the discs centred between them): sum_j T_j / R_c over all. The
    spur planet's tangential force on the crank (T_in/(k r_sun): 0.19 kN beside 6.8 kN on
    the RV-40E at its rating) is left out. The system model's loads on the RV-40E at 412
    N m (the discs off-centre on the shaft: 3.81 and 2.83 kN on a crank's two bearings)
    sum to the power flow's disc torque, 3.3 % below the even share the loss model takes
    (``Drive.member_torque``; tests/test_efficiency_defaults.py).

    Parameters
    ----------
    si : toothfem.si.CaseSI
        The crank holes' circle.
    t_discs : numpy.ndarray, shape (M,)
        The discs' torque together [N m].

    Returns
    -------
    numpy.ndarray, shape (M,)
        [N].
    """
    return np.abs(t_discs) / si.cycloid.holes.crank_hole_circle_radius_m


def cycloid_losses(si, drive, points: OperatingPoints, power_flow) -> DriveLosses:
    """Losses of a cycloid stage with the layout's ``power_flow`` (:func:`_khv_flow`,
    :func:`_rv_flow`): the pins' contact loss of every member, the flow's own loads and
    losses, the main bearings' and the load-independent losses.

    Raises
    ------
    CaseError
        For a missing section, or a 2K-V train that self-locks at these points.

    Parameters
    ----------
    si : toothfem.si.CaseSI
    drive : toothfem.fem.drives.Drive
    points : toothfem.efficiency.drive_losses.OperatingPoints
    power_flow : callable
        ``power_flow(si, drive, points, stage_loads) -> PowerFlow``: the layout's.

    Returns
    -------
    DriveLosses
    """
    cyc = si.cycloid
    w = drive.speeds()
    w_in = points.input_speed_rad_s
    t2 = points.output_torque_Nm
    crank = np.abs(w_in * w["crank"])
    disc_rel = np.abs(w_in * (w["crank"] - w["member"]))     # crank relative to the disc
    p_out = t2 * np.abs(w_in * w["output"])
    notes: list[str] = []
    t_disc = drive.member_torque(t2, peak=False)   # the even share
    table = mesh_table_of(si, drive, points, t_disc, notes)
    eta0 = si.lubricant.dynamic_viscosity_Pa_s * points.viscosity_factor
    # every member's loss at its own loads: (label, table, torque (M,), members alike)
    members = _members(si, drive, points, table, t_disc, notes)
    pins: np.ndarray | float = 0.0
    f_bearing: list[np.ndarray] = []
    limits: list[Exceeded] = []
    for label, tab, t_j, count in members:
        said: list[str] = []
        loss, f_b = disc_contact_losses(si, tab, t_j, crank, eta0, said, limits)
        notes.extend(f"{label}: {n}" if label else n for n in said)
        pins = pins + count * loss
        f_bearing.append(f_b)
    # disc-pin mesh in the crank frame: the loss over the discs' virtual power
    eta2 = 1 - pins / (drive.members_torque(t2) * disc_rel)
    flow = power_flow(si, drive, points, StageLoads(members=members, f_bearing=f_bearing,
                                                    pins_W=pins, eta2=eta2, disc_rel=disc_rel,
                                                    p_out=p_out, eta0=eta0))
    loads, losses = flow.loads, flow.losses
    # each row's load term takes its preload beside the external loads' share
    loads["main_bearings"] = (main_bearing_load(si, drive, table, t2)
                              + envelope(si, drive).main_count * main_preload_N(si, drive))
    losses.update(bearing_losses(si, drive, loads, w_in, points.viscosity_factor))
    stages = [(cyc.geometry.eccentricity_m, crank), *flow.churning_stages]
    losses.update(no_load_losses(si, drive, stages=stages, input_rad_s=w_in,
                                 output_rad_s=w_in * w["output"],
                                 viscosity_factor=points.viscosity_factor, bearings=False))
    if "churning" in losses:
        notes.append("churning: Eq. 42 of Lu & Xu (2024), after Xu & Yang (1998), is the "
                     "sine paper's oil-bath law for the agitation, splashing and seals of its "
                     "one-tooth-difference stage, used by its source only there; on this "
                     f"drive's {' and '.join(flow.stage_names)} it is an estimate outside "
                     "that use")
    return DriveLosses(output_power_W=p_out, losses_W=losses, notes=tuple(notes),
                       mesh_efficiency={"cycloid": eta2, **flow.mesh_efficiency},
                       limits=tuple(limits))


@dataclass(frozen=True)
class StageLoads:
    """The cycloid stage's figures a power flow needs (:func:`cycloid_losses`)."""
    members: list            # (label, table, torque (M,), members alike)
    f_bearing: list          # each member's bearing force (M,) [N]
    pins_W: np.ndarray | float   # the pins' contact loss of all members (M,)
    eta2: np.ndarray         # the disc-pin mesh efficiency in the crank frame (M,)
    disc_rel: np.ndarray     # the crank's speed relative to the disc (M,) [rad/s]
    p_out: np.ndarray        # the output power (M,) [W]
    eta0: np.ndarray         # the oil's viscosity at the points (M,) [Pa s]


@dataclass(frozen=True)
class PowerFlow:
    """A layout's power flow: bearing loads [N], losses [W], further mesh efficiencies,
    further churning stages (centre distance [m], speed [rad/s]) and the stages' names."""
    loads: dict
    losses: dict
    mesh_efficiency: dict
    churning_stages: tuple
    stage_names: tuple


def bearing_component(drive) -> str | None:
    """The loss component proportional to the bearing coefficient, if there is one.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive

    Returns
    -------
    str or None
        "eccentric_bearing" for the sine reducer (Eq. 32), None for a cycloid or RV
        reducer (the coefficient acts on every bearing's load term, not alone).
    """
    return drive.layout.loss_model.bearing_coefficient_component


def loss_sources(drive, names) -> dict:
    """The law and source of each named loss component of a drive.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    names : iterable of str
        Loss components (the keys of ``DriveLosses.losses_W``).

    Returns
    -------
    dict
        name -> source.
    """
    own = drive.layout.loss_model.sources
    return {n: own.get(n, LOSSES[n].law if n in LOSSES else "") for n in names}


@dataclass(frozen=True)
class LossModel:
    """A layout's loss model (``Layout.loss_model``, toothfem/layout.py).

    Attributes
    ----------
    losses : callable
        (si, drive, points) -> :class:`DriveLosses`.
    sources : dict
        The layout's own reading of a component's law and source (beside
        :data:`toothfem.efficiency.losses.LOSSES`).
    bearing_coefficient_component : str or None
        The component proportional to ``friction.bearing_coefficient`` alone (the sine
        paper's Eq. 32); None where the coefficient is the load term of every bearing's
        Palmgren moment (:func:`bearing_losses`).
    """
    losses: Callable[..., DriveLosses]
    sources: Mapping[str, str] = field(default_factory=dict)
    bearing_coefficient_component: str | None = None

    def __call__(self, si, drive, points: OperatingPoints) -> DriveLosses:
        """The losses at the points.

        Parameters
        ----------
        si : toothfem.si.CaseSI
        drive : toothfem.fem.drives.Drive
        points : OperatingPoints

        Returns
        -------
        DriveLosses
        """
        return self.losses(si, drive, points)
